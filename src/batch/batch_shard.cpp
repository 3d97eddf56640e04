// Shards of a batch: jump consistent hash over the relative path's SHA-256.
#include "medspheres/batch/batch_shard.h"

#include <stdexcept>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/sha256.h"

namespace medspheres {

namespace {

// A decimal count without sign or blanks; false when it is not one or overflows.
bool parse_count(const std::string& text, std::uint64_t& value) {
  if (text.empty() || text.size() > 18) return false;
  value = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
  }
  return true;
}

// Lamping and Veach, "A Fast, Minimal Memory, Consistent Hash Algorithm" (2014): the
// bucket in [0, buckets) of a key; from n to n+1 buckets a key moves with probability
// 1/(n+1), and only into the new bucket.
std::uint64_t jump_consistent_hash(std::uint64_t key, std::uint64_t buckets) {
  std::int64_t b = -1, j = 0;
  while (j < static_cast<std::int64_t>(buckets)) {
    b = j;
    key = key * 2862933555777941757ULL + 1;
    j = static_cast<std::int64_t>(
        static_cast<double>(b + 1) *
        (static_cast<double>(1LL << 31) / static_cast<double>((key >> 33) + 1)));
  }
  return static_cast<std::uint64_t>(b);
}

}  // namespace

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  Shard s;
  const bool ok = slash != std::string::npos && parse_count(text.substr(0, slash), s.index) &&
                  parse_count(text.substr(slash + 1), s.count) && s.count >= 1 &&
                  s.count <= kMaxShards && s.index < s.count;
  if (!ok)
    throw InputError::option(ErrorKind::kOutOfRange, "shard", text,
                             "expected i/N with 0 <= i < N <= 2^31 (the worker's index and the "
                             "number of workers), got '" +
                                 text + "'");
  return s;
}

std::uint64_t shard_of(const std::string& relative, std::uint64_t count) {
  if (count == 0 || count > kMaxShards)
    throw std::invalid_argument("shard_of: count must be in [1, 2^31]");
  const std::string hex = sha256_hex(relative);
  const std::uint64_t key = std::stoull(hex.substr(0, 16), nullptr, 16);
  return jump_consistent_hash(key, count);
}

bool in_shard(const std::string& relative, const Shard& shard) {
  return shard_of(relative, shard.count) == shard.index;
}

}  // namespace medspheres
