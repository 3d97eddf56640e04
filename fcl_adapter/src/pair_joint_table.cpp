// A self pair's certified verdicts over the box of its one or two joints (pair_joint_table.h).

#include "medspheres/fcl/pair_joint_table.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "medspheres/fcl/pair_table_store.h"
#include "medspheres/sha256.h"

namespace medspheres::fcl {
namespace {

using Step = KinematicTree::Step;

// The actuated steps on the path between links a and b: {steps on a's side (bottom-up),
// steps on b's side (bottom-up)}, each the steps with a source only.
std::pair<std::vector<std::size_t>, std::vector<std::size_t>> moving_steps(
    const KinematicTree& tree, std::size_t a, std::size_t b) {
  const std::vector<Step>& steps = tree.steps();
  std::vector<long> step_of(tree.link_names().size(), -1);
  for (std::size_t s = 0; s < steps.size(); ++s) step_of[steps[s].child] = long(s);
  auto up = [&](std::size_t link) {  // the links from `link` to the root, itself first
    std::vector<std::size_t> out{link};
    while (step_of[out.back()] >= 0) out.push_back(steps[std::size_t(step_of[out.back()])].parent);
    return out;
  };
  const std::vector<std::size_t> from_a = up(a), from_b = up(b);
  std::size_t ancestor = tree.root();
  for (std::size_t l : from_a)
    if (std::find(from_b.begin(), from_b.end(), l) != from_b.end()) {
      ancestor = l;
      break;
    }
  auto side = [&](const std::vector<std::size_t>& links) {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; links[k] != ancestor; ++k) {
      const std::size_t s = std::size_t(step_of[links[k]]);
      if (steps[s].source >= 0) out.push_back(s);
    }
    return out;
  };
  return {side(from_a), side(from_b)};
}

// Whether step s is an actuated revolute joint with limits, driven by its own position.
bool table_joint(const RobotModel& model, const KinematicTree& tree, const Step& s) {
  if (s.type != JointType::kRevolute || s.multiplier != 1.0 || s.offset != 0.0) return false;
  const Joint* j = model.find_joint(tree.joint_names()[std::size_t(s.source)]);
  return j != nullptr && j->child == tree.link_names()[s.child] && j->limits &&
         std::isfinite(j->limits->lower) && std::isfinite(j->limits->upper) &&
         j->limits->lower < j->limits->upper;
}

// Max |v - o| over the mesh's vertices v posed at X.
double farthest(const MeshModel& mesh, const Eigen::Isometry3d& X, const Eigen::Vector3d& o) {
  double r = 0.0;
  for (int i = 0; i < mesh.num_vertices; ++i) r = std::max(r, (X * mesh.vertices[i] - o).norm());
  return r;
}

}  // namespace

std::unique_ptr<const PairJointTable> PairJointTable::build(
    const RobotModel& model, const KinematicTree& tree, std::size_t a, const BoundedGeometry& ga,
    std::size_t b, const BoundedGeometry& gb, double margin, std::size_t max_cells,
    const PairTableStore* store) {
  if (!std::isfinite(margin) || margin < 0.0 || max_cells == 0)
    throw std::invalid_argument("PairJointTable: margin must be finite and >= 0, max_cells >= 1");
  if (ga.mesh() == nullptr || gb.mesh() == nullptr) return nullptr;
  auto [side_a, side_b] = moving_steps(tree, a, b);
  const BoundedGeometry* far = &gb;
  std::size_t far_link = b;
  if (!side_a.empty()) {  // the joints below a: a is the far link
    if (!side_b.empty()) return nullptr;
    std::swap(side_a, side_b);
    far = &ga;
    far_link = a;
  }
  if (side_b.empty() || side_b.size() > 2) return nullptr;
  std::reverse(side_b.begin(), side_b.end());  // from the ancestor down
  const std::vector<Step>& steps = tree.steps();
  auto table = std::unique_ptr<PairJointTable>(new PairJointTable());
  for (std::size_t s : side_b) {
    if (!table_joint(model, tree, steps[s])) return nullptr;
    const JointLimits& l =
        *model.find_joint(tree.joint_names()[std::size_t(steps[s].source)])->limits;
    if (std::find(table->source_.begin(), table->source_.end(), steps[s].source) !=
        table->source_.end())
      return nullptr;
    table->source_.push_back(steps[s].source);
    table->lower_.push_back(l.lower);
    table->upper_.push_back(l.upper);
  }
  // R_j at any pose (the distances are fixed in the links), here q = 0.
  const std::vector<Eigen::Isometry3d> X0 =
      tree.link_poses(Eigen::VectorXd::Zero(Eigen::Index(tree.num_positions())));
  const std::size_t k = side_b.size();
  std::vector<double> R(k);
  R[k - 1] = farthest(*far->mesh(), X0[far_link], X0[steps[side_b[k - 1]].child].translation());
  for (std::size_t j = k - 1; j-- > 0;)
    R[j] = R[j + 1] +
           (X0[steps[side_b[j + 1]].child].translation() - X0[steps[side_b[j]].child].translation())
               .norm();
  table->far_ = far_link;
  const Pair pair{a, &ga, b, &gb};
  const std::string key = store ? sha256_hex(table->store_key(tree, pair, margin, max_cells)) : "";
  if (store && store->load(key, *table)) return table;
  if (store)
    store->require_writable(key, "the table of links '" + tree.link_names()[a] + "' and '" +
                                     tree.link_names()[b] + "'");
  table->make_shells(*far->mesh(),
                     X0[far_link].inverse() * X0[steps[side_b[k - 1]].child].translation(),
                     R[k - 1]);
  table->bake(tree, pair, margin, R, max_cells);
  table->shells_.clear();  // the bake's alone
  if (store) store->save(key, *table);
  return table;
}

