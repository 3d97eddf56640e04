#include "medspheres/fcl/certified_checker.h"

#include <algorithm>
#include <exception>
#include <memory>
#include <stdexcept>

#include "medspheres/error.h"
#include "medspheres/fcl/pair_table_store.h"
#include "medspheres/fcl/scene_from_fcl.h"
#include "medspheres/threads.h"

#include "witness_points.h"

namespace medspheres::fcl {
namespace {

// Every covering set the certified mode decides "free" on must be a certified cover.
const RobotModel& certified(const RobotModel& model, const BoundedGeometryOptions& bounds) {
  if (bounds.allow_uncertified) return model;
  for (const Link& l : model.links)
    if (!l.spheres.outer.empty() && !records_certified_cover(l.spheres.outer_certificate_json))
      throw InputError(l.name,
                       "its covering set carries no certificate (the certified checker "
                       "decides on covers only)");
  return model;
}

// The fallback's geometries (the trees' sets, else the fine ones, else the planner's),
// after the planner's and the fine model's covers are found certified.
RobotBounds make_bounds(const RobotModel& planner, const RobotModel* fine,
                        const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes,
                        const check::CheckerOptions& options, const FallbackOptions& fallback);

// The kernel's checker: the planner's sets, with the witnesses' points in their links'
// inner sets when asked (witness_points.h).
check::RobotChecker make_checker(const RobotModel& planner, const RobotModel* fine,
                                 const RobotBounds& bounds, const FclScene& scene,
                                 const check::CheckerOptions& options,
                                 const FallbackOptions& fallback) {
  if (!fallback.kernel_witnesses || bounds.witnesses().empty())
    return check::RobotChecker(planner, scene.scene, options, fine);
  check::CheckerOptions with = options;
  for (auto& [link, points] : detail::witness_points(planner, bounds)) {
    std::vector<Sphere>& to = with.inner_points[link];
    to.insert(to.end(), points.begin(), points.end());
  }
  return check::RobotChecker(planner, scene.scene, with, fine);
}

// The learnt order at the checker's margin: learnt at another, its witnesses and pair
// ranks would fit other contacts (they change no verdict, only the cost).
SelfPairOrder order_at(SelfPairOrder order, double margin) {
  order.margin = margin;
  return order;
}

RobotBounds make_bounds(const RobotModel& planner, const RobotModel* fine,
                        const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes,
                        const check::CheckerOptions& options, const FallbackOptions& fallback) {
  certified(planner, fallback.bounds);
  if (fine) certified(*fine, fallback.bounds);
  return RobotBounds(fallback.trees ? *fallback.trees
                     : fine         ? *fine
                                    : planner,
                     meshes, options.disabled, fallback.bounds,
                     order_at(fallback.order, options.margin));
}

// bounded_geometry.h's settle(), by a name the member settle() does not hide.
template <class... Args>
CollideResult settle_pair(Args&&... args) {
  return medspheres::fcl::settle(std::forward<Args>(args)...);
}

}  // namespace

CertifiedChecker::CertifiedChecker(
    const RobotModel& planner, const RobotModel* fine,
    const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes,
    const std::vector<const ::fcl::CollisionObjectd*>& scene, const check::CheckerOptions& options,
    const FallbackOptions& fallback)
    : CertifiedChecker(planner, fine, meshes, scene, scene_from_fcl(scene), options, fallback) {}

CertifiedChecker::CertifiedChecker(
    const RobotModel& planner, const RobotModel* fine,
    const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes,
    const std::vector<const ::fcl::CollisionObjectd*>& scene, FclScene converted,
    const check::CheckerOptions& options, const FallbackOptions& fallback)
    : bounds_(std::make_shared<const RobotBounds>(
          make_bounds(planner, fine, meshes, options, fallback))),
      checker_(make_checker(planner, fine, *bounds_, converted, options, fallback)),
      scene_(scene),
      scene_source_(std::move(converted.source)) {
  if (bounds_->kinematics().joint_names() != checker_.joint_names())
    throw InputError("certified checker",
                     "the sphere trees' model is not the planner's robot (its joints differ)");
  for (const std::string& link : checker_.links()) {
    std::size_t g = 0;
    while (g < bounds_->geometries().size() && bounds_->geometries()[g].link() != link) ++g;
    if (g == bounds_->geometries().size())
      throw InputError(link, "the fallback's model has no sets for this link");
    geometry_of_.push_back(g);
  }
  // The witnesses the kernel has not tested already (those of links it took none for).
  const std::map<std::string, std::vector<Sphere>>& in_kernel = checker_.options().inner_points;
  for (const SelfWitness& w : bounds_->witnesses())
    if (!fallback.kernel_witnesses || !in_kernel.count(bounds_->geometries()[w.a].link()) ||
        !in_kernel.count(bounds_->geometries()[w.b].link()))
      witnesses_.push_back(w);
  const std::size_t G = bounds_->geometries().size();
  rank_.assign(G * G, bounds_->self_pairs().size());
  for (std::size_t k = 0; k < bounds_->self_pairs().size(); ++k) {
    const auto [a, b] = bounds_->self_pairs()[k];
    rank_[std::min(a, b) * G + std::max(a, b)] = k;
  }
  if (fallback.table_cells > 0)
    tables_ = std::make_shared<const Tables>(bake_tables(fallback.trees ? *fallback.trees
                                                         : fine         ? *fine
                                                                        : planner,
                                                         fallback.table_cells, fallback.table_pairs,
                                                         fallback.table_store));
  // tables_first: the tables that can prove a collision, in the self pairs' order.
  for (const auto& [a, b] : bounds_->self_pairs())
    if (const PairJointTable* t = table(a, b);
        fallback.tables_first && t != nullptr && t->colliding_cells() > 0)
      tabled_.push_back(t);
  if (fallback.separating_planes) make_supports();
  attach_scene(nullptr);
}

CertifiedChecker::CertifiedChecker(const CertifiedChecker& donor,
                                   const std::vector<const ::fcl::CollisionObjectd*>& scene,
                                   FclScene converted)
    : bounds_(donor.bounds_),
      checker_(donor.checker_.with_scene(converted.scene)),
      scene_(scene),
      scene_source_(std::move(converted.source)),
      geometry_of_(donor.geometry_of_),
      witnesses_(donor.witnesses_),
      rank_(donor.rank_),
      tables_(donor.tables_),
      tabled_(donor.tabled_),
      supports_(donor.supports_) {
  attach_scene(&donor);
}

CertifiedChecker CertifiedChecker::with_scene(
    const std::vector<const ::fcl::CollisionObjectd*>& scene) const {
  return CertifiedChecker(*this, scene, scene_from_fcl(scene));
}

// The scene's own parts of the fallback: an octree's cells, with the links as OctreeCells
// takes them (the donor's when it has them), and the objects' supports when the links have
// theirs (FallbackOptions::separating_planes).
void CertifiedChecker::attach_scene(const CertifiedChecker* donor) {
  bool octree = false;
  for (const ::fcl::CollisionObjectd* o : scene_) {
    cells_.push_back(octree_cells_of(*o->collisionGeometry(), o->getTransform()));
    octree = octree || cells_.back() != nullptr;
  }
  if (donor != nullptr) cell_links_ = donor->cell_links_;
  if (octree && cell_links_ == nullptr) {
    CellLinks links(bounds_->geometries().size());
    for (std::size_t g = 0; g < links.size(); ++g)
      if (bounds_->geometries()[g].mesh() != nullptr)
        links[g] = std::make_unique<const OctreeCells::Link>(bounds_->geometries()[g]);
    cell_links_ = std::make_shared<const CellLinks>(std::move(links));
  }
  if (supports_ != nullptr)
    for (const ::fcl::CollisionObjectd* o : scene_)
      scene_supports_.push_back(support_of(*o->collisionGeometry()));
}

// The links' supports for separating planes: a link's mesh vertices, or its balls when its
// sets are the solid itself (exact_balls).
void CertifiedChecker::make_supports() {
  Supports links;
  for (const BoundedGeometry& g : bounds_->geometries()) {
    std::unique_ptr<const VertexSupport> s;
    if (g.mesh() != nullptr) {
      s = std::make_unique<const VertexSupport>(*g.mesh());
    } else if (g.exact_balls()) {
      std::vector<Sphere> balls;
      for (std::size_t i = 0; i < g.outer().num_spheres(); ++i)
        balls.push_back(g.outer().sphere(i));
      s = std::make_unique<const VertexSupport>(balls);
    }
    links.push_back(std::move(s));
  }
  supports_ = std::make_shared<const Supports>(std::move(links));
}

// Whether a plane between the pair's two sides clears the margin (separating_plane.h),
// GJK starting along the inner pair that gave the trees' upper bound, else along the
// links' bounding balls.
bool CertifiedChecker::plane_free(const check::UndecidedPair& p,
                                  const std::vector<::fcl::Transform3d>& X,
                                  const CollideResult& decided) const {
  if (supports_ == nullptr) return false;
  const std::vector<BoundedGeometry>& g = bounds_->geometries();
  const std::size_t a = geometry_of_[p.link];
  const VertexSupport* s_a = (*supports_)[a].get();
  const VertexSupport* s_b = p.self ? (*supports_)[geometry_of_[p.other]].get()
                                    : scene_supports_[scene_source_[p.other]].get();
  if (s_a == nullptr || s_b == nullptr) return false;
  const ::fcl::Transform3d& X_WB =
      p.self ? X[geometry_of_[p.other]] : scene_[scene_source_[p.other]]->getTransform();
  const Eigen::Vector3d from = X[a] * g[a].outer().bounding_ball(0).center;
  Eigen::Vector3d guess = X_WB.translation() - from;
  if (p.self) {
    const BoundedGeometry& o = g[geometry_of_[p.other]];
    const DistanceBounds& d = decided.bounds;
    guess = d.upper_a >= 0 && d.upper_b >= 0
                ? Eigen::Vector3d(X_WB * o.inner().sphere(std::size_t(d.upper_b)).center -
                                  X[a] * g[a].inner().sphere(std::size_t(d.upper_a)).center)
                : Eigen::Vector3d(X_WB * o.outer().bounding_ball(0).center - from);
  }
  return separated(*s_a, X[a], *s_b, X_WB, checker_.options().margin, guess).free;
}

// The pairs in the order decide() takes them: as robot_collide, the self pairs seen
// colliding most often first (their rank), then the scene, then the other self pairs
// (the bounds' order kept among equals).
std::vector<check::UndecidedPair> CertifiedChecker::ordered(
    const std::vector<check::UndecidedPair>& pairs) const {
  const std::size_t G = bounds_->geometries().size(), seen = bounds_->seen_colliding();
  auto key = [&](const check::UndecidedPair& p) {
    if (!p.self) return seen;
    const std::size_t a = geometry_of_[p.link], b = geometry_of_[p.other];
    const std::size_t r = rank_[std::min(a, b) * G + std::max(a, b)];
    return r < seen ? r : seen + 1;
  };
  std::vector<check::UndecidedPair> out = pairs;
  std::stable_sort(out.begin(), out.end(),
                   [&](const check::UndecidedPair& x, const check::UndecidedPair& y) {
                     return key(x) < key(y);
                   });
  return out;
}

// The self pairs' tables (the first `first` pairs of the learnt order, or all for 0), two
// pairs at a time.
CertifiedChecker::Tables CertifiedChecker::bake_tables(const RobotModel& model, std::size_t cells,
                                                       std::size_t first,
                                                       const std::string& store_folder) const {
  const std::size_t G = bounds_->geometries().size();
  const auto& pairs = bounds_->self_pairs();
  const std::size_t count = first > 0 ? std::min(first, pairs.size()) : pairs.size();
  Tables tables(G * G);
  const std::vector<BoundedGeometry>& g = bounds_->geometries();
  const std::unique_ptr<const PairTableStore> store =
      store_folder.empty() ? nullptr : std::make_unique<const PairTableStore>(store_folder);
  std::vector<std::exception_ptr> failed(count);  // no exception may leave the parallel loop
#pragma omp parallel for schedule(dynamic, 1)
  for (long k = 0; k < static_cast<long>(count); ++k) {
    const auto [a, b] = pairs[std::size_t(k)];
    try {
      tables[std::min(a, b) * G + std::max(a, b)] = PairJointTable::build(
          model, bounds_->kinematics(), bounds_->link_of()[a], g[a], bounds_->link_of()[b], g[b],
          checker_.options().margin, cells, store.get());
    } catch (...) {
      failed[std::size_t(k)] = std::current_exception();
    }
  }
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
  return tables;
}

// Whether a joint-space table proves the configuration colliding (a look-up per table, the
// pairs most often colliding first): such a configuration needs no bounds.
bool CertifiedChecker::table_colliding(const double* q) const {
  for (const PairJointTable* t : tabled_)
    if (t->verdict(q) == BoundsVerdict::colliding) return true;
  return false;
}

const PairJointTable* CertifiedChecker::table(std::size_t a, std::size_t b) const {
  const std::size_t G = bounds_->geometries().size();
  if (tables_ == nullptr || a >= G || b >= G) return nullptr;
  return (*tables_)[std::min(a, b) * G + std::max(a, b)].get();
}

CertifiedChecker::Poses CertifiedChecker::poses(const double* q) const {
  const Eigen::Map<const Eigen::VectorXd> qv(q,
                                             static_cast<Eigen::Index>(checker_.num_positions()));
  return bounds_->poses(qv, checker_.options().X_WB);
}

// Whether some witness (two points of a self pair's solids, each in its link's frame) is
// certainly within the margin at the poses X. The witnesses' pairs are the fallback's self
// pairs (RobotBounds takes options.disabled as the checker does).
bool CertifiedChecker::witnessed(const Poses& X) const {
  if (!checker_.options().self) return false;
  for (const SelfWitness& w : witnesses_)
    if (witness_holds(w, X, checker_.options().margin)) return true;
  return false;
}

std::vector<std::size_t> CertifiedChecker::unwitnessed(const double* q, std::size_t n,
                                                       check::Verdict* out, std::vector<Poses>& X,
                                                       int threads, FallbackStats& stats) const {
  const std::size_t dof = checker_.num_positions();
  std::vector<std::size_t> open;
  for (std::size_t i = 0; i < n; ++i)
    if (out[i] == check::Verdict::undecided) open.push_back(i);
  stats.configurations += open.size();
  std::vector<Poses> posed(open.size());
  std::vector<char> held(open.size(), 0);
#pragma omp parallel for schedule(dynamic, 8) num_threads(thread_count(threads))
  for (long k = 0; k < static_cast<long>(open.size()); ++k) {
    posed[std::size_t(k)] = poses(q + open[std::size_t(k)] * dof);
    held[std::size_t(k)] = witnessed(posed[std::size_t(k)]);
  }
  std::vector<std::size_t> rest;
  X.clear();
  for (std::size_t k = 0; k < open.size(); ++k) {
    if (held[k]) {
      out[open[k]] = check::Verdict::colliding;
      ++stats.witnessed;
      continue;
    }
    rest.push_back(open[k]);
    X.push_back(std::move(posed[k]));
  }
  return rest;
}

// One configuration: the tables' colliding cells, then the bounds with its undecided
// pairs; when undecided, the witnesses, then settle_pairs() on the pairs.
check::Verdict CertifiedChecker::settle(const double* q, FallbackStats& stats) const {
  checker_.validate(q, 1);  // before the tables, which read only their joints
  if (table_colliding(q)) {
    ++stats.table_first;
    return check::Verdict::colliding;
  }
  std::vector<check::UndecidedPair> pairs;
  check::Verdict v = checker_.check(q, check::Mode::bounds, &pairs);
  std::vector<Poses> X;
  if (unwitnessed(q, 1, &v, X, 1, stats).empty()) return v;
  return settle_pairs(q, X[0], pairs, stats);
}

// A configuration the bounds left undecided, with the pairs they left open, posed (X): as
// robot_collide does, decide() on every pair (the links' sphere trees, surface points
// included), stopping at the first certainly colliding one; only when none is do the meshes
// settle() the pairs still open.
check::Verdict CertifiedChecker::settle_pairs(const double* q, const Poses& X,
                                              const std::vector<check::UndecidedPair>& pairs,
                                              FallbackStats& stats) const {
  const double margin = checker_.options().margin;
  const std::vector<BoundedGeometry>& g = bounds_->geometries();
  auto object = [&](const check::UndecidedPair& p) { return scene_[scene_source_[p.other]]; };
  std::vector<std::pair<const check::UndecidedPair*, CollideResult>> open;
  const std::vector<check::UndecidedPair> in_order = ordered(pairs);
  for (const check::UndecidedPair& p : in_order) {
    const std::size_t a = geometry_of_[p.link];
    if (const PairJointTable* t = p.self ? table(a, geometry_of_[p.other]) : nullptr) {
      const BoundsVerdict v = t->verdict(q);
      stats.tabled += v != BoundsVerdict::undecided;
      if (v == BoundsVerdict::colliding) return check::Verdict::colliding;
      if (v == BoundsVerdict::free) continue;
    }
    ++stats.pairs;
    const CollideResult r =
        p.self ? decide(g[a], X[a], g[geometry_of_[p.other]], X[geometry_of_[p.other]], margin)
               : decide(g[a], X[a], *object(p)->collisionGeometry(), object(p)->getTransform(),
                        margin);
    if (r.verdict == BoundsVerdict::colliding) return check::Verdict::colliding;
    if (r.verdict == BoundsVerdict::undecided) open.emplace_back(&p, r);
  }
  bool undecided = false;
  for (const auto& [p, decided] : open) {
    if (plane_free(*p, X, decided)) {
      ++stats.planes;
      continue;
    }
    ++stats.meshes;
    const std::size_t a = geometry_of_[p->link];
    const OctreeCells* cells = p->self ? nullptr : cells_[scene_source_[p->other]].get();
    if (cells != nullptr && (*cell_links_)[a] != nullptr) {
      if (cells->distance(*(*cell_links_)[a], X[a], margin) <= margin)
        return check::Verdict::colliding;
      continue;
    }
    const CollideResult r = p->self
                                ? settle_pair(decided, g[a], X[a], g[geometry_of_[p->other]],
                                              X[geometry_of_[p->other]], margin)
                                : settle_pair(decided, g[a], X[a], *object(*p)->collisionGeometry(),
                                              object(*p)->getTransform(), margin);
    if (r.verdict == BoundsVerdict::colliding) return check::Verdict::colliding;
    undecided = undecided || r.verdict == BoundsVerdict::undecided;
  }
  return undecided ? check::Verdict::undecided : check::Verdict::free;
}

check::Verdict CertifiedChecker::check(const double* q, FallbackStats* stats) const {
  FallbackStats s;
  const check::Verdict v = settle(q, s);
  if (stats) *stats += s;
  return v;
}

void CertifiedChecker::check(const double* q, std::size_t n, check::Verdict* out, int threads,
                             FallbackStats* stats) const {
  check_threads(threads);
  if (!tabled_.empty()) {
    // The rows a table proves colliding need no bounds; the others go on as a batch. Every
    // row is checked first, so that a bad one is named by its index in this batch.
    checker_.validate(q, n);
    const std::size_t dof = checker_.num_positions();
    std::vector<char> hit(n, 0);
#pragma omp parallel for schedule(static, 64) num_threads(thread_count(threads))
    for (long i = 0; i < static_cast<long>(n); ++i)
      hit[std::size_t(i)] = table_colliding(q + std::size_t(i) * dof);
    std::vector<std::size_t> rest;
    std::vector<double> qr;
    for (std::size_t i = 0; i < n; ++i) {
      if (hit[i]) {
        out[i] = check::Verdict::colliding;
        continue;
      }
      rest.push_back(i);
      qr.insert(qr.end(), q + i * dof, q + (i + 1) * dof);
    }
    if (stats) stats->table_first += n - rest.size();
    std::vector<check::Verdict> vr(rest.size());
    check_untabled(qr.data(), rest.size(), vr.data(), threads, stats);
    for (std::size_t k = 0; k < rest.size(); ++k) out[rest[k]] = vr[k];
    return;
  }
  check_untabled(q, n, out, threads, stats);
}

void CertifiedChecker::check_untabled(const double* q, std::size_t n, check::Verdict* out,
                                      int threads, FallbackStats* stats) const {
  // The bounds of the batch with each undecided configuration's pairs, in one pass; then
  // the witnesses, and the pairs of the configurations they leave open.
  std::vector<std::vector<check::UndecidedPair>> pairs(n);
  checker_.check_bounds(q, n, out, pairs.data(), threads);
  FallbackStats s;
  std::vector<Poses> X;
  const std::vector<std::size_t> open = unwitnessed(q, n, out, X, threads, s);
  const std::size_t dof = checker_.num_positions();
  std::vector<FallbackStats> each(open.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count(threads))
  for (long k = 0; k < static_cast<long>(open.size()); ++k) {
    const std::size_t j = std::size_t(k), i = open[j];
    out[i] = settle_pairs(q + i * dof, X[j], pairs[i], each[j]);
  }
  if (!stats) return;
  *stats += s;
  for (const FallbackStats& e : each) *stats += e;
}

check::Verdict CertifiedChecker::check_edge(const double* q0, const double* q1, double resolution,
                                            std::size_t* checked, FallbackStats* stats) const {
  std::vector<double> open_t;
  const check::Verdict v =
      checker_.check_edge(q0, q1, resolution, check::Mode::bounds, &open_t, checked);
  if (v != check::Verdict::undecided) return v;
  // The undecided samples: the witnesses, then their pairs in one check_bounds batch, then
  // each settled in order.
  const std::size_t dof = checker_.num_positions(), m = open_t.size();
  std::vector<double> q(m * dof);
  for (std::size_t k = 0; k < m; ++k)
    for (std::size_t j = 0; j < dof; ++j) q[k * dof + j] = q0[j] + open_t[k] * (q1[j] - q0[j]);
  FallbackStats s;
  std::vector<check::Verdict> again(m, check::Verdict::undecided);
  std::vector<Poses> X;
  check::Verdict out = unwitnessed(q.data(), m, again.data(), X, 1, s).size() < m
                           ? check::Verdict::colliding
                           : check::Verdict::free;
  std::vector<std::vector<check::UndecidedPair>> pairs(m);
  if (out != check::Verdict::colliding)
    checker_.check_bounds(q.data(), m, again.data(), pairs.data(), 1);
  bool undecided = false;
  for (std::size_t k = 0; k < m && out != check::Verdict::colliding; ++k) {
    const check::Verdict w = again[k] == check::Verdict::undecided
                                 ? settle_pairs(q.data() + k * dof, X[k], pairs[k], s)
                                 : again[k];
    if (w == check::Verdict::colliding) out = w;
    undecided = undecided || w == check::Verdict::undecided;
  }
  if (out != check::Verdict::colliding && undecided) out = check::Verdict::undecided;
  if (stats) *stats += s;
  return out;
}

std::size_t CertifiedChecker::check_edges(const double* q0, const double* q1, std::size_t n,
                                          double resolution, check::Verdict* out, int threads,
                                          FallbackStats* stats) const {
  const std::size_t dof = checker_.num_positions();
  check_threads(threads);
  checker_.validate_edges(q0, q1, n, resolution);  // no exception may leave the parallel loop
  std::vector<FallbackStats> each(n);
  std::vector<std::size_t> checked(n, 0);
#pragma omp parallel for schedule(dynamic, 4) num_threads(thread_count(threads))
  for (long i = 0; i < static_cast<long>(n); ++i) {
    const std::size_t e = std::size_t(i);
    out[e] = check_edge(q0 + e * dof, q1 + e * dof, resolution, &checked[e], &each[e]);
  }
  if (stats)
    for (const FallbackStats& s : each) *stats += s;
  std::size_t total = 0;
  for (std::size_t c : checked) total += c;
  return total;
}

}  // namespace medspheres::fcl
