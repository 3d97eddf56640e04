// Certified distance bounds (medspheres/fcl/bounded_geometry.h) against oracles: the exact
// distance between the solids, from FCL's OBBRSS mesh queries (surfaces) plus a winding
// number test for one solid inside another; independent sphere-tree distance queries for
// the values of the joint walk; serial answers for the thread test.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <fcl/fcl.h>
#include <catch2/catch.hpp>

#include "medspheres/bake/bake.h"
#include "medspheres/cover/cover.h"
#include "medspheres/error.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/point_triangle.h"
#include "support/fcl_fixtures.h"
#include "support/robot_fixtures.h"
#include "support/sphere_fixtures.h"

using namespace medspheres;
namespace mt = medspheres::test;
namespace mf = medspheres::fcl;

namespace {

// FCL's own double rounding in the exact distance (a few ulps of the scene).
constexpr double kOracleRounding = 1e-12;

struct Solid {
  std::string name;
  TriangleMesh mesh;
  std::unique_ptr<MeshQuery> query;
  SphereSet inner, outer;
  std::shared_ptr<mf::MeshModel> bvh;
  std::unique_ptr<mf::BoundedGeometry> geometry;      // with the mesh
  std::unique_ptr<mf::BoundedGeometry> spheres_only;  // without it
};

std::unique_ptr<Solid> make_solid(const std::string& name, TriangleMesh mesh) {
  auto s = std::make_unique<Solid>();
  s->name = name;
  s->mesh = std::move(mesh);
  s->query = std::make_unique<MeshQuery>(s->mesh);
  BakeOptions bo;
  bo.resolution = 24;
  s->inner = bake(*s->query, bo).spheres;
  CoverResult cover = bake_cover(*s->query, 24);
  REQUIRE(cover.certificate.certified);
  s->outer = cover.spheres;
  s->outer.metadata_json = R"({"stats": {"certified": true}})";
  s->bvh = mt::make_bvh<::fcl::OBBRSSd>(s->mesh);
  s->geometry = std::make_unique<mf::BoundedGeometry>(name, s->inner, s->outer, s->bvh);
  s->spheres_only = std::make_unique<mf::BoundedGeometry>(name, s->inner, s->outer);
  return s;
}

const std::vector<std::unique_ptr<Solid>>& solids() {
  static const std::vector<std::unique_ptr<Solid>> all = [] {
    std::vector<std::unique_ptr<Solid>> v;
    v.push_back(make_solid("box", make_box(Eigen::Vector3d(0.3, 0.2, 0.25), 2)));
    v.push_back(make_solid("ball", make_icosphere(0.3, 2)));
    v.push_back(make_solid("capsule", make_capsule(0.12, 0.35, 16, 6)));
    v.push_back(make_solid("torus", make_torus(0.3, 0.1, 24, 12)));
    return v;
  }();
  return all;
}

bool inside(const Solid& s, const ::fcl::Transform3d& X_WS, const Eigen::Vector3d& p_W) {
  return s.query->inside(X_WS.inverse() * p_W);
}

// The distance between the two solids (0 when they overlap): FCL's surface distance, or 0
// when the surfaces meet or one solid holds a vertex of the other. *nested tells whether
// they overlap with no surface contact (one inside the other).
double exact_distance(const Solid& a, const ::fcl::Transform3d& X_WA, const Solid& b,
                      const ::fcl::Transform3d& X_WB, bool* nested) {
  ::fcl::CollisionRequestd creq;
  ::fcl::CollisionResultd cres;
  *nested = false;
  if (::fcl::collide(a.bvh.get(), X_WA, b.bvh.get(), X_WB, creq, cres) > 0) return 0.0;
  if (inside(b, X_WB, X_WA * a.mesh.vertices[0]) || inside(a, X_WA, X_WB * b.mesh.vertices[0])) {
    *nested = true;
    return 0.0;
  }
  ::fcl::DistanceRequestd dreq;
  ::fcl::DistanceResultd dres;
  return ::fcl::distance(a.bvh.get(), X_WA, b.bvh.get(), X_WB, dreq, dres);
}

// The distance between solid a and an FCL geometry g (a solid primitive or a mesh), 0 when
// they meet; *nested when g's origin is inside a without surface contact.
double exact_distance(const Solid& a, const ::fcl::Transform3d& X_WA,
                      const ::fcl::CollisionGeometryd& g, const ::fcl::Transform3d& X_WG,
                      bool* nested) {
  ::fcl::CollisionRequestd creq;
  ::fcl::CollisionResultd cres;
  *nested = false;
  if (::fcl::collide(a.bvh.get(), X_WA, &g, X_WG, creq, cres) > 0) return 0.0;
  // A primitive inside the solid touches no triangle: its centre is then inside.
  if (inside(a, X_WA, X_WG.translation())) {
    *nested = true;
    return 0.0;
  }
  // GJK shapes (the capsule) to a tight tolerance: at FCL's default (1e-6) its triangle
  // distances come out up to ~6e-6 long, more than the surface points' upper bound.
  ::fcl::DistanceRequestd dreq;
  dreq.distance_tolerance = 1e-12;
  ::fcl::DistanceResultd dres;
  return ::fcl::distance(a.bvh.get(), X_WA, &g, X_WG, dreq, dres);
}

struct PosedPair {
  const Solid* a;
  const Solid* b;
  ::fcl::Transform3d X_WA, X_WB;
};

std::vector<PosedPair> seeded_pairs(unsigned seed, int per_pair, double spread) {
  std::mt19937 rng(seed);
  std::vector<PosedPair> out;
  for (const auto& a : solids())
    for (const auto& b : solids())
      for (int k = 0; k < per_pair; ++k)
        out.push_back(
            {a.get(), b.get(), mt::random_pose(rng, spread), mt::random_pose(rng, spread)});
  return out;
}

}  // namespace

