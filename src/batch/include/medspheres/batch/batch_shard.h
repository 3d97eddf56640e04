#pragma once
/// \file
/// A worker's share of a batch (--shard i/N): the inputs whose relative path hashes to
/// shard i of N. Shards 0 .. N-1 are disjoint and together hold every input; an input's
/// shard depends only on its relative path and N, so adding or removing files moves no
/// other file, and going from N to N+1 shards moves about 1/(N+1) of them (jump
/// consistent hash, Lamping and Veach 2014, over the first 8 bytes of the path's SHA-256).

#include <cstdint>
#include <string>

namespace medspheres {

/// The most shards (the hash's buckets are 32-bit).
inline constexpr std::uint64_t kMaxShards = std::uint64_t{1} << 31;

struct Shard {
  std::uint64_t index = 0;  ///< i, 0 <= i < count
  std::uint64_t count = 1;  ///< N >= 1
};

/// "i/N" with 0 <= i < N <= kMaxShards (decimal, no sign or blanks).
/// \throws InputError (kOutOfRange, field "shard", value \p text) otherwise.
Shard parse_shard(const std::string& text);

/// The shard in [0, count) of the relative path \p relative.
/// \throws std::invalid_argument for count 0 or above kMaxShards.
std::uint64_t shard_of(const std::string& relative, std::uint64_t count);

/// shard_of(relative, shard.count) == shard.index.
bool in_shard(const std::string& relative, const Shard& shard);

}  // namespace medspheres
