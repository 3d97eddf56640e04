#include "support/shared_meshes.h"

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace medspheres::test {

bool have_shared_meshes() {
#ifdef MEDSPHERES_SHARED_MESHES
  return true;
#else
  return false;
#endif
}

const std::vector<SharedMesh>& shared_meshes() {
  static const std::vector<SharedMesh> rows = [] {
    std::vector<SharedMesh> out;
#ifdef MEDSPHERES_SHARED_MESHES
    const std::string dir = MEDSPHERES_SHARED_MESHES;
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
      m.category = row["category"];
      out.push_back(m);
    }
#endif
    return out;
  }();
  return rows;
}

}  // namespace medspheres::test