TEST_CASE("distance bounds hold the exact distance between two solids", "[bounds]") {
  int apart = 0, touching = 0, nested = 0;
  for (const PosedPair& p : seeded_pairs(7, 60, 0.45)) {
    bool is_nested = false;
    const double d = exact_distance(*p.a, p.X_WA, *p.b, p.X_WB, &is_nested);
    const mf::BoundsResult r = mf::distance_bounds(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB);
    INFO(p.a->name << " / " << p.b->name << ": exact " << d << ", [" << r.bounds.lower << ", "
                   << r.bounds.upper << "]");
    CHECK(r.certified);
    CHECK(r.bounds.lower <= r.bounds.upper);
    CHECK(d <= r.bounds.upper + kOracleRounding);
    // Nested solids (no surface contact) are outside the surface certificate's reach.
    if (!is_nested) CHECK(r.bounds.lower <= d + kOracleRounding);
    (is_nested ? nested : d > 0.0 ? apart : touching)++;
  }
  INFO("apart " << apart << ", overlapping " << touching << ", nested " << nested);
  CHECK(apart > 100);
  CHECK(touching > 100);
}

TEST_CASE("surface points tighten the upper bound and keep it above the exact distance",
          "[bounds]") {
  // Every vertex (the default), and one per 50 cm cube.
  mf::BoundedGeometryOptions sparse;
  sparse.surface_point_spacing = 0.5;
  std::map<const Solid*, std::unique_ptr<mf::BoundedGeometry>> thinned;
  for (const auto& s : solids()) {
    CHECK(s->geometry->surface_points() == s->mesh.vertices.size());
    CHECK(s->spheres_only->surface_points() == 0);
    thinned[s.get()] =
        std::make_unique<mf::BoundedGeometry>(s->name, s->inner, s->outer, s->bvh, sparse);
    CHECK(thinned[s.get()]->surface_points() > 0);
    CHECK(thinned[s.get()]->surface_points() < s->mesh.vertices.size());
  }
  int tighter = 0, decided_colliding = 0, colliding_without = 0;
  for (const PosedPair& p : seeded_pairs(17, 60, 0.45)) {
    bool is_nested = false;
    const double d = exact_distance(*p.a, p.X_WA, *p.b, p.X_WB, &is_nested);
    const double with =
        mf::distance_bounds(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB).bounds.upper;
    const double few =
        mf::distance_bounds(*thinned[p.a], p.X_WA, *thinned[p.b], p.X_WB).bounds.upper;
    const double without =
        mf::distance_bounds(*p.a->spheres_only, p.X_WA, *p.b->spheres_only, p.X_WB).bounds.upper;
    INFO(p.a->name << " / " << p.b->name << ": exact " << d << ", upper " << with << " (thinned "
                   << few << ", inner balls only " << without << ")");
    CHECK(d <= with + kOracleRounding);
    CHECK(d <= few + kOracleRounding);
    CHECK(with <= without + 1e-12);
    CHECK(with <= few + 1e-12);
    if (with < without - 1e-9) ++tighter;
    // At margin 0: a surface point inside the other solid's inner balls is a certain contact.
    decided_colliding += mf::decide(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB).verdict ==
                         BoundsVerdict::colliding;
    colliding_without +=
        mf::decide(*p.a->spheres_only, p.X_WA, *p.b->spheres_only, p.X_WB).verdict ==
        BoundsVerdict::colliding;
  }
  INFO("tighter " << tighter << ", certain contacts " << decided_colliding << " against "
                  << colliding_without);
  CHECK(tighter > 100);
  CHECK(decided_colliding > colliding_without);
  sparse.surface_point_spacing = -1.0;
  const Solid& s = *solids()[0];
  CHECK_THROWS_AS(mf::BoundedGeometry("l", s.inner, s.outer, s.bvh, sparse), InputError);
}

// Brute force: the least distance of the balls at X_WA to the mesh's triangles at X_WB
// (a surface), minus the balls' radii.
double balls_to_triangles(const SphereSet& balls, const ::fcl::Transform3d& X_WA,
                          const TriangleMesh& mesh, const ::fcl::Transform3d& X_WB) {
  double d = std::numeric_limits<double>::infinity();
  for (const Sphere& b : balls.spheres) {
    const Eigen::Vector3d c = X_WB.inverse() * (X_WA * b.center);
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
      const Eigen::Vector3d q =
          closest_point_on_triangle(c, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2));
      d = std::min(d, (q - c).norm() - b.radius);
    }
  }
  return d;
}