// Everything the cells are computed from, as bytes (pair_table_store.h names it): the
// store's key is their digest.
std::string PairJointTable::store_key(const KinematicTree& tree, const Pair& p, double margin,
                                      std::size_t max_cells) const {
  std::string out = "medspheres pair joint table 1\n";
  auto put = [&out](const auto& v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); };
  auto put_vector = [&put](const Eigen::Vector3d& v) {
    for (int i = 0; i < 3; ++i) put(v[i]);
  };
  put(margin);
  put(max_cells);
  put(tree.num_positions());
  for (const Step& s : tree.steps()) {
    out += tree.link_names()[s.parent] + '\n' + tree.link_names()[s.child] + '\n';
    put(s.type);
    for (int i = 0; i < 16; ++i) put(s.origin.matrix().data()[i]);
    put_vector(s.axis);
    put(s.source);
    put(s.multiplier);
    put(s.offset);
  }
  for (std::size_t j = 0; j < source_.size(); ++j) {
    put(source_[j]);
    put(lower_[j]);
    put(upper_[j]);
  }
  put(far_);
  for (const auto& [link, g] : {std::pair{p.a, p.ga}, std::pair{p.b, p.gb}}) {
    out += tree.link_names()[link] + '\n';
    const MeshModel& mesh = *g->mesh();
    put(mesh.num_vertices);
    for (int i = 0; i < mesh.num_vertices; ++i) put_vector(mesh.vertices[i]);
    put(mesh.num_tris);
    for (int t = 0; t < mesh.num_tris; ++t)
      for (int k = 0; k < 3; ++k) put(mesh.tri_indices[t][k]);
    for (const SphereTree* balls : {&g->outer(), &g->inner()}) {
      put(balls->num_spheres());
      for (std::size_t i = 0; i < balls->num_spheres(); ++i) {
        put_vector(balls->sphere(i).center);
        put(balls->sphere(i).radius);
      }
    }
  }
  return out;
}

// B's triangles by their vertices' largest distance from o_k, in shells up to these shares of
// R_k (the last takes the rest); empty shells are left out.
void PairJointTable::make_shells(const MeshModel& far, const Eigen::Vector3d& o_k, double R_k) {
  constexpr double kShare[] = {0.125, 0.25, 0.375, 0.5, 0.75};
  constexpr std::size_t kShells = std::size(kShare) + 1;
  std::vector<TriangleMesh> parts(kShells);
  std::vector<double> rho(kShells, 0.0);
  for (int t = 0; t < far.num_tris; ++t) {
    const ::fcl::Triangle& tri = far.tri_indices[t];
    double r = 0.0;
    for (int k = 0; k < 3; ++k) r = std::max(r, (far.vertices[tri[k]] - o_k).norm());
    std::size_t s = 0;
    while (s + 1 < kShells && r > kShare[s] * R_k) ++s;
    TriangleMesh& part = parts[s];
    const int first = int(part.vertices.size());
    for (int k = 0; k < 3; ++k) part.vertices.push_back(far.vertices[tri[k]]);
    part.triangles.push_back({first, first + 1, first + 2});
    rho[s] = std::max(rho[s], r);
  }
  for (std::size_t s = 0; s < kShells; ++s)
    if (!parts[s].triangles.empty()) shells_.push_back({make_mesh_model(parts[s]), rho[s]});
}

