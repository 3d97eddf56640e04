#include "support/shared_meshes.h"

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "support/sanitizer_build.h"

namespace medspheres::test {

std::string shared_meshes_dir() {
#ifdef MEDSPHERES_SHARED_MESHES
  return MEDSPHERES_SHARED_MESHES;
#else
  return {};
#endif
}

bool have_shared_meshes() {
  return !shared_meshes_dir().empty();
}

std::vector<SharedMesh> read_manifest(const std::string& dir) {
  std::ifstream in(dir + "/MANIFEST.tsv");
  if (!in) throw std::runtime_error("cannot read " + dir + "/MANIFEST.tsv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::istringstream h(line);
    std::string cell;
    while (std::getline(h, cell, '\t')) header.push_back(cell);
  }
  std::vector<SharedMesh> out;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::map<std::string, std::string> row;
    std::istringstream s(line);
    std::string cell;
    for (std::size_t i = 0; std::getline(s, cell, '\t'); ++i)
      if (i < header.size()) row[header[i]] = cell;
    SharedMesh m;
    m.file = row["file"];
    m.path = dir + "/" + m.file;
    m.triangles = std::stoul(row["triangles"]);
    m.closed = row["closed"] == "yes";
    m.boundary_edges = std::stoul(row["boundary_edges"]);
    m.nonmanifold_edges = std::stoul(row["nonmanifold_edges"]);
    m.components = std::stoul(row["components"]);
    m.degenerate_triangles = std::stoul(row["degenerate_tris"]);
    m.selfint_pairs = std::stoul(row["selfint_pairs"]);
    m.category = row["category"];
    out.push_back(m);
  }
  return out;
}

namespace {

// The sanitizer builds leave out the meshes above this many triangles: the scanned dragon
// (10^5) and Stanford bunny (69,451), a third of the manifest's triangles and of the sweeps'
// time, whose code paths the other closed and open meshes take as well.
constexpr std::size_t kSanitizerMaxTriangles = 50000;

std::vector<SharedMesh> sweep_rows() {
  std::vector<SharedMesh> rows;
  if (!have_shared_meshes()) return rows;
  for (SharedMesh& row : read_manifest(shared_meshes_dir()))
    if (!kSanitizerBuild || row.triangles <= kSanitizerMaxTriangles) rows.push_back(std::move(row));
  return rows;
}

}  // namespace

const std::vector<SharedMesh>& shared_meshes() {
  static const std::vector<SharedMesh> rows = sweep_rows();
  return rows;
}

}  // namespace medspheres::test