TEST_CASE("a geometry of exact balls settles against a mesh without a mesh of its own",
          "[bounds]") {
  // Four 2 cm balls (a foot of contact spheres): inner and outer are the same balls.
  SphereSet feet;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(0.1, 0.05, 0), Eigen::Vector3d(0.1, -0.05, 0),
                                   Eigen::Vector3d(-0.1, 0.05, 0), Eigen::Vector3d(-0.1, -0.05, 0)})
    feet.spheres.push_back({c, 0.02});
  feet.metadata_json = R"({"certified": true})";
  const mf::BoundedGeometry foot("foot", feet, feet);
  CHECK(foot.exact_balls());
  CHECK_FALSE(solids()[0]->geometry->exact_balls());
  std::mt19937 rng(37);
  int by_mesh = 0;
  for (const auto& s : solids()) {
    for (int k = 0; k < 60; ++k) {
      const ::fcl::Transform3d X_WA = mt::random_pose(rng, 0.35), X_WB = mt::random_pose(rng, 0.35);
      // Oracle: brute force, each ball's distance to the mesh's triangles (a surface), 0
      // when they meet. A ball wholly inside the solid (no surface contact) is outside the
      // bounds' reach.
      double d = std::numeric_limits<double>::infinity();
      bool nested = false;
      for (const Sphere& b : feet.spheres) {
        SphereSet one;
        one.spheres.push_back(b);
        const double db = std::max(0.0, balls_to_triangles(one, X_WA, s->mesh, X_WB));
        nested = nested || (db > 0.0 && inside(*s, X_WB, X_WA * b.center));
        d = std::min(d, db);
      }
      if (nested) continue;
      for (const double margin : {0.0, 0.02}) {
        const mf::CollideResult c = mf::collide(foot, X_WA, *s->geometry, X_WB, margin);
        const mf::CollideResult r = mf::collide(*s->geometry, X_WB, foot, X_WA, margin);
        const mf::CollideResult g = mf::collide(foot, X_WA, *s->bvh, X_WB, margin);
        INFO(s->name << " margin " << margin << ": exact " << d);
        for (const mf::CollideResult* x : {&c, &r, &g}) {
          REQUIRE(x->verdict != BoundsVerdict::undecided);
          // Away from the threshold by more than the oracle's rounding.
          if (std::abs(d - margin) > 1e-9)
            CHECK((x->verdict == BoundsVerdict::colliding) == (d <= margin));
          by_mesh += x->path == mf::AnswerPath::mesh;
        }
        CHECK(c.verdict == r.verdict);
      }
    }
  }
  CHECK(by_mesh > 0);
}

TEST_CASE(
    "exact balls against a mesh near contact: the mesh's geometry, the walk and brute force agree",
    "[bounds]") {
  // Three 1 cm balls brought towards each solid from outside until the first pose within
  // the margin, bisected to the brute-force distance = margin, then moved 1e-6 and 1e-4
  // either side: the settle() against a BoundedGeometry with its mesh, the tree-target walk
  // (the bare BVHModel) and brute force agree.
  SphereSet feet;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(0.04, 0.0, 0.0), Eigen::Vector3d(-0.03, 0.02, 0),
                                   Eigen::Vector3d(0.0, -0.03, 0.01)})
    feet.spheres.push_back({c, 0.01});
  feet.metadata_json = R"({"certified": true})";
  const mf::BoundedGeometry foot("foot", feet, feet);
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double margin = 0.01;
  int checked = 0, colliding = 0;
  for (const auto& s : solids()) {
    for (int k = 0; k < 8; ++k) {
      const ::fcl::Transform3d X_WB = mt::random_pose(rng, 0.2);
      ::fcl::Transform3d X_WA = mt::random_pose(rng, 0.2);
      const Eigen::Vector3d dir = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
      auto at = [&](double t) {
        ::fcl::Transform3d X = X_WA;
        X.translation() = X_WB.translation() + t * dir;
        return X;
      };
      auto f = [&](double t) { return balls_to_triangles(feet, at(t), s->mesh, X_WB) - margin; };
      double far = 1.0, near = far;
      while (near > 0.0 && f(near) > 0.0) near -= 0.01;
      if (!(f(near) <= 0.0)) continue;
      far = near + 0.01;
      for (int h = 0; h < 60; ++h) (f(0.5 * (near + far)) > 0.0 ? far : near) = 0.5 * (near + far);
      for (const double eps : {-1e-4, -1e-6, 0.0, 1e-6, 1e-4}) {
        const ::fcl::Transform3d X = at(far + eps);
        const double d = balls_to_triangles(feet, X, s->mesh, X_WB);
        const mf::CollideResult fcl_path = mf::collide(foot, X, *s->geometry, X_WB, margin);
        const mf::CollideResult swapped = mf::collide(*s->geometry, X_WB, foot, X, margin);
        const mf::CollideResult walk = mf::collide(foot, X, *s->bvh, X_WB, margin);
        INFO(s->name << " pose " << k << " eps " << eps << ": brute force " << d);
        REQUIRE(fcl_path.verdict != BoundsVerdict::undecided);
        CHECK(fcl_path.verdict == swapped.verdict);
        // Away from the threshold by more than the methods' rounding.
        if (std::abs(d - margin) > 1e-9) {
          CHECK(fcl_path.verdict == walk.verdict);
          CHECK((fcl_path.verdict == BoundsVerdict::colliding) == (d <= margin));
          ++checked;
          colliding += d <= margin;
        }
      }
    }
  }
  CHECK(checked >= 60);
  CHECK(colliding >= 20);
  CHECK(checked - colliding >= 20);
}

TEST_CASE("a ball that meets a mesh's surface is never read as farther", "[bounds]") {
  // A 1 cm ball centred half its radius outside and inside each solid's faces, margin 0:
  // exact balls and an fcl::Sphere against the geometry with its mesh both collide (FCL's
  // own sphere-to-mesh distance left such triangles' distances unset, and read some balls
  // as far).
  std::mt19937 rng(43);
  int checked = 0;
  for (const auto& s : solids()) {
    std::uniform_int_distribution<std::size_t> pick(0, s->mesh.triangles.size() - 1);
    for (int k = 0; k < 40; ++k) {
      const std::size_t t = pick(rng);
      const Eigen::Vector3d a = s->mesh.corner(t, 0), b = s->mesh.corner(t, 1),
                            c = s->mesh.corner(t, 2);
      const Eigen::Vector3d n = (b - a).cross(c - a).normalized(), mid = (a + b + c) / 3;
      const ::fcl::Transform3d X_WB = mt::random_pose(rng, 0.35);
      for (const double side : {0.5, -0.5}) {
        const Eigen::Vector3d centre = X_WB * (mid + side * 0.01 * n);
        SphereSet one;
        one.spheres.push_back({Eigen::Vector3d::Zero(), 0.01});
        one.metadata_json = R"({"certified": true})";
        const mf::BoundedGeometry ball("ball", one, one);
        ::fcl::Transform3d X_WA = ::fcl::Transform3d::Identity();
        X_WA.translation() = centre;
        INFO(s->name << " triangle " << t << " side " << side);
        CHECK(mf::collide(ball, X_WA, *s->geometry, X_WB, 0.0).verdict == BoundsVerdict::colliding);
        CHECK(mf::collide(*s->geometry, X_WB, ::fcl::Sphered(0.01), X_WA, 0.0).verdict ==
              BoundsVerdict::colliding);
        CHECK(mf::exact_distance(*s->bvh, X_WB, ::fcl::Sphered(0.01), X_WA, 0.0) <= 0.0);
        ++checked;
      }
    }
  }
  CHECK(checked >= 160);
}

