// The covering bake to a budget (cover.h).
//
// Two measures judge a cover: its largest protrusion P (how far any ball reaches beyond the
// solid) and the volume of its union outside the solid (U - V). They pull apart: the
// balls of least P are balanced so that every one protrudes about as far, and balanced
// balls overlap and bulge where a few larger or deeper ones would fit closer. So the bake
// runs two stages, each one objective with one optimiser:
// - the protrusion stage (cover_protrusion.cpp) lowers P: a global start (the threshold
//   cover, a bottleneck set cover over candidate centres) and local moves (minimax rounds,
//   split and exchange);
// - the volume stage (cover_flow.cpp) lowers the union's volume, all balls moving and
//   resizing at once down its gradient while penalties keep the elements held and each
//   protrusion within (1 + protrusion_allowance) P. It is kept when the product of the
//   volume outside the solid and the largest protrusion falls, so that neither is traded
//   away for a small gain in the other.
// The allowance lets the volume stage trade a little of the first stage's protrusion for
// volume: at 0 the stage may only keep P, where the balanced balls leave little room.
//
// The elements are the pieces of the certificate's own subdivision (cover_elements.cpp);
// the balls hold them with a margin above the certificate's rounding allowance, so the
// certificate rarely has anything to repair. After the stages, the elements that bind a
// ball's radius are split and handed to the balls that hold their pieces, so that the
// balls meet at a finer grain than the elements'.
#include "medspheres/cover/cover.h"

#include "cover_elements.h"
#include "cover_flow.h"
#include "cover_polish.h"
#include "cover_protrusion.h"
#include "cover_weights.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/number_text.h"
#include "medspheres/threads.h"