// Free when every shell of B is farther than margin + W_s from the other link at the poses
// X, colliding when one is within margin - W_s (its closest point moves by at most W_s), as
// the file comment's levers say. A shell's distance is exact wherever it decides.
BoundsVerdict PairJointTable::shells_verdict(const std::vector<Eigen::Isometry3d>& X, const Pair& p,
                                             double margin, double H, double E, double pad) const {
  const bool far_is_b = far_ == p.b;
  const MeshModel& near = *(far_is_b ? p.ga : p.gb)->mesh();
  const Eigen::Isometry3d& X_near = X[far_is_b ? p.a : p.b];
  bool free = true;
  for (const Shell& s : shells_) {
    const double W = (H * s.rho + E) * (1.0 + 1e-12) + pad;
    const double d = exact_distance(near, X_near, *s.mesh, X[far_], margin + W);
    if (d + W <= margin) return BoundsVerdict::colliding;
    free = free && d > margin + W;
  }
  return free ? BoundsVerdict::free : BoundsVerdict::undecided;
}

// One cell's verdict: the sphere trees' bounds against margin +- D, then each shell's
// distance at the centre against margin + W_s (free) and margin - W_s (colliding).
BoundsVerdict PairJointTable::cell(const KinematicTree& tree, const Pair& p, double margin,
                                   const std::vector<double>& R, const std::vector<double>& lo,
                                   const std::vector<double>& hi) const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(Eigen::Index(tree.num_positions()));
  double D = 0.0, H = 0.0, E = 0.0;  // E, H: the levers' terms
  for (std::size_t j = 0; j < source_.size(); ++j) {
    const double h = 0.5 * (hi[j] - lo[j]);
    q[source_[j]] = 0.5 * (lo[j] + hi[j]);
    D += R[j] * h;
    H += h;
    E += (R[j] - R.back()) * h;
  }
  const double pad = 1e-9 * (1.0 + R[0]);
  D = D * (1.0 + 1e-12) + pad;
  const std::vector<Eigen::Isometry3d> X = tree.link_poses(q);
  // The sphere trees' bounds first (lower > margin + D: free; upper <= margin - D:
  // colliding), then the meshes.
  if (decide(*p.ga, X[p.a], *p.gb, X[p.b], margin + D).verdict == BoundsVerdict::free)
    return BoundsVerdict::free;
  if (D <= margin &&
      decide(*p.ga, X[p.a], *p.gb, X[p.b], margin - D).verdict == BoundsVerdict::colliding)
    return BoundsVerdict::colliding;
  return shells_verdict(X, p, margin, H, E, pad);
}

// Breadth first: a leaf neither free nor colliding is split in two along the joint of the
// largest R_j h_j, while the leaves number fewer than max_cells.
void PairJointTable::bake(const KinematicTree& tree, const Pair& p, double margin,
                          const std::vector<double>& R, std::size_t max_cells) {
  struct Box {
    std::size_t node;
    std::vector<double> lo, hi;
  };
  std::deque<Box> queue{{0, lower_, upper_}};
  nodes_.assign(1, Node{});
  std::size_t leaves = 1;
  while (!queue.empty()) {
    Box box = std::move(queue.front());
    queue.pop_front();
    nodes_[box.node].verdict = cell(tree, p, margin, R, box.lo, box.hi);
    if (nodes_[box.node].verdict != BoundsVerdict::undecided || leaves >= max_cells) continue;
    std::size_t dim = 0;
    for (std::size_t j = 1; j < source_.size(); ++j)
      if (R[j] * (box.hi[j] - box.lo[j]) > R[dim] * (box.hi[dim] - box.lo[dim])) dim = j;
    const double mid = 0.5 * (box.lo[dim] + box.hi[dim]);
    const std::size_t child = nodes_.size();
    nodes_[box.node].child = int(child);
    nodes_[box.node].dim = int(dim);
    nodes_[box.node].mid = mid;
    nodes_.resize(child + 2);
    Box left{child, box.lo, box.hi};
    left.hi[dim] = mid;
    Box right{child + 1, std::move(box.lo), std::move(box.hi)};
    right.lo[dim] = mid;
    queue.push_back(std::move(left));
    queue.push_back(std::move(right));
    ++leaves;
  }
}

BoundsVerdict PairJointTable::verdict(const double* q) const {
  for (std::size_t j = 0; j < source_.size(); ++j) {
    const double x = q[source_[j]];
    if (!(x >= lower_[j] && x <= upper_[j])) return BoundsVerdict::undecided;
  }
  std::size_t n = 0;
  while (nodes_[n].child >= 0)
    n = std::size_t(nodes_[n].child) + (q[source_[std::size_t(nodes_[n].dim)]] > nodes_[n].mid);
  return nodes_[n].verdict;
}

std::size_t PairJointTable::free_cells() const noexcept {
  return std::size_t(std::count_if(nodes_.begin(), nodes_.end(), [](const Node& n) {
    return n.child < 0 && n.verdict == BoundsVerdict::free;
  }));
}

std::size_t PairJointTable::colliding_cells() const noexcept {
  return std::size_t(std::count_if(nodes_.begin(), nodes_.end(), [](const Node& n) {
    return n.child < 0 && n.verdict == BoundsVerdict::colliding;
  }));
}

}  // namespace medspheres::fcl