TEST_CASE("the joint walk gives the two sphere-set distances", "[bounds]") {
  for (const PosedPair& p : seeded_pairs(11, 25, 0.6)) {
    const DistanceBounds b =
        distance_bounds(p.a->geometry->inner(), p.a->geometry->outer(), p.X_WA,
                        p.b->geometry->inner(), p.b->geometry->outer(), p.X_WB);
    const double outer =
        distance(p.a->geometry->outer(), p.X_WA, p.b->geometry->outer(), p.X_WB).distance;
    const double inner =
        distance(p.a->geometry->inner(), p.X_WA, p.b->geometry->inner(), p.X_WB).distance;
    INFO(p.a->name << " / " << p.b->name);
    // The rounding allowance is at most 64 ulps of a scene of extent < 10.
    CHECK(b.lower == Approx(std::max(0.0, outer)).margin(1e-12));
    CHECK(b.upper == Approx(std::max(0.0, inner)).margin(1e-12));
    // The pair named for upper is an inner pair at the inner sets' distance.
    REQUIRE(b.upper_a >= 0);
    REQUIRE(b.upper_b >= 0);
    const Sphere sa = p.a->geometry->inner().sphere(static_cast<std::size_t>(b.upper_a));
    const Sphere sb = p.b->geometry->inner().sphere(static_cast<std::size_t>(b.upper_b));
    const double gap = (p.X_WA * sa.center - p.X_WB * sb.center).norm() - sa.radius - sb.radius;
    CHECK(std::max(0.0, gap) == Approx(std::max(0.0, inner)).margin(1e-12));
  }
}

TEST_CASE("three-valued collide is never wrong and uses the mesh only when undecided", "[bounds]") {
  for (const double margin : {0.0, 0.01, 0.05}) {
    int decided = 0, fallback = 0;
    for (const PosedPair& p : seeded_pairs(23, 40, 0.5)) {
      bool is_nested = false;
      const double d = exact_distance(*p.a, p.X_WA, *p.b, p.X_WB, &is_nested);
      const mf::CollideResult fast =
          mf::collide(*p.a->spheres_only, p.X_WA, *p.b->spheres_only, p.X_WB, margin);
      const mf::CollideResult full =
          mf::collide(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB, margin);
      // The spheres' own verdict with the surface points the mesh brings.
      const mf::CollideResult first =
          mf::decide(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB, margin);
      INFO(p.a->name << " / " << p.b->name << " margin " << margin << ": exact " << d);
      CHECK(fast.path == mf::AnswerPath::spheres);
      if (fast.verdict == BoundsVerdict::free && !is_nested) CHECK(d > margin - kOracleRounding);
      if (fast.verdict == BoundsVerdict::colliding) CHECK(d <= margin + kOracleRounding);
      CHECK(fast.bounds.lower <= d + kOracleRounding + (is_nested ? 1e9 : 0.0));
      CHECK(d <= fast.bounds.upper + kOracleRounding);
      if (first.verdict == BoundsVerdict::free && !is_nested) CHECK(d > margin - kOracleRounding);
      if (first.verdict == BoundsVerdict::colliding) CHECK(d <= margin + kOracleRounding);
      // Surface points only ever decide more: a verdict of the balls alone stands.
      if (fast.verdict != BoundsVerdict::undecided) CHECK(first.verdict == fast.verdict);
      // The mesh is consulted exactly when the spheres leave it undecided.
      CHECK((full.path == mf::AnswerPath::mesh) == (first.verdict == BoundsVerdict::undecided));
      CHECK(full.verdict != BoundsVerdict::undecided);
      if (full.path == mf::AnswerPath::spheres) CHECK(full.verdict == first.verdict);
      if (full.path == mf::AnswerPath::mesh) {
        ++fallback;
        if (!is_nested) CHECK((full.verdict == BoundsVerdict::colliding) == (d <= margin));
        // FCL's search is pruned at the margin: exact within it, above it otherwise.
        if (!is_nested && d > 0.0 && d <= margin - kOracleRounding)
          CHECK(std::abs(full.mesh_distance - d) <= kOracleRounding);
        if (!is_nested && d > margin + kOracleRounding) CHECK(full.mesh_distance > margin);
      } else {
        ++decided;
      }
    }
    INFO("decided " << decided << ", fallback " << fallback);
    CHECK(decided > fallback);
  }
}