namespace medspheres {

namespace {

using detail::Clustering;
using detail::Elements;

constexpr double kFinePatchFloor = 4000.0;  // patches of the threshold cover, at least
constexpr int kFlowIterations = 240;
constexpr int kBindingLevels = 3;  // splits of the binding elements, at most
// The volume stage runs again (at most twice) only when its first run ends at most this
// far above the cap. The runs again met the cap on 5 of 67 overshoots on the classic meshes
// at K = 16, 32 and 64 (first 2 to 12% above it; the one at 12% not kept) and on 22 of 119
// on the G1's links at K = 2 to 64 (first 0.3 to 9.7% above); beyond that they failed and
// cost twice the first run, up to 0.5 CPU s at K = 64 (bench_budget --k 16,32,64).
constexpr double kRetryOvershoot = 0.10;
// Up to this budget the volume stage runs at kCaps caps, the allowance halved between them
// (P0 (1 + a/4), P0 (1 + a/2), P0 (1 + a)), from each start of the protrusion stage: a single
// cap's flow ends in one local optimum, and which cap reaches the least union varies from
// solid to solid (with a single cap, one bench_budget run each at allowances 0.06 to 0.25
// on the pairs of the spheretree comparison: neither P nor the union was monotone in the
// allowance; docs/covers.md). Above it, one run at
// the cap from the protrusion stage's result: each run costs more there, and at K = 16 the
// six runs took the scanned dragon to 1.04 CPU s (bench_budget --k 16).
constexpr std::size_t kPortfolioBudget = 8;
constexpr int kCaps = 3;
// The volume polish's sweeps at most: on the G1's head link at K = 29 the sweeps took 4.1,
// 1.1 and 0.05% off the union, a fourth 0.04%; on its right ankle pitch link at K = 8, 3.0
// and 0.4%, then nothing.
constexpr int kPolishSweeps = 3;
// The polish runs up to this budget. At K = 64 each ball meets more others, so each measure
// of the union costs more: with a cost per sweep bounded as at K = 32 (cover_polish.cpp) it
// still took 1 to 3 CPU s (bench_budget --k 64 on the asteroids and the ellipsoid), beyond
// the bake's second per link.
constexpr std::size_t kPolishBudget = 32;
// A cover whose union is larger than the single ball's is kept only when it sticks out at
// most this share of the single ball's protrusion (and costs less).
constexpr double kSingleBallShare = 0.5;
// Up to kPortfolioBudget (volume_choice), the candidates of least (U - V) P^kChoiceExponent
// before the polish (at most kPolished of them, and the one of least (U - V) P) are
// polished, and of those whose (U - V) P is still at most the least before the polish, the
// one of least (U - V) P^kChoiceExponent is kept. The polish lowers the union more on some
// layouts than on others (on the G1's right ankle pitch link at K = 8: 6% off the union
// outside of the one of least (U - V) P, 9% off another whose P is 10% higher), so the
// product before it does not tell which polished cover is best. The exponent below 1
// counts the volume more than the protrusion: with the polished candidates of the ankle
// link, the torus, spot and the ellipsoid at K = 4 (docs/covers.md), the choice keeps P
// within spheretree's on all four for exponents 0.66 to 0.84.
constexpr double kChoiceExponent = 0.75;
constexpr std::size_t kPolished = 3;

// V: the solid's volume \p solid, or on an open mesh (the winding solid, \p solid empty) the
// interior points' cells.
double volume_of(const MeshQuery& query, const Elements& e, const CoverOptions& o,
                 const std::optional<double>& solid) {
  if (solid) return *solid;
  const double cell = query.mesh().bounds().sizes().maxCoeff() / o.interior_resolution;
  return static_cast<double>(e.size() - e.surface) * cell * cell * cell;
}

// The volume flow from \p c with the protrusion \p cap, on the patches \p flow_elements (each
// the ball that holds its elements, so a patch held holds them; at most max(4000, 60 K)
// of them against up to 40,000 elements and the interior points: the flow costs that much
// less); then each element of \p e to the ball that must grow least to hold it, the balls
// shrunk to what their elements need, the empty ones dropped. The flow's penalties hold the
// patches only nearly, so holding them all again raises the protrusion (by 2 to 8% on the
// bunny and the G1's ankle at K = 4 and 8); when that leaves it at most kRetryOvershoot
// above the cap, one minimax round (the protrusion stage's local step) from the flow's
// centres brings it back near the least protrusion of that layout, which keeps most of the
// flow's gain in volume (bunny, K = 4: union 11% below the protrusion stage's, P 4% above).
// The volume stage's result and its largest protrusion.
struct VolumeResult {
  Clustering clustering;
  double protrusion = 0.0;
};

VolumeResult volume_stage(const MeshQuery& query, const Elements& e, const Elements& flow_elements,
                          Clustering c, double cap, int threads) {
  detail::drop_empty(c);
  detail::FlowOptions fo;
  fo.cap = cap;
  fo.iterations = kFlowIterations;
  fo.threads = threads;
  c.balls = detail::volume_flow(query, flow_elements, std::move(c.balls), fo);
  c.settled.clear();
  detail::hold_all(e, c, threads);
  detail::shrink(e, c);
  detail::drop_empty(c);
  double p = detail::largest_protrusion(query, c.balls, threads);
  if (p > cap && p <= (1.0 + kRetryOvershoot) * cap) {
    c = detail::minimax_rounds(query, e, std::move(c), 1, threads);
    p = detail::largest_protrusion(query, c.balls, threads);
  }
  return {std::move(c), p};
}

// The volume stage from \p start under the cap, or nothing when it ends beyond the cap. The
// flow's penalties aim at the cap without certainty: while it overshoots, at most twice more
// with the aim lowered by the first overshoot, then by twice it; but only when the first run
// ends within kRetryOvershoot of the cap.
std::optional<Clustering> capped_volume_stage(const MeshQuery& query, const Elements& e,
                                              const Elements& fine, const Clustering& start,
                                              double cap, int threads) {
  VolumeResult v = volume_stage(query, e, fine, start, cap, threads);
  const double over = v.protrusion;
  const int retries = over <= (1.0 + kRetryOvershoot) * cap ? 2 : 0;
  for (int retry = 1; retry <= retries && v.protrusion > cap; ++retry)
    v = volume_stage(query, e, fine, start, cap * std::pow(cap / over, retry), threads);
  if (v.protrusion > cap) return std::nullopt;
  return std::move(v.clustering);
}

// A result and the elements it holds (refined where they bind its radii).
struct Candidate {
  Clustering clustering;
  Elements elements;
};

// \p c over the elements \p e, the binding elements split (at most as deep as the
// certificate goes).
Candidate refined(Elements e, Clustering c, const CoverOptions& o) {
  detail::refine_binding(
      e, c, std::min(kBindingLevels, o.certificate.max_depth - detail::kMaxElementDepth));
  return {std::move(c), std::move(e)};
}

// The volume polish (cover_polish.h) of \p c, capped at its own largest protrusion, kept
// when neither measure rose: the polish checks each ball's protrusion with the depth search
// of the protrusion stage, and this checks it again with the measure's own.
void polish(const MeshQuery& query, Candidate& c, int threads) {
  const double cap = detail::largest_protrusion(query, c.clustering.balls, threads);
  Clustering p =
      detail::volume_polish(query, c.elements, c.clustering, cap, kPolishSweeps, threads);
  if (detail::largest_protrusion(query, p.balls, threads) <= cap &&
      detail::union_volume(p.balls) < detail::union_volume(c.clustering.balls))
    c.clustering = std::move(p);
}

// The volume stage's results (those within their cap): up to kPortfolioBudget from each start
// of \p p at kCaps caps, else from its result at the allowance's own cap.
std::vector<Clustering> volume_results(const MeshQuery& query, const Elements& e,
                                       const Elements& fine, const detail::ProtrusionStage& p,
                                       std::size_t budget, double allowance, int threads) {
  const double p0 = detail::largest_protrusion(query, p.clustering.balls, threads);
  const bool portfolio = budget <= kPortfolioBudget;
  std::vector<const Clustering*> starts{&p.clustering};
  if (portfolio)
    for (const Clustering& other : p.others) starts.push_back(&other);
  const int caps = portfolio ? kCaps : 1;
  std::vector<Clustering> out;
  for (int step = caps - 1; step >= 0; --step) {
    const double cap = (1.0 + std::ldexp(allowance, -step)) * p0;
    for (const Clustering* start : starts)
      if (std::optional<Clustering> v = capped_volume_stage(query, e, fine, *start, cap, threads))
        out.push_back(std::move(*v));
  }
  return out;
}

// A candidate's measures: its index among the candidates, its union's volume, its largest
// protrusion and its volume outside the solid (the union's minus V). Its cost, to choose
// between the stages' results, is the product of the last two; its score the choice's
// (kChoiceExponent).
struct Measured {
  std::size_t index = 0;
  double union_volume = 0.0, protrusion = 0.0, outside = 0.0;
  double cost() const { return outside * std::max(protrusion, 0.0); }
  double score() const { return outside * std::pow(std::max(protrusion, 0.0), kChoiceExponent); }
};

// Least cost first; ties: the lower index.
bool cheaper(const Measured& a, const Measured& b) {
  return a.cost() < b.cost() || (a.cost() == b.cost() && a.index < b.index);
}

Measured measured(const MeshQuery& query, std::size_t index, const Clustering& c, double volume,
                  int threads) {
  const double u = detail::union_volume(c.balls);
  return {index, u, detail::largest_protrusion(query, c.balls, threads), std::max(u - volume, 0.0)};
}

// The choice among polished candidates (kChoiceExponent): of \p eligible (indices into
// \p results), the one of least cost and the kPolished of least score are refined and
// polished; of those whose cost is still at most that least cost and whose union is at
// most that of the one of least cost polished, the one of least score (ties: the one of
// least cost first, then by score before the polish). So the choice trades protrusion for
// volume, never volume for protrusion (on the G1's left wrist roll link at K = 4, without
// the bar on the union, it took P from 57.7 to 53.9% of L and the excess from 1782 to 1849%).
Candidate choose_polished(const MeshQuery& query, const Elements& e,
                          const std::vector<Clustering>& results, std::vector<Measured> eligible,
                          double volume, const CoverOptions& options, int threads) {
  const auto by_score = [](const Measured& a, const Measured& b) {
    return a.score() < b.score() || (a.score() == b.score() && a.index < b.index);
  };
  const Measured cheapest = *std::min_element(eligible.begin(), eligible.end(), cheaper);
  std::sort(eligible.begin(), eligible.end(), by_score);
  std::vector<std::size_t> pool{cheapest.index};
  for (std::size_t k = 0; k < eligible.size() && k < kPolished; ++k)
    if (eligible[k].index != cheapest.index) pool.push_back(eligible[k].index);
  std::optional<Candidate> best;
  Measured best_m, first;
  for (std::size_t r : pool) {
    Candidate c = refined(e, results[r], options);
    polish(query, c, threads);
    const Measured m = measured(query, r, c.clustering, volume, threads);
    if (best && (m.cost() > cheapest.cost() || m.union_volume > first.union_volume ||
                 !(m.score() < best_m.score())))
      continue;
    if (!best) first = m;
    best = std::move(c), best_m = m;
  }
  return std::move(*best);
}

// The stages for budget >= 2 (file comment). The candidates: the protrusion stage's result,
// the volume stage's within their caps, and the single ball (the minimum enclosing ball
// moved inward); of those whose union is no larger than the single ball's or whose largest
// protrusion is at most kSingleBallShare of its, the one of least cost (Measured; ties: that
// order), with its binding elements then refined. Refining only shrinks balls, so the cap
// holds after it.
Candidate search(const MeshQuery& query, const Elements& e, std::size_t budget,
                 const CoverOptions& options, int threads, CoverStats& s) {
  const std::optional<double>& solid = s.mesh_volume;
  const Elements fine =
      detail::make_patches(e, budget, kFinePatchFloor, query.mesh().bounds().min());
  s.patches = fine.surface;
  const detail::BallWeights weights(options.weights);
  detail::ProtrusionStage p =
      detail::protrusion_stage(query, e, fine, budget, options.rounds, solid, threads, weights,
                               options.protrusion_restarts, options.balance_rounds);
  s.rounds_run = p.rounds;
  s.stage_spheres = p.clustering.balls.size();
  // Weighted: the protrusion stage's result as it is (the volume stage and the choice
  // below measure the unweighted protrusion, which would undo the weights).
  if (options.weights.active()) return refined(e, std::move(p.clustering), options);
  std::vector<Clustering> results;
  if (options.volume_descent)
    results = volume_results(query, e, fine, p, budget, options.protrusion_allowance, threads);
  results.insert(results.begin(), std::move(p.clustering));
  results.push_back(detail::one_ball(query, e, threads));
  const double volume = options.interior_resolution > 0 ? volume_of(query, e, options, solid) : 0.0;
  std::vector<Measured> eligible{
      measured(query, results.size() - 1, results.back(), volume, threads)};
  const Measured one = eligible.front();
  for (std::size_t r = 0; r + 1 < results.size(); ++r) {
    const Measured m = measured(query, r, results[r], volume, threads);
    if (m.union_volume <= one.union_volume || m.protrusion <= kSingleBallShare * one.protrusion)
      eligible.push_back(m);
  }
  const bool polished = options.volume_descent && options.volume_polish && budget <= kPolishBudget;
  if (polished && options.volume_choice && budget <= kPortfolioBudget)
    return choose_polished(query, e, results, eligible, volume, options, threads);
  const std::size_t best = std::min_element(eligible.begin(), eligible.end(), cheaper)->index;
  Candidate out = refined(e, std::move(results[best]), options);
  if (polished) polish(query, out, threads);
  return out;
}

void check_cover_options(std::size_t budget, const CoverOptions& o) {
  if (budget == 0) throw std::invalid_argument("budget must be >= 1, got 0");
  if (o.rounds < 1)
    throw std::invalid_argument("rounds must be >= 1, got " + std::to_string(o.rounds));
  if (o.interior_resolution < 0 || o.interior_resolution > 256)
    throw std::invalid_argument("interior_resolution must be in [0, 256], got " +
                                std::to_string(o.interior_resolution));
  if (o.repair_rounds < 1)
    throw std::invalid_argument("repair_rounds must be >= 1, got " +
                                std::to_string(o.repair_rounds));
  if (o.certificate.max_depth < detail::kMaxElementDepth)
    throw std::invalid_argument(
        "certificate.max_depth must be >= " + std::to_string(detail::kMaxElementDepth) + ", got " +
        std::to_string(o.certificate.max_depth));
  if (const std::optional<CoverSearchProblem> search = cover_search_problem(o))
    throw std::invalid_argument(search->message());
  check_threads(o.threads);
  const std::string weights = protrusion_weights_problem(o.weights);
  if (!weights.empty()) throw std::invalid_argument(weights);
}

// s.mesh_volume is already set (solid_volume, once per call).
void measure(const MeshQuery& query, const std::vector<Sphere>& balls, int threads, CoverStats& s) {
  s.union_volume = measure_union(balls).volume;
  s.excess_volume = s.mesh_volume ? (s.union_volume - *s.mesh_volume) / *s.mesh_volume
                                  : std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> p = sphere_protrusions(query, balls, threads);
  s.max_protrusion = p.empty() ? 0.0 : *std::max_element(p.begin(), p.end());
}

// The last step, for both entry points: the live balls of \p c with the slack, certified
// and repaired, then measured; \p start is when the call began.
void finish(const MeshQuery& query, const Clustering& c, const CoverOptions& options,
            std::chrono::steady_clock::time_point start, CoverResult& out) {
  const TriangleMesh& mesh = query.mesh();
  CoverStats& s = out.stats;
  const double coordinates =
      mesh.bounds().min().cwiseAbs().cwiseMax(mesh.bounds().max().cwiseAbs()).maxCoeff();
  std::vector<Sphere>& balls = out.spheres.spheres;
  for (const Sphere& b : c.balls)
    if (b.radius > 0.0)
      balls.push_back(
          {b.center, b.radius + cover_radius_slack(s.largest_side, coordinates + b.radius)});
  CoverCertificateOptions co = options.certificate;
  co.threads = options.threads;
  for (int round = 0; round < options.repair_rounds; ++round) {
    out.certificate = certify_cover(mesh, balls, co);
    s.repair_rounds_run = round;
    if (out.certificate.certified) break;
    s.repaired += grow_to_hold(balls, out.certificate,
                               cover_radius_slack(s.largest_side, coordinates + s.largest_side));
  }
  if (!out.certificate.certified && s.repaired > 0)
    out.certificate = certify_cover(mesh, balls, co);
  s.certified = out.certificate.certified;
  s.spheres = balls.size();
  measure(query, balls, options.threads, s);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

CoverResult bake_cover(const MeshQuery& query, std::size_t budget, const CoverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check_cover_options(budget, options);
  const int threads = thread_count(options.threads);
  CoverResult out;
  out.search = options;
  CoverStats& s = out.stats;
  s.budget = budget;
  s.largest_side = query.mesh().bounds().sizes().maxCoeff();
  s.mesh_volume = solid_volume(query.mesh());
  const Elements e = detail::make_elements(query, budget, options.interior_resolution, threads);
  s.elements = e.surface;
  s.interior_points = e.size() - e.surface;
  const Clustering c = budget == 1 ? detail::one_ball(query, e, threads)
                                   : search(query, e, budget, options, threads, s).clustering;
  finish(query, c, options, start, out);
  return out;
}

CoverResult tighten_cover(const MeshQuery& query, const std::vector<Sphere>& start_balls,
                          const CoverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string problem = cover_start_problem(start_balls);
  if (!problem.empty()) throw std::invalid_argument("start: " + problem);
  check_cover_options(start_balls.size(), options);
  const int threads = thread_count(options.threads);
  CoverResult out;
  CoverStats& s = out.stats;
  s.budget = s.start_spheres = start_balls.size();
  s.largest_side = query.mesh().bounds().sizes().maxCoeff();
  s.mesh_volume = solid_volume(query.mesh());
  const Elements e = detail::make_elements(query, start_balls.size(), 0, threads);
  s.elements = e.surface;
  // Each element to the ball that must grow least to hold it, each ball then just large
  // enough for its elements (grown or shrunk), the shrink; then the volume stage, capped at
  // the largest protrusion so far and kept only when the union falls.
  Clustering c;
  c.balls = start_balls;
  detail::hold_all(e, c, threads);
  detail::shrink(e, c);
  if (options.volume_descent) {
    const double cap = detail::largest_protrusion(query, c.balls, threads);
    const Elements fine =
        detail::make_patches(e, start_balls.size(), kFinePatchFloor, query.mesh().bounds().min());
    VolumeResult v = volume_stage(query, e, fine, c, cap, threads);
    if (detail::union_volume(v.clustering.balls) < detail::union_volume(c.balls) &&
        v.protrusion <= cap)
      c = std::move(v.clustering);
  }
  finish(query, refined(e, std::move(c), options).clustering, options, start, out);
  return out;
}

std::optional<CoverSearchProblem> cover_search_problem(const CoverSearch& o) {
  const auto problem = [](const char* field, const std::string& value, const char* must) {
    return CoverSearchProblem{field, value, std::string(must) + ", got " + value};
  };
  if (!(o.protrusion_allowance >= 0.0) || !std::isfinite(o.protrusion_allowance))
    return problem("protrusion_allowance", number_text(o.protrusion_allowance),
                   "must be finite and >= 0");
  if (o.protrusion_restarts < 0)
    return problem("protrusion_restarts", std::to_string(o.protrusion_restarts), "must be >= 0");
  if (o.balance_rounds < 0)
    return problem("balance_rounds", std::to_string(o.balance_rounds), "must be >= 0");
  return std::nullopt;
}

std::string cover_start_problem(const std::vector<Sphere>& start) {
  if (start.empty()) return "no spheres";
  for (std::size_t j = 0; j < start.size(); ++j)
    if (!start[j].center.allFinite() || !std::isfinite(start[j].radius) || start[j].radius < 0.0)
      return "sphere " + std::to_string(j) +
             " has a non-finite centre or a radius that is not >= 0";
  return "";
}

std::size_t grow_to_hold(std::vector<Sphere>& balls, const CoverCertificate& cert, double slack) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  std::size_t grown = 0;
  for (const CoverPiece& piece : cert.uncertified_pieces) {
    std::size_t chosen = 0;
    double least = std::numeric_limits<double>::infinity(), needed = 0.0;
    for (std::size_t j = 0; j < balls.size(); ++j) {
      double reach = 0.0;
      for (const Eigen::Vector3d& corner : piece.corners)
        reach = std::max(reach, (corner - balls[j].center).norm());
      if (reach - balls[j].radius < least) {
        least = reach - balls[j].radius;
        chosen = j;
        needed = reach;
      }
    }
    const double radius = needed + slack + 64.0 * kEps * needed;
    if (radius > balls[chosen].radius) {
      balls[chosen].radius = radius;
      ++grown;
    }
  }
  return grown;
}

// Far above the certificate's rounding allowance (a few ulps of the coordinates), so that a
// ball holding an element's computed corners certifies it.
double cover_radius_slack(double L, double coordinates) {
  return 1e-9 * L + 64.0 * std::numeric_limits<double>::epsilon() * coordinates;
}

}  // namespace medspheres
