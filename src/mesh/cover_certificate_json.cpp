// The certificate of surface coverage as JSON (cover_certificate_json.h).
#include "medspheres/mesh/cover_certificate_json.h"

#include <nlohmann/json.hpp>

namespace medspheres {

std::string cover_certificate_json(const CoverCertificate& c) {
  nlohmann::ordered_json j = {{"certified", c.certified},
                              {"triangles", c.triangles},
                              {"uncertified_triangles", c.uncertified_triangles},
                              {"proven_uncovered_triangles", c.proven_uncovered_triangles},
                              {"pieces_tested", c.pieces_tested},
                              {"max_depth", c.max_depth_reached}};
  if (!c.certified) {
    j["worst_uncovered_distance"] = c.worst_distance;
    j["worst_uncovered_point"] = {c.worst_point.x(), c.worst_point.y(), c.worst_point.z()};
    j["worst_uncovered_bound"] = c.worst_bound;
  }
  return j.dump();
}

}  // namespace medspheres