TEST_CASE("bounds against FCL geometries hold the exact distance", "[bounds]") {
  std::vector<std::pair<std::string, std::shared_ptr<::fcl::CollisionGeometryd>>> others = {
      {"fcl box", std::make_shared<::fcl::Boxd>(0.4, 0.3, 0.5)},
      {"fcl sphere", std::make_shared<::fcl::Sphered>(0.2)},
      {"fcl capsule", std::make_shared<::fcl::Capsuled>(0.1, 0.5)},
      {"torus mesh", solids()[3]->bvh},
  };
  std::mt19937 rng(31);
  int apart = 0, overlapping = 0;
  for (const auto& a : solids()) {
    for (const auto& [name, g] : others) {
      for (int k = 0; k < 50; ++k) {
        const ::fcl::Transform3d X_WA = mt::random_pose(rng, 0.4), X_WB = mt::random_pose(rng, 0.4);
        bool nested = false;
        const double d = exact_distance(*a, X_WA, *g, X_WB, &nested);
        const mf::BoundsResult r = mf::distance_bounds(*a->geometry, X_WA, *g, X_WB);
        INFO(a->name << " / " << name << ": exact " << d << ", [" << r.bounds.lower << ", "
                     << r.bounds.upper << "]");
        // GJK primitives answer within FCL's default tolerance (1e-6).
        CHECK(d <= r.bounds.upper + 1e-6);
        if (!nested) CHECK(r.bounds.lower <= d + 1e-6);
        const mf::CollideResult c = mf::collide(*a->geometry, X_WA, *g, X_WB, 0.0);
        CHECK(c.verdict != BoundsVerdict::undecided);
        if (c.path == mf::AnswerPath::spheres && !nested)
          CHECK((c.verdict == BoundsVerdict::colliding) == (d <= 0.0));
        (d > 0.0 ? apart : overlapping)++;
      }
    }
  }
  CHECK(apart > 50);
  CHECK(overlapping > 50);
}

