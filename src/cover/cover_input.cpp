#include "medspheres/cover/cover_input.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace medspheres {

namespace {

// Certify-and-grow rounds at most.
constexpr int kInputRepairRounds = 64;

// The cover's measures against the solid, for its current balls.
void remeasure(const FitEvaluator& solid, CoverResult& cover, int threads) {
  const VolumeError v = solid.volume_error(cover.spheres.spheres, threads);
  CoverStats& s = cover.stats;
  s.union_volume = v.union_measures.volume;
  s.max_protrusion = v.max_protrusion;
  s.excess_volume = s.mesh_volume ? (s.union_volume - *s.mesh_volume) / *s.mesh_volume
                                  : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

InputCoverCheck certify_input_cover(const TriangleMesh& input, const FitEvaluator& solid,
                                    CoverResult& cover, const CoverOptions& options) {
  InputCoverCheck out;
  std::vector<Sphere>& balls = cover.spheres.spheres;
  if (balls.empty() || input.triangles.empty()) {
    out.certificate = certify_cover(input, balls, options.certificate);
    return out;
  }
  CoverCertificateOptions co = options.certificate;
  co.threads = options.threads;
  const Eigen::AlignedBox3d box = input.bounds();
  const double coordinates = box.min().cwiseAbs().cwiseMax(box.max().cwiseAbs()).maxCoeff();
  const double slack = cover_radius_slack(box.sizes().maxCoeff(), coordinates);
  // Rounds after the first certify only the triangles still uncertified: balls only grow,
  // so a certified triangle stays certified.
  out.certificate = certify_cover(input, balls, co);
  out.rounds = 1;
  CoverCertificate last = out.certificate;
  TriangleMesh rest;
  rest.vertices = input.vertices;
  while (!last.certified && out.rounds <= kInputRepairRounds) {
    const std::size_t grown = grow_to_hold(balls, last, slack);
    if (grown == 0) break;
    out.repaired += grown;
    std::vector<std::array<int, 3>> open;
    for (std::size_t t = 0; t < last.triangle_certified.size(); ++t)
      if (!last.triangle_certified[t])
        open.push_back(out.rounds == 1 ? input.triangles[t] : rest.triangles[t]);
    rest.triangles = std::move(open);
    last = certify_cover(rest, balls, co);
    ++out.rounds;
  }
  if (out.repaired > 0) out.certificate = certify_cover(input, balls, co);
  if (out.repaired > 0) remeasure(solid, cover, options.threads);
  return out;
}

}  // namespace medspheres
