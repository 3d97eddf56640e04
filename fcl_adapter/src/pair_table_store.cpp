// A folder of joint-space tables, one CBOR file a table (pair_table_store.h).

#include "medspheres/fcl/pair_table_store.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/fcl/pair_joint_table.h"
#include "medspheres/io.h"
#include "medspheres/sha256.h"

namespace medspheres::fcl {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr const char* kFormat = "medspheres pair joint table";
constexpr int kVersion = 1;

// Whether the nodes make a tree that verdict() walks within bounds: every child pair
// after its parent and inside the list, every split along one of the table's joints.
bool walkable(const std::vector<int>& child, const std::vector<int>& dim,
              const std::vector<double>& mid, const std::vector<int>& verdict, std::size_t joints) {
  const std::size_t n = child.size();
  if (n == 0 || n % 2 == 0 || dim.size() != n || mid.size() != n || verdict.size() != n)
    return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (verdict[i] < 0 || verdict[i] > int(BoundsVerdict::undecided)) return false;
    if (child[i] == -1) continue;
    if (child[i] <= int(i) || std::size_t(child[i]) + 1 >= n || dim[i] < 0 ||
        std::size_t(dim[i]) >= joints || !std::isfinite(mid[i]))
      return false;
  }
  return true;
}

}  // namespace

PairTableStore::PairTableStore(std::string folder) : folder_(std::move(folder)) {
  if (folder_.empty()) throw InputError("table store", "the folder's name is empty");
  std::error_code ec;
  fs::create_directories(folder_, ec);
  if (ec || !fs::is_directory(folder_))
    throw InputError(folder_, "cannot be made the table store's folder" +
                                  (ec ? ": " + ec.message() : std::string(": not a folder")));
}

std::string PairTableStore::path(const std::string& key) const {
  return (fs::path(folder_) / (key + ".table")).string();
}

// The file: a header (format, version, key, the table's joints, limits and far link) and
// the nodes as a CBOR payload of their own, with its SHA-256: a damaged payload is never
// read as a table.
bool PairTableStore::load(const std::string& key, PairJointTable& table) const {
  std::error_code ec;
  if (!fs::is_regular_file(path(key), ec)) return false;
  std::string bytes;
  try {
    bytes = read_text_file(path(key));
  } catch (const Error&) {
    return false;
  }
  const json j = json::from_cbor(bytes, true, false);
  if (j.is_discarded() || !j.is_object()) return false;
  try {  // a value of another type than written throws: not this table's file
    if (j.at("format").get<std::string>() != kFormat || j.at("version").get<int>() != kVersion ||
        j.at("key").get<std::string>() != key ||
        j.at("source").get<std::vector<long>>() != table.source_ ||
        j.at("lower").get<std::vector<double>>() != table.lower_ ||
        j.at("upper").get<std::vector<double>>() != table.upper_ ||
        j.at("far").get<std::size_t>() != table.far_)
      return false;
    const std::vector<std::uint8_t>& payload = j.at("nodes").get_binary();
    if (sha256_hex(std::string(payload.begin(), payload.end())) !=
        j.at("nodes_sha256").get<std::string>())
      return false;
    const json nodes = json::from_cbor(payload);
    const auto child = nodes.at("child").get<std::vector<int>>();
    const auto dim = nodes.at("dim").get<std::vector<int>>();
    const auto mid = nodes.at("mid").get<std::vector<double>>();
    const auto verdict = nodes.at("verdict").get<std::vector<int>>();
    if (!walkable(child, dim, mid, verdict, table.source_.size())) return false;
    table.nodes_.resize(child.size());
    for (std::size_t i = 0; i < child.size(); ++i)
      table.nodes_[i] = {child[i], dim[i], mid[i], static_cast<BoundsVerdict>(verdict[i])};
  } catch (const json::exception&) {
    return false;
  }
  table.stored_ = true;
  return true;
}

void PairTableStore::require_writable(const std::string& key, const std::string& what) const {
  const fs::path probe = fs::path(folder_) / ("." + key + ".probe");
  bool written = false;
  {
    std::ofstream out(probe, std::ios::binary);
    written = out && (out << key) && out.flush();
  }
  std::error_code ec;
  fs::remove(probe, ec);
  if (!written)
    throw InputError(folder_, "the table store's folder cannot be written: " + what +
                                  " is not in it, and a table baked now could not be kept "
                                  "(give a writable folder, or one that holds every table)");
}

void PairTableStore::save(const std::string& key, const PairJointTable& table) const {
  const std::size_t n = table.nodes_.size();
  std::vector<int> child(n), dim(n), verdict(n);
  std::vector<double> mid(n);
  for (std::size_t i = 0; i < n; ++i) {
    child[i] = table.nodes_[i].child;
    dim[i] = table.nodes_[i].dim;
    mid[i] = table.nodes_[i].mid;
    verdict[i] = int(table.nodes_[i].verdict);
  }
  const std::vector<std::uint8_t> nodes =
      json::to_cbor({{"child", child}, {"dim", dim}, {"mid", mid}, {"verdict", verdict}});
  const json j = {{"format", kFormat},
                  {"version", kVersion},
                  {"key", key},
                  {"source", table.source_},
                  {"lower", table.lower_},
                  {"upper", table.upper_},
                  {"far", table.far_},
                  {"nodes", json::binary(nodes)},
                  {"nodes_sha256", sha256_hex(std::string(nodes.begin(), nodes.end()))}};
  const std::vector<std::uint8_t> bytes = json::to_cbor(j);
  write_file_atomically(path(key), std::string(bytes.begin(), bytes.end()));
}

}  // namespace medspheres::fcl