TEST_CASE("bounded geometries refuse bad sets and report uncertified covers", "[bounds]") {
  const Solid& s = *solids()[0];
  SphereSet uncertified = s.outer;
  uncertified.metadata_json = R"({"stats": {"certified": false}})";
  try {
    mf::BoundedGeometry g("left_wrist", s.inner, uncertified);
    FAIL("an uncertified outer set was accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("left_wrist") != std::string::npos);
    CHECK(std::string(e.what()).find("certified") != std::string::npos);
  }
  CHECK_THROWS_AS(mf::BoundedGeometry("l", SphereSet{}, s.outer), InputError);
  CHECK_THROWS_AS(mf::BoundedGeometry("l", s.inner, SphereSet{}), InputError);
  SphereSet bad = s.inner;
  bad.spheres[0].radius = -1.0;
  CHECK_THROWS_AS(mf::BoundedGeometry("l", bad, s.outer), InputError);

  mf::BoundedGeometryOptions loose;
  loose.allow_uncertified = true;
  const mf::BoundedGeometry g("left_wrist", s.inner, uncertified, nullptr, loose);
  CHECK_FALSE(g.certified());
  const ::fcl::Transform3d X = ::fcl::Transform3d::Identity();
  ::fcl::Transform3d Y = X;
  Y.translation() = Eigen::Vector3d(2, 0, 0);
  CHECK_FALSE(mf::distance_bounds(g, X, *s.geometry, Y).certified);
  CHECK_FALSE(mf::collide(g, X, *s.geometry, Y).certified);
  CHECK(mf::distance_bounds(*s.geometry, X, *s.geometry, Y).certified);
  CHECK_THROWS_AS(mf::collide(*s.geometry, X, *s.geometry, Y, -0.1), std::invalid_argument);

  LinkSpheres link;
  link.inner = s.inner;
  link.outer = s.outer;
  link.outer.metadata_json = "{}";
  CHECK_THROWS_AS(mf::BoundedGeometry::from_link("hand", link), InputError);
  link.outer_certificate_json = R"({"certified": true, "triangles": 12})";
  CHECK(mf::BoundedGeometry::from_link("hand", link).certified());
  CHECK(mf::records_certified_cover(R"({"stats": {"certified": true}})"));
  CHECK_FALSE(mf::records_certified_cover("not json"));
  CHECK_FALSE(mf::records_certified_cover(R"({"certified": 1})"));
}

TEST_CASE("bounds queries from many threads give the serial answers", "[bounds]") {
  const std::vector<PosedPair> pairs = seeded_pairs(41, 10, 0.5);
  auto run = [&](std::vector<double>& out) {
    for (const PosedPair& p : pairs) {
      const mf::BoundsResult r =
          mf::distance_bounds(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB);
      const mf::CollideResult c = mf::collide(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB, 0.01);
      out.insert(out.end(), {r.bounds.lower, r.bounds.upper, double(c.verdict), double(c.path),
                             c.mesh_distance});
    }
  };
  std::vector<double> serial;
  run(serial);
  std::vector<std::vector<double>> results(8);
  std::vector<std::thread> threads;
  for (auto& r : results) threads.emplace_back([&run, &r] { run(r); });
  for (auto& t : threads) t.join();
  for (const auto& r : results) CHECK(r == serial);
}

namespace {

// The three-link arm with a solid on every link but the tool.
RobotModel solid_arm(std::map<std::string, std::shared_ptr<const mf::MeshModel>>* meshes,
                     std::map<std::string, const Solid*>* solid_of) {
  RobotModel m = mt::three_link_arm();
  const std::vector<std::string> names = {"base", "l1", "l2", "l3"};
  for (Link& link : m.links) {
    const auto k = std::find(names.begin(), names.end(), link.name) - names.begin();
    if (k == 4) continue;
    const Solid& s = *solids()[k];
    link.spheres.inner = s.inner;
    link.spheres.outer = s.outer;
    link.spheres.outer_certificate_json = R"({"certified": true})";
    (*meshes)[link.name] = s.bvh;
    (*solid_of)[link.name] = &s;
  }
  return m;
}

}  // namespace

namespace {

// The exact distance of one pair of robot_bounds (a link against a link or a scene object).
double pair_exact(const mf::RobotBounds& robot, const std::map<std::string, const Solid*>& solid_of,
                  const std::vector<::fcl::Transform3d>& X,
                  const std::vector<const ::fcl::CollisionObjectd*>& scene,
                  const mf::LinkPairBounds& p, bool* nested) {
  const auto& names = robot.kinematics().link_names();
  const Solid& a = *solid_of.at(names[robot.link_of()[p.link]]);
  if (p.self)
    return exact_distance(a, X[p.link], *solid_of.at(names[robot.link_of()[p.other]]), X[p.other],
                          nested);
  return exact_distance(a, X[p.link], *scene[p.other]->collisionGeometry(),
                        scene[p.other]->getTransform(), nested);
}

}  // namespace

TEST_CASE("robot bounds hold every pair's and the minimum exact distance", "[bounds][robot]") {
  std::map<std::string, std::shared_ptr<const mf::MeshModel>> meshes;
  std::map<std::string, const Solid*> solid_of;
  const RobotModel model = solid_arm(&meshes, &solid_of);
  const mf::RobotBounds robot(model, meshes);
  const auto& names = robot.kinematics().link_names();
  // base, l1, l2, l3 have geometry; adjacent pairs excluded: (base, l2), (base, l3), (l1, l3).
  std::set<std::pair<std::string, std::string>> pairs;
  for (const auto& [a, b] : robot.self_pairs())
    pairs.insert({names[robot.link_of()[a]], names[robot.link_of()[b]]});
  CHECK(pairs == std::set<std::pair<std::string, std::string>>{
                     {"base", "l2"}, {"base", "l3"}, {"l1", "l3"}});
  CHECK(mf::RobotBounds(model, meshes, {{"l3", "base"}}).self_pairs().size() == 2);
  CHECK_THROWS_AS(mf::RobotBounds(model, meshes, {{"l3", "elbow"}}), InputError);

  auto box = std::make_shared<::fcl::Boxd>(0.6, 0.4, 0.3);
  auto ball = std::make_shared<::fcl::Sphered>(0.25);
  std::mt19937 rng(5);
  ::fcl::CollisionObjectd o1(box, mt::random_pose(rng, 1.0)), o2(ball, mt::random_pose(rng, 1.0)),
      o3(solids()[3]->bvh, mt::random_pose(rng, 1.0));
  const std::vector<const ::fcl::CollisionObjectd*> scene = {&o1, &o2, &o3};

  std::uniform_real_distribution<double> q1(-3.0, 3.0), q2(0.0, 0.5);
  int colliding = 0, free = 0;
  for (int k = 0; k < 40; ++k) {
    const Eigen::VectorXd q = Eigen::Vector2d(q1(rng), q2(rng));
    const mf::RobotBoundsResult r = mf::robot_bounds(robot, q, scene, true, true);
    const std::vector<::fcl::Transform3d> X = robot.poses(q, Eigen::Isometry3d::Identity());
    double min_exact = std::numeric_limits<double>::infinity();
    bool any_nested = false;
    REQUIRE(r.pairs.size() == 4 * scene.size() + 3);
    for (const mf::LinkPairBounds& p : r.pairs) {
      bool nested = false;
      const double d = pair_exact(robot, solid_of, X, scene, p, &nested);
      INFO("q " << q.transpose() << " pair " << p.link << "/" << p.other
                << (p.self ? " self" : ""));
      CHECK(d <= p.bounds.upper + 1e-6);
      if (!nested) CHECK(p.bounds.lower <= d + 1e-6);
      min_exact = std::min(min_exact, d);
      any_nested = any_nested || nested;
    }
    CHECK(min_exact <= r.minimum.upper + 1e-6);
    if (!any_nested) CHECK(r.minimum.lower <= min_exact + 1e-6);
    const mf::RobotCollideResult c = mf::robot_collide(robot, q, scene, true, 0.01);
    CHECK(c.verdict != BoundsVerdict::undecided);
    if (!any_nested) CHECK((c.verdict == BoundsVerdict::colliding) == (min_exact <= 0.01));
    (c.verdict == BoundsVerdict::colliding ? colliding : free)++;
  }
  CHECK(colliding > 0);
  CHECK(free > 0);
}

TEST_CASE("decide then settle is collide", "[bounds]") {
  for (const PosedPair& p : seeded_pairs(29, 10, 0.5)) {
    const mf::CollideResult whole =
        mf::collide(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB, 0.02);
    const mf::CollideResult first =
        mf::decide(*p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB, 0.02);
    const mf::CollideResult two =
        mf::settle(first, *p.a->geometry, p.X_WA, *p.b->geometry, p.X_WB, 0.02);
    CHECK(first.path == mf::AnswerPath::spheres);
    CHECK(two.verdict == whole.verdict);
    CHECK(two.path == whole.path);
    CHECK(two.mesh_distance == whole.mesh_distance);
    const mf::CollideResult g = mf::decide(*p.a->geometry, p.X_WA, *p.b->bvh, p.X_WB, 0.02);
    CHECK(mf::settle(g, *p.a->geometry, p.X_WA, *p.b->bvh, p.X_WB, 0.02).verdict ==
          mf::collide(*p.a->geometry, p.X_WA, *p.b->bvh, p.X_WB, 0.02).verdict);
  }
}

TEST_CASE("robot collide: meshes only when no pair surely collides, scene AABBs may be stale",
          "[bounds][robot]") {
  std::map<std::string, std::shared_ptr<const mf::MeshModel>> meshes;
  std::map<std::string, const Solid*> solid_of;
  const RobotModel model = solid_arm(&meshes, &solid_of);
  const mf::RobotBounds robot(model, meshes);
  auto box = std::make_shared<::fcl::Boxd>(0.3, 0.2, 0.2);
  ::fcl::CollisionObjectd o1(box), o2(solids()[1]->bvh);  // AABBs computed at the origin
  const std::vector<const ::fcl::CollisionObjectd*> scene = {&o1, &o2};
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> q1(-3.0, 3.0), q2(0.0, 0.5);
  int colliding = 0, free = 0, fallbacks = 0;
  for (int k = 0; k < 60; ++k) {
    o1.setTransform(mt::random_pose(rng, 1.2));  // no computeAABB(): the world AABB is stale
    o2.setTransform(mt::random_pose(rng, 1.2));
    const Eigen::VectorXd q = Eigen::Vector2d(q1(rng), q2(rng));
    const std::vector<::fcl::Transform3d> X = robot.poses(q, Eigen::Isometry3d::Identity());
    double min_exact = std::numeric_limits<double>::infinity();
    bool any_nested = false, sure = false;
    for (const mf::LinkPairBounds& p : mf::robot_bounds(robot, q, scene, true, true).pairs) {
      bool nested = false;
      const double d = pair_exact(robot, solid_of, X, scene, p, &nested);
      min_exact = std::min(min_exact, d);
      any_nested = any_nested || nested;
      sure = sure || p.bounds.upper <= 0.01;
    }
    const mf::RobotCollideResult c = mf::robot_collide(robot, q, scene, true, 0.01);
    INFO("q " << q.transpose() << ": exact " << min_exact);
    if (!any_nested) CHECK((c.verdict == BoundsVerdict::colliding) == (min_exact <= 0.01));
    if (sure) CHECK(c.mesh_fallbacks == 0);
    fallbacks += static_cast<int>(c.mesh_fallbacks);
    (c.verdict == BoundsVerdict::colliding ? colliding : free)++;
  }
  CHECK(colliding > 0);
  CHECK(free > 0);
  CHECK(fallbacks > 0);
}

TEST_CASE("sample_configurations are seeded and within the joint limits", "[bounds][robot]") {
  std::map<std::string, std::shared_ptr<const mf::MeshModel>> meshes;
  std::map<std::string, const Solid*> solid_of;
  const RobotModel model = solid_arm(&meshes, &solid_of);
  const KinematicTree tree(model);
  const auto a = mf::sample_configurations(model, tree, 200, 3);
  REQUIRE(a.size() == 200);
  CHECK(mf::sample_configurations(model, tree, 200, 3) == a);
  CHECK(mf::sample_configurations(model, tree, 200, 4) != a);
  for (std::size_t k = 0; k < tree.num_positions(); ++k) {
    const Joint& j = *model.find_joint(tree.joint_names()[k]);
    const bool limited = j.type != JointType::kContinuous && j.limits;
    const double lo = limited ? j.limits->lower : -M_PI, hi = limited ? j.limits->upper : M_PI;
    double seen_lo = hi, seen_hi = lo;
    for (const Eigen::VectorXd& q : a) {
      REQUIRE(q.size() == static_cast<Eigen::Index>(tree.num_positions()));
      CHECK(q[k] >= lo);
      CHECK(q[k] <= hi);
      seen_lo = std::min(seen_lo, q[k]);
      seen_hi = std::max(seen_hi, q[k]);
    }
    CHECK(seen_hi - seen_lo > 0.8 * (hi - lo));  // spread over the range
  }
}

namespace {

// solid_arm with l2 near the base, so that the arm collides with itself.
RobotModel self_colliding_arm(std::map<std::string, std::shared_ptr<const mf::MeshModel>>* meshes,
                              std::map<std::string, const Solid*>* solid_of) {
  RobotModel model = solid_arm(meshes, solid_of);
  for (Joint& j : model.joints)
    if (j.name == "j2") j.origin.translation() = Eigen::Vector3d(0.25, 0.0, 0.0);
  return model;
}

}  // namespace

TEST_CASE(
    "a self-pair order changes no verdict and puts first the pair that collides most "
    "where no witness holds",
    "[bounds][robot]") {
  std::map<std::string, std::shared_ptr<const mf::MeshModel>> meshes;
  std::map<std::string, const Solid*> solid_of;
  const RobotModel model = self_colliding_arm(&meshes, &solid_of);
  const mf::RobotBounds plain(model, meshes);
  const mf::SelfPairOrder order{300, 0.01, 7, 1};  // one witness: it leaves samples open
  const mf::RobotBounds ordered(model, meshes, {}, {}, order);
  auto sorted = [](std::vector<std::pair<std::size_t, std::size_t>> v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  CHECK(sorted(ordered.self_pairs()) == sorted(plain.self_pairs()));
  // Brute force over the same samples: every pair's count of certain collisions, in all
  // samples and in those where no witness holds.
  const auto samples = mf::sample_configurations(model, plain.kinematics(), order.samples, 7);
  std::map<std::pair<std::size_t, std::size_t>, int> hits, open_hits;
  const auto& g = plain.geometries();
  const auto& pairs = ordered.self_pairs();
  const std::size_t seen = ordered.seen_colliding();
  int samples_hit = 0, samples_hit_by_seen = 0;
  for (const Eigen::VectorXd& q : samples) {
    const auto X = plain.poses(q, Eigen::Isometry3d::Identity());
    bool any = false, by_seen = false, witnessed = false;
    for (const mf::SelfWitness& w : ordered.witnesses())
      witnessed = witnessed || (X[w.a] * w.in_a.center - X[w.b] * w.in_b.center).norm() -
                                       w.in_a.radius - w.in_b.radius <=
                                   0.01;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const auto [a, b] = pairs[k];
      const bool c = mf::decide(g[a], X[a], g[b], X[b], 0.01).verdict == BoundsVerdict::colliding;
      hits[{a, b}] += c ? 1 : 0;
      open_hits[{a, b}] += c && !witnessed ? 1 : 0;
      any = any || c;
      by_seen = by_seen || (c && k < seen);
    }
    samples_hit += any ? 1 : 0;
    samples_hit_by_seen += by_seen ? 1 : 0;
  }
  int most = 0, most_open = 0;
  for (const auto& [pair, n] : hits) most = std::max(most, n);
  for (const auto& [pair, n] : open_hits) most_open = std::max(most_open, n);
  REQUIRE(most > 0);
  REQUIRE(most_open > 0);  // the witnesses leave some colliding samples to the walks
  CHECK(open_hits[pairs.front()] == most_open);
  // The pairs seen colliding cover every sample in which some pair collides, and each of
  // them collides in some sample; without an order every pair counts as seen.
  CHECK(seen >= 1);
  CHECK(samples_hit_by_seen == samples_hit);
  for (std::size_t k = 0; k < seen; ++k) CHECK(hits[pairs[k]] > 0);
  CHECK(plain.seen_colliding() == plain.self_pairs().size());
  CHECK_THROWS_AS(mf::RobotBounds(model, meshes, {}, {}, {10, -1.0, 1}), std::invalid_argument);

  auto box = std::make_shared<::fcl::Boxd>(0.6, 0.4, 0.3);
  std::mt19937 rng(17);
  ::fcl::CollisionObjectd o1(box, mt::random_pose(rng, 1.0));
  const std::vector<const ::fcl::CollisionObjectd*> scene = {&o1};
  int colliding = 0;
  for (const Eigen::VectorXd& q : mf::sample_configurations(model, plain.kinematics(), 60, 8)) {
    const auto a = mf::robot_collide(plain, q, scene, true, 0.01);
    const auto b = mf::robot_collide(ordered, q, scene, true, 0.01);
    CHECK(a.verdict == b.verdict);
    colliding += a.verdict == BoundsVerdict::colliding ? 1 : 0;
  }
  CHECK(colliding > 0);
  CHECK(colliding < 60);
}

TEST_CASE("witnesses are inner sphere pairs of the samples, and each hit is a true collision",
          "[bounds][robot]") {
  std::map<std::string, std::shared_ptr<const mf::MeshModel>> meshes;
  std::map<std::string, const Solid*> solid_of;
  const RobotModel model = self_colliding_arm(&meshes, &solid_of);
  const double margin = 0.01;
  const mf::SelfPairOrder order{300, margin, 7};
  const mf::RobotBounds robot(model, meshes, {}, {}, order);
  CHECK(mf::RobotBounds(model, meshes).witnesses().empty());
  CHECK(mf::RobotBounds(model, meshes, {}, {}, {300, margin, 7, 1}).witnesses().size() == 1);
  const auto& w = robot.witnesses();
  REQUIRE(!w.empty());
  CHECK(w.size() <= order.max_witnesses);
  const auto& g = robot.geometries();
  auto is_inner_sphere = [&](std::size_t link, const Sphere& s) {
    const SphereTree& t = g[link].inner();
    for (std::size_t i = 0; i < t.num_spheres(); ++i)
      if (t.sphere(i).center == s.center && t.sphere(i).radius == s.radius) return true;
    return false;
  };
  // Brute force over the order's samples: in how many each witness's spheres are within
  // the margin; the first witness holds in the most (the greedy cover's first pick).
  const auto samples = mf::sample_configurations(model, robot.kinematics(), order.samples, 7);
  std::vector<int> held(w.size(), 0);
  for (const Eigen::VectorXd& q : samples) {
    const auto X = robot.poses(q, Eigen::Isometry3d::Identity());
    for (std::size_t k = 0; k < w.size(); ++k) {
      const double gap = (X[w[k].a] * w[k].in_a.center - X[w[k].b] * w[k].in_b.center).norm() -
                         w[k].in_a.radius - w[k].in_b.radius;
      held[k] += gap <= margin ? 1 : 0;
    }
  }
  for (std::size_t k = 0; k < w.size(); ++k) {
    CHECK(is_inner_sphere(w[k].a, w[k].in_a));
    CHECK(is_inner_sphere(w[k].b, w[k].in_b));
    CHECK(held[k] >= 1);
    CHECK(held[0] >= held[k]);
  }
  // Fresh configurations: a witness's "colliding" is confirmed by the exact meshes and by
  // the pair's own walk.
  int by_witness = 0;
  for (const Eigen::VectorXd& q : mf::sample_configurations(model, robot.kinematics(), 200, 8)) {
    const mf::RobotCollideResult r = mf::robot_collide(robot, q, {}, true, margin);
    if (!r.by_witness) continue;
    ++by_witness;
    CHECK(r.verdict == BoundsVerdict::colliding);
    const auto X = robot.poses(q, Eigen::Isometry3d::Identity());
    double nearest = std::numeric_limits<double>::infinity();
    bool walk_agrees = false;
    for (const auto& [a, b] : robot.self_pairs()) {
      bool nested = false;
      const auto& names = robot.kinematics().link_names();
      nearest =
          std::min(nearest, exact_distance(*solid_of.at(names[robot.link_of()[a]]), X[a],
                                           *solid_of.at(names[robot.link_of()[b]]), X[b], &nested));
      walk_agrees = walk_agrees ||
                    mf::decide(g[a], X[a], g[b], X[b], margin).verdict == BoundsVerdict::colliding;
    }
    CHECK(nearest <= margin + 1e-12);
    CHECK(walk_agrees);
  }
  CHECK(by_witness > 0);
  CHECK(mf::robot_collide(robot, samples[0], {}, false, margin).by_witness == false);
  CHECK_THROWS_AS(mf::robot_collide(robot, samples[0], {}, true, -1.0), std::invalid_argument);
}
