// A sphere set against every FCL primitive, BVHModels of every BV type, and an octree,
// against brute force over its spheres through FCL's own fcl::Sphere narrowphase: values,
// primitive ids (triangle indices, octree query cell ids), nearest points and contact
// positions; exact touching; abs_err and rel_err; many threads.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <thread>
#include <tuple>
#include <vector>

#include <octomap/octomap.h>
#include <catch2/catch.hpp>

#include "medspheres/fcl/sphere_set_geometry.h"
#include "support/fcl_fixtures.h"
#include "support/sphere_fixtures.h"
#include "support/tolerance_tally.h"

using medspheres::Sphere;
using medspheres::SphereSet;
using medspheres::fcl::SphereSetGeometry;
namespace mt = medspheres::test;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();
const Eigen::Vector3d kUnknown = Eigen::Vector3d::Constant(std::nan(""));

// One sphere's answer from the oracle, in W: its smallest signed distance to the object
// with the nearest points of that pair when apart, its signed distance to every
// primitive by id (one entry, Contact::NONE, for a lone primitive), and one entry per
// primitive it collides with: the primitive's id, the depth, and the unit normal from
// the sphere into the primitive (zero when the oracle has none).
struct SphereAnswer {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0.0;
  double signed_distance = kInf;
  Eigen::Vector3d p_sphere = kUnknown;
  Eigen::Vector3d p_other = kUnknown;
  std::map<intptr_t, double> by_id;
  struct Hit {
    intptr_t id;
    double depth;
    Eigen::Vector3d normal;
  };
  std::vector<Hit> hits;

  const Hit* hit(intptr_t id) const {
    for (const Hit& h : hits)
      if (h.id == id) return &h;
    return nullptr;
  }
};

// Records the answer of one primitive (signed distance sd, with FCL's nearest points when
// apart, or a hit) for sphere a.
void add_primitive(SphereAnswer& a, intptr_t id, double sd, const Eigen::Vector3d& p_sphere,
                   const Eigen::Vector3d& p_other, const Eigen::Vector3d& normal) {
  a.by_id[id] = sd;
  if (sd < a.signed_distance) {
    a.signed_distance = sd;
    a.p_sphere = sd > 0.0 ? p_sphere : kUnknown;
    a.p_other = sd > 0.0 ? p_other : kUnknown;
  }
  if (sd <= 0.0) a.hits.push_back({id, -sd, normal});
}

SphereAnswer sphere_answer(const Sphere& s, const Eigen::Isometry3d& X_WA) {
  SphereAnswer a;
  a.center = X_WA * s.center;
  a.radius = s.radius;
  return a;
}

// --- oracles -----------------------------------------------------------------------------

bool is_flat(const fcl::CollisionGeometryd& g) {
  return g.getNodeType() == fcl::GEOM_PLANE || g.getNodeType() == fcl::GEOM_HALFSPACE;
}

// FCL's fcl::Sphere narrowphase for each sphere against a lone primitive.
std::vector<SphereAnswer> primitive_answers(const SphereSet& set, const fcl::Transform3d& X_WA,
                                            const fcl::CollisionGeometryd& shape,
                                            const fcl::Transform3d& X_WB) {
  const fcl::NODE_TYPE t = shape.getNodeType();
  std::vector<SphereAnswer> answers;
  for (const Sphere& sphere : set.spheres) {
    SphereAnswer a = sphere_answer(sphere, X_WA);
    const mt::FclAnswer f = mt::fcl_sphere_answer(sphere, X_WA, &shape, X_WB, !is_flat(shape));
    if (f.collides) {
      add_primitive(a, fcl::Contactd::NONE, -f.depth, kUnknown, kUnknown, f.normal);
      // FCL's sphere-box contact position is the documented midpoint: the convention
      // checked below is FCL's own.
      if (t == fcl::GEOM_BOX)
        CHECK((f.pos - mt::documented_contact_position(a.center, a.radius, f.depth, f.normal))
                  .norm() <= 1e-12);
    } else if (is_flat(shape)) {
      // libfcl has no sphere-plane or sphere-halfspace distance: FCL's own
      // signedDistance of the shape, minus the radius, and the foot of the centre.
      const Eigen::Vector3d c = X_WB.inverse() * a.center;
      Eigen::Vector3d n;
      double s;
      if (t == fcl::GEOM_PLANE) {
        const auto& plane = static_cast<const fcl::Planed&>(shape);
        s = plane.signedDistance(c);
        n = plane.n;
      } else {
        const auto& half = static_cast<const fcl::Halfspaced&>(shape);
        s = half.signedDistance(c);
        n = half.n;
      }
      const double side = s >= 0.0 ? 1.0 : -1.0;
      add_primitive(a, fcl::Contactd::NONE, std::abs(s) - sphere.radius,
                    X_WB * (c - side * sphere.radius * n), X_WB * (c - s * n),
                    Eigen::Vector3d::Zero());
    } else {
      add_primitive(a, fcl::Contactd::NONE, f.distance, f.p_sphere, f.p_other,
                    Eigen::Vector3d::Zero());
    }
    answers.push_back(a);
  }
  return answers;
}

// FCL's sphere-triangle core (fcl::detail::Project) over every triangle; the mesh is a
// surface. Normal and nearest points from FCL's closest point.
std::vector<SphereAnswer> mesh_answers(const SphereSet& set, const fcl::Transform3d& X_WA,
                                       const medspheres::TriangleMesh& mesh,
                                       const fcl::Transform3d& X_WB) {
  std::vector<SphereAnswer> answers;
  for (const Sphere& sphere : set.spheres) {
    SphereAnswer a = sphere_answer(sphere, X_WA);
    const Eigen::Vector3d& c = a.center;
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
      const Eigen::Vector3d p = X_WB * mesh.corner(t, 0), q = X_WB * mesh.corner(t, 1),
                            r = X_WB * mesh.corner(t, 2);
      const double sd = mt::fcl_sphere_triangle_signed_distance(c, sphere.radius, p, q, r);
      const Eigen::Vector3d nearest = mt::fcl_closest_point_on_triangle(c, p, q, r);
      const double len = (nearest - c).norm();
      // A centre on the triangle has no well-conditioned direction: leave it unknown.
      const Eigen::Vector3d n =
          len > 1e-9 ? Eigen::Vector3d((nearest - c) / len) : Eigen::Vector3d::Zero();
      add_primitive(a, static_cast<intptr_t>(t), sd, c + sphere.radius * n, nearest, n);
    }
    answers.push_back(a);
  }
  return answers;
}

// An occupied leaf cell of an octree: FCL's query cell id and its cube, in the octree's
// frame.
struct Cell {
  intptr_t id;
  Eigen::Vector3d center;
  double size;
};

// The occupied leaf cells, by octomap's own leaf iteration and FCL's occupancy rule; each
// id is checked against fcl::OcTree::getNodeByQueryCellId, which finds the cell again.
std::vector<Cell> occupied_cells(const octomap::OcTree& tree, const fcl::OcTreed& octree) {
  std::vector<Cell> cells;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!octree.isNodeOccupied(&*it)) continue;
    Cell cell{static_cast<intptr_t>(&*it - octree.getRoot()),
              Eigen::Vector3d(it.getX(), it.getY(), it.getZ()), it.getSize()};
    fcl::AABBd box;
    CHECK(octree.getNodeByQueryCellId(cell.id, cell.center, &box) == &*it);
    CHECK(box.min_ == (cell.center.array() - 0.5 * cell.size).matrix());
    CHECK(box.max_ == (cell.center.array() + 0.5 * cell.size).matrix());
    cells.push_back(cell);
  }
  CHECK(cells.size() == octree.toBoxes().size());
  return cells;
}

// FCL's sphere-box narrowphase against every occupied cell.
std::vector<SphereAnswer> octree_answers(const SphereSet& set, const fcl::Transform3d& X_WA,
                                         const std::vector<Cell>& cells,
                                         const fcl::Transform3d& X_WB) {
  std::vector<SphereAnswer> answers;
  for (const Sphere& sphere : set.spheres) {
    SphereAnswer a = sphere_answer(sphere, X_WA);
    for (const Cell& cell : cells) {
      const fcl::Boxd box(cell.size, cell.size, cell.size);
      fcl::Transform3d X_WC = X_WB;
      X_WC.translation() = X_WB * cell.center;
      const mt::FclAnswer f = mt::fcl_sphere_answer(sphere, X_WA, &box, X_WC);
      if (f.collides)
        CHECK((f.pos - mt::documented_contact_position(a.center, a.radius, f.depth, f.normal))
                  .norm() <= 1e-12);
      add_primitive(a, cell.id, f.signed_distance(), f.p_sphere, f.p_other, f.normal);
    }
    answers.push_back(a);
  }
  return answers;
}

double min_signed_distance(const std::vector<SphereAnswer>& answers) {
  double out = kInf;
  for (const SphereAnswer& a : answers) out = std::min(out, a.signed_distance);
  return out;
}

// --- checks ------------------------------------------------------------------------------

// The reported pair (sphere s, primitive id) with value d and nearest points p_sphere and
// p_other: the pair exists with that signed distance, and the points are its witness
// points: when apart FCL's nearest points, when overlapping the two deepest points
// c + r n and c + (r - depth) n.
void check_pair(const std::vector<SphereAnswer>& answers, intptr_t s, intptr_t id, double d,
                const Eigen::Vector3d& p_sphere, const Eigen::Vector3d& p_other, double tol,
                double point_tol) {
  REQUIRE(s >= 0);
  REQUIRE(static_cast<std::size_t>(s) < answers.size());
  const SphereAnswer& a = answers[static_cast<std::size_t>(s)];
  const auto it = a.by_id.find(id);
  REQUIRE(it != a.by_id.end());
  CHECK(it->second == Approx(d).margin(tol));
  if (it->second > 0.0) {
    // The sphere's nearest primitive (or one at the same distance, with the same points).
    if (a.p_sphere.allFinite() && a.signed_distance == Approx(d).margin(tol)) {
      CHECK((p_sphere - a.p_sphere).norm() <= point_tol);
      CHECK((p_other - a.p_other).norm() <= point_tol);
    }
  } else if (const SphereAnswer::Hit* h = a.hit(id)) {
    if (h->normal.norm() > 0.5) {
      CHECK((p_sphere - (a.center + a.radius * h->normal)).norm() <= point_tol);
      CHECK((p_other - (a.center + (a.radius - h->depth) * h->normal)).norm() <= point_tol);
    }
  }
}

// Runs medspheres::fcl in both orders against the per-sphere oracle answers.
// tol bounds differences of distances and depths; point_tol those of points (GJK's
// points are accurate to about the square root of its distance tolerance across the
// surface).
void check_against(const std::shared_ptr<SphereSetGeometry>& g, const fcl::Transform3d& X_WA,
                   const fcl::CollisionGeometryd* other, const fcl::Transform3d& X_WB, double tol,
                   double point_tol, const std::vector<SphereAnswer>& answers, int& separated,
                   int& colliding) {
  const double min_signed = min_signed_distance(answers);
  std::size_t hits = 0;
  for (const SphereAnswer& a : answers) hits += a.hits.size();
  for (bool sphere_first : {true, false}) {
    INFO("sphere set first: " << sphere_first);
    const fcl::CollisionGeometryd* o1 = sphere_first ? g.get() : other;
    const fcl::CollisionGeometryd* o2 = sphere_first ? other : g.get();
    const fcl::Transform3d& X1 = sphere_first ? X_WA : X_WB;
    const fcl::Transform3d& X2 = sphere_first ? X_WB : X_WA;
    auto sphere_of = [&](intptr_t b1, intptr_t b2) { return sphere_first ? b1 : b2; };
    auto id_of = [&](intptr_t b1, intptr_t b2) { return sphere_first ? b2 : b1; };

    // Signed distance: the deepest pair, or the nearest.
    fcl::DistanceRequestd sreq(true, true);
    fcl::DistanceResultd sres;
    medspheres::fcl::distance(o1, X1, o2, X2, sreq, sres);
    CHECK(sres.min_distance == Approx(min_signed).margin(tol));
    CHECK(sres.o1 == o1);
    CHECK(sres.o2 == o2);
    const Eigen::Vector3d& sp = sphere_first ? sres.nearest_points[0] : sres.nearest_points[1];
    const Eigen::Vector3d& op = sphere_first ? sres.nearest_points[1] : sres.nearest_points[0];
    check_pair(answers, sphere_of(sres.b1, sres.b2), id_of(sres.b1, sres.b2), sres.min_distance, sp,
               op, tol, point_tol);
    // The witness points differ by the signed distance.
    CHECK((sres.nearest_points[1] - sres.nearest_points[0]).norm() ==
          Approx(std::abs(sres.min_distance)).margin(tol));

    // Unsigned distance: the nearest pair, or the first overlapping pair found.
    fcl::DistanceRequestd ureq(true);
    fcl::DistanceResultd ures;
    medspheres::fcl::distance(o1, X1, o2, X2, ureq, ures);
    CHECK(ures.o1 == o1);
    CHECK(ures.o2 == o2);
    const Eigen::Vector3d& usp = sphere_first ? ures.nearest_points[0] : ures.nearest_points[1];
    const Eigen::Vector3d& uop = sphere_first ? ures.nearest_points[1] : ures.nearest_points[0];
    check_pair(answers, sphere_of(ures.b1, ures.b2), id_of(ures.b1, ures.b2), ures.min_distance,
               usp, uop, tol, point_tol);
    if (hits == 0) {
      CHECK(ures.min_distance == Approx(min_signed).margin(tol));
    } else {
      CHECK(ures.min_distance <= tol);
      CHECK(ures.min_distance >= min_signed - tol);
    }

    // Collision: exactly the oracle's hits, each with its id, depth, normal and the
    // documented position.
    fcl::CollisionRequestd creq(1u << 20, true);
    fcl::CollisionResultd cres;
    medspheres::fcl::collide(o1, X1, o2, X2, creq, cres);
    if (hits == 0) {
      CHECK_FALSE(cres.isCollision());
      if (sphere_first) ++separated;
    } else {
      CHECK(cres.numContacts() == hits);
      std::set<std::pair<intptr_t, intptr_t>> seen;
      for (std::size_t k = 0; k < cres.numContacts(); ++k) {
        const fcl::Contactd& c = cres.getContact(k);
        CHECK(c.o1 == o1);
        CHECK(c.o2 == o2);
        const intptr_t s = sphere_of(c.b1, c.b2);
        const intptr_t id = id_of(c.b1, c.b2);
        INFO("sphere " << s << " primitive " << id);
        REQUIRE(s >= 0);
        REQUIRE(static_cast<std::size_t>(s) < answers.size());
        CHECK(seen.insert({s, id}).second);
        const SphereAnswer& a = answers[static_cast<std::size_t>(s)];
        const SphereAnswer::Hit* hit = a.hit(id);
        REQUIRE(hit != nullptr);
        CHECK(c.penetration_depth == Approx(hit->depth).margin(tol));
        CHECK(c.normal.norm() == Approx(1.0));
        // FCL's normal runs from the sphere to the other object; a contact's from o1 to o2.
        const Eigen::Vector3d n = sphere_first ? c.normal : Eigen::Vector3d(-c.normal);
        if (hit->normal.norm() > 0.5) {
          CHECK((hit->normal - n).norm() <= 1e-6);
          CHECK(
              (c.pos - mt::documented_contact_position(a.center, a.radius, hit->depth, hit->normal))
                  .norm() <= point_tol);
        }
      }
      if (sphere_first) ++colliding;
    }
  }
}

std::shared_ptr<fcl::Convexd> tetrahedron() {
  auto verts = std::make_shared<std::vector<Eigen::Vector3d>>(std::vector<Eigen::Vector3d>{
      {-0.9, -0.7, -0.5}, {0.9, -0.7, -0.5}, {0.0, 1.0, -0.5}, {0.0, 0.0, 1.1}});
  auto faces = std::make_shared<std::vector<int>>(
      std::vector<int>{3, 0, 2, 1, 3, 0, 1, 3, 3, 1, 2, 3, 3, 2, 0, 3});
  return std::make_shared<fcl::Convexd>(verts, 4, faces, true);
}

// Seeded scenes for check_against: `count` random sets of 1 to max_spheres spheres
// (mt::random_sphere_set with spread, r_min, r_max) posed within pose_a of the origin,
// against the target posed within pose_b.
struct Scenes {
  int count;
  unsigned max_spheres;
  double spread, r_min, r_max, pose_a, pose_b;
};

// Runs check_against on every scene, the oracle's answers from answers_for(set, X_WA,
// X_WB), and checks that the scenes had both outcomes (more than 2 of each).
template <class Answers>
void check_scenes(std::mt19937& rng, const fcl::CollisionGeometryd* target, const Scenes& sc,
                  double tol, double point_tol, Answers&& answers_for) {
  int separated = 0, colliding = 0;
  for (int k = 0; k < sc.count; ++k) {
    const SphereSet set =
        mt::random_sphere_set(rng, 1 + rng() % sc.max_spheres, sc.spread, sc.r_min, sc.r_max);
    auto g = std::make_shared<SphereSetGeometry>(set);
    const fcl::Transform3d X_WA = mt::random_pose(rng, sc.pose_a);
    const fcl::Transform3d X_WB = mt::random_pose(rng, sc.pose_b);
    check_against(g, X_WA, target, X_WB, tol, point_tol, answers_for(set, X_WA, X_WB), separated,
                  colliding);
  }
  CHECK(separated > 2);
  CHECK(colliding > 2);
}

// A random octree of cells of side 0.125 (some free), with FCL's view of it.
struct RandomOctree {
  std::shared_ptr<octomap::OcTree> tree;
  std::shared_ptr<fcl::OcTreed> octree;
  std::vector<Cell> cells;
};

RandomOctree random_octree(std::mt19937& rng) {
  RandomOctree out;
  out.tree = std::make_shared<octomap::OcTree>(0.125);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 400; ++k) {
    const octomap::point3d p(static_cast<float>(u(rng)), static_cast<float>(u(rng)),
                             static_cast<float>(0.3 * u(rng)));
    out.tree->updateNode(p, k % 5 != 0);  // some free cells
  }
  out.tree->updateInnerOccupancy();
  out.octree = std::make_shared<fcl::OcTreed>(out.tree);
  out.cells = occupied_cells(*out.tree, *out.octree);
  return out;
}

fcl::Transform3d translation(double x, double y, double z) {
  fcl::Transform3d X = fcl::Transform3d::Identity();
  X.translation() = Eigen::Vector3d(x, y, z);
  return X;
}

}  // namespace

TEST_CASE("Sphere set against every FCL primitive matches FCL's sphere narrowphase",
          "[fcl][primitives]") {
  struct Named {
    const char* name;
    std::shared_ptr<fcl::CollisionGeometryd> g;
  };
  const std::vector<Named> shapes = {
      {"box", std::make_shared<fcl::Boxd>(0.8, 0.5, 1.1)},
      {"sphere", std::make_shared<fcl::Sphered>(0.6)},
      {"ellipsoid", std::make_shared<fcl::Ellipsoidd>(0.5, 0.3, 0.7)},
      {"capsule", std::make_shared<fcl::Capsuled>(0.3, 0.9)},
      {"cone", std::make_shared<fcl::Coned>(0.7, 1.4)},
      {"cylinder", std::make_shared<fcl::Cylinderd>(0.4, 0.8)},
      {"convex", tetrahedron()},
      {"plane", std::make_shared<fcl::Planed>(Eigen::Vector3d(0.3, -0.2, 1.0).normalized(), 0.1)},
      {"halfspace",
       std::make_shared<fcl::Halfspaced>(Eigen::Vector3d(-0.5, 0.2, 1.0).normalized(), -0.2)},
  };
  std::mt19937 rng(21);
  for (const Named& shape : shapes) {
    INFO(shape.name);
    // Shapes answered by libccd's GJK carry its accuracy: its distances change by up to
    // about 1e-4 between two frames of the same configuration (the oracle works in W,
    // the adapter in the shape's frame).
    const fcl::NODE_TYPE t = shape.g->getNodeType();
    const bool gjk = t == fcl::GEOM_ELLIPSOID || t == fcl::GEOM_CONE || t == fcl::GEOM_CONVEX;
    const double tol = gjk ? 1e-4 : 1e-9;
    check_scenes(
        rng, shape.g.get(), {24, 25, 0.5, 0.05, 0.25, 1.0, 1.0}, tol, gjk ? 5e-3 : 1e-9,
        [&](const SphereSet& set, const fcl::Transform3d& X_WA, const fcl::Transform3d& X_WB) {
          return primitive_answers(set, X_WA, *shape.g, X_WB);
        });
  }
}

TEST_CASE("Sphere set against BVHModels of every BV type matches sphere x triangle", "[fcl][bvh]") {
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(9, 13, 1.0);
  const std::vector<std::shared_ptr<fcl::CollisionGeometryd>> models = {
      mt::make_bvh<fcl::AABBd>(mesh),     mt::make_bvh<fcl::OBBd>(mesh),
      mt::make_bvh<fcl::RSSd>(mesh),      mt::make_bvh<fcl::kIOSd>(mesh),
      mt::make_bvh<fcl::OBBRSSd>(mesh),   mt::make_bvh<fcl::KDOPd<16>>(mesh),
      mt::make_bvh<fcl::KDOPd<18>>(mesh), mt::make_bvh<fcl::KDOPd<24>>(mesh),
  };
  std::mt19937 rng(22);
  for (const auto& model : models) {
    INFO("node type " << model->getNodeType());
    check_scenes(rng, model.get(), {16, 40, 0.6, 0.05, 0.3, 1.4, 1.4}, 1e-9, 1e-9,
                 [&](const SphereSet& set, const fcl::Transform3d& X_WA,
                     const fcl::Transform3d& X_WB) { return mesh_answers(set, X_WA, mesh, X_WB); });
  }
}

TEST_CASE("Sphere set against an octree matches its occupied cells, ids included",
          "[fcl][octree]") {
  std::mt19937 rng(23);
  const RandomOctree o = random_octree(rng);
  REQUIRE(o.cells.size() > 50);
  check_scenes(
      rng, o.octree.get(), {20, 20, 0.4, 0.03, 0.15, 1.2, 0.3}, 1e-9, 1e-9,
      [&](const SphereSet& set, const fcl::Transform3d& X_WA, const fcl::Transform3d& X_WB) {
        return octree_answers(set, X_WA, o.cells, X_WB);
      });
}

TEST_CASE("Touching a primitive, a mesh or an octree cell is a collision, exactly",
          "[fcl][touching]") {
  // Dyadic coordinates and axis-permuting rotations keep every value exact: the sphere
  // of radius 1/2 at the origin touches each object at p_WT = (1/2, y, z), normal +x.
  struct Touch {
    const char* name;
    std::shared_ptr<fcl::CollisionGeometryd> g;
    fcl::Transform3d X_WB;
    Eigen::Vector3d center;  // of the sphere, in W
    intptr_t id;             // of the primitive touched
  };
  fcl::Transform3d R_z = fcl::Transform3d::Identity();  // 90 degrees about z
  R_z.linear() << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  fcl::Transform3d R_y = fcl::Transform3d::Identity();  // 90 degrees about y
  R_y.linear() << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  std::vector<Touch> touches = {
      // Box sides (1, 2, 4) turned about z: its face -y in B is the face x = 1/2 in W.
      {"box", std::make_shared<fcl::Boxd>(1, 2, 4), translation(1.5, 0, 0) * R_z,
       Eigen::Vector3d::Zero(), fcl::Contactd::NONE},
      {"sphere", std::make_shared<fcl::Sphered>(0.5), translation(1, 0, 0), Eigen::Vector3d::Zero(),
       fcl::Contactd::NONE},
      {"capsule", std::make_shared<fcl::Capsuled>(0.25, 2), translation(0.75, 0, 0),
       Eigen::Vector3d::Zero(), fcl::Contactd::NONE},
      // Axis along x in W: the flat end face x = 1/2.
      {"cylinder", std::make_shared<fcl::Cylinderd>(0.5, 2), translation(1.5, 0, 0) * R_y,
       Eigen::Vector3d::Zero(), fcl::Contactd::NONE},
      {"plane", std::make_shared<fcl::Planed>(Eigen::Vector3d(1, 0, 0), 0.5),
       fcl::Transform3d::Identity(), Eigen::Vector3d::Zero(), fcl::Contactd::NONE},
      // The solid {x >= 1/2}.
      {"halfspace", std::make_shared<fcl::Halfspaced>(Eigen::Vector3d(-1, 0, 0), -0.5),
       fcl::Transform3d::Identity(), Eigen::Vector3d::Zero(), fcl::Contactd::NONE},
  };
  // A square in the plane x = 1/2, two triangles; the sphere touches triangle 0 inside.
  medspheres::TriangleMesh square;
  square.vertices = {{0.5, -1, -1}, {0.5, 1, -1}, {0.5, 1, 1}, {0.5, -1, 1}};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  const Eigen::Vector3d on_triangle(0, 0.5, -0.25);
  for (const auto& model : std::vector<std::shared_ptr<fcl::CollisionGeometryd>>{
           mt::make_bvh<fcl::AABBd>(square), mt::make_bvh<fcl::OBBd>(square),
           mt::make_bvh<fcl::RSSd>(square), mt::make_bvh<fcl::kIOSd>(square),
           mt::make_bvh<fcl::OBBRSSd>(square), mt::make_bvh<fcl::KDOPd<16>>(square),
           mt::make_bvh<fcl::KDOPd<18>>(square), mt::make_bvh<fcl::KDOPd<24>>(square)})
    touches.push_back({"BVHModel", model, fcl::Transform3d::Identity(), on_triangle, 0});
  // One occupied octree cell, [1/2, 1] x [0, 1/2] x [0, 1/2].
  auto tree = std::make_shared<octomap::OcTree>(0.5);
  tree->updateNode(octomap::point3d(0.75f, 0.25f, 0.25f), true);
  tree->updateInnerOccupancy();
  auto octree = std::make_shared<fcl::OcTreed>(tree);
  const std::vector<Cell> cells = occupied_cells(*tree, *octree);
  REQUIRE(cells.size() == 1);
  REQUIRE(cells[0].center == Eigen::Vector3d(0.75, 0.25, 0.25));
  touches.push_back({"octree", octree, fcl::Transform3d::Identity(), Eigen::Vector3d(0, 0.25, 0.25),
                     cells[0].id});

  for (const Touch& t : touches) {
    INFO(t.name << " node type " << t.g->getNodeType());
    SphereSet set;
    set.spheres.push_back({Eigen::Vector3d(-4, 0, 0), 0.25});  // far from everything
    set.spheres.push_back({t.center, 0.5});
    auto g = std::make_shared<SphereSetGeometry>(set);
    const Eigen::Vector3d p_WT(0.5, t.center.y(), t.center.z());
    const fcl::Transform3d I = fcl::Transform3d::Identity();
    for (bool sphere_first : {true, false}) {
      INFO("sphere set first: " << sphere_first);
      const fcl::CollisionGeometryd* o1 = sphere_first ? g.get() : t.g.get();
      const fcl::CollisionGeometryd* o2 = sphere_first ? t.g.get() : g.get();
      const fcl::Transform3d& X1 = sphere_first ? I : t.X_WB;
      const fcl::Transform3d& X2 = sphere_first ? t.X_WB : I;
      const intptr_t b1 = sphere_first ? 1 : t.id, b2 = sphere_first ? t.id : 1;
      const Eigen::Vector3d n_12(sphere_first ? 1.0 : -1.0, 0, 0);
      fcl::CollisionRequestd creq(8, true);
      fcl::CollisionResultd cres;
      CHECK(medspheres::fcl::collide(o1, X1, o2, X2, creq, cres) == 1);
      for (std::size_t k = 0; k < cres.numContacts(); ++k) {
        const fcl::Contactd& c = cres.getContact(k);
        CHECK(c.b1 == b1);
        CHECK(c.b2 == b2);
        CHECK(c.penetration_depth == 0.0);
        CHECK((c.normal - n_12).norm() <= 4 * kEps);
        CHECK((c.pos - p_WT).norm() <= 4 * kEps);
      }
      for (bool is_signed : {false, true}) {
        fcl::DistanceRequestd dreq(true, is_signed);
        fcl::DistanceResultd dres;
        CHECK(medspheres::fcl::distance(o1, X1, o2, X2, dreq, dres) == 0.0);
        CHECK(dres.b1 == b1);
        CHECK(dres.b2 == b2);
        CHECK((dres.nearest_points[0] - p_WT).norm() <= 4 * kEps);
        CHECK((dres.nearest_points[1] - p_WT).norm() <= 4 * kEps);
      }
      // Apart by 2^-30: no collision, and that distance.
      const double gap = std::ldexp(1.0, -30);
      const fcl::Transform3d X_WA_apart = translation(-gap, 0, 0);
      fcl::CollisionResultd apart;
      CHECK(medspheres::fcl::collide(o1, sphere_first ? X_WA_apart : X1, o2,
                                     sphere_first ? X2 : X_WA_apart, creq, apart) == 0);
      fcl::DistanceRequestd dreq;
      fcl::DistanceResultd dres;
      CHECK(medspheres::fcl::distance(o1, sphere_first ? X_WA_apart : X1, o2,
                                      sphere_first ? X2 : X_WA_apart, dreq,
                                      dres) == Approx(gap).margin(4 * kEps));
    }
  }
}

TEST_CASE("abs_err and rel_err reach the sphere tree against every target kind",
          "[fcl][tolerance]") {
  // Over seeded scenes apart: with both tolerances binding some answers exceed the exact
  // minimum d*, every answer keeps d* <= d <= min(d* + abs_err, (1 + rel_err) d*) and is
  // the value of the pair it reports; one tolerance alone leaves the answer exact (FCL's
  // rule then prunes as with none).
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(9, 13, 1.0);
  std::mt19937 rng(24);
  const RandomOctree octree = random_octree(rng);
  struct Target {
    const char* name;
    std::shared_ptr<fcl::CollisionGeometryd> g;
  };
  const std::vector<Target> targets = {
      {"BVHModel<OBBRSS>", mt::make_bvh<fcl::OBBRSSd>(mesh)},
      {"BVHModel<AABB>", mt::make_bvh<fcl::AABBd>(mesh)},
      {"box", std::make_shared<fcl::Boxd>(0.8, 0.5, 1.1)},
      {"capsule", std::make_shared<fcl::Capsuled>(0.3, 0.9)},
      {"octree", octree.octree},
  };
  const std::vector<mt::ToleranceMode>& modes = mt::kToleranceModes;
  for (const Target& target : targets) {
    INFO(target.name);
    mt::ToleranceTally tally;
    for (int k = 0; k < 30; ++k) {
      const SphereSet set = (k % 2) ? mt::random_sheet_set(rng, 20 + rng() % 100)
                                    : mt::random_sphere_set(rng, 20 + rng() % 100, 0.6, 0.02, 0.1);
      auto g = std::make_shared<SphereSetGeometry>(set);
      const fcl::Transform3d X_WA = mt::random_pose(rng, 2.5);
      const fcl::Transform3d X_WB = mt::random_pose(rng, 0.5);
      const std::vector<SphereAnswer> answers = target.g->getObjectType() == fcl::OT_BVH
                                                    ? mesh_answers(set, X_WA, mesh, X_WB)
                                                : target.g->getObjectType() == fcl::OT_OCTREE
                                                    ? octree_answers(set, X_WA, octree.cells, X_WB)
                                                    : primitive_answers(set, X_WA, *target.g, X_WB);
      const double exact = min_signed_distance(answers);
      if (exact <= 1e-6) continue;
      tally.add_scene();
      for (std::size_t m = 0; m < modes.size(); ++m) {
        INFO(modes[m].name);
        for (bool sphere_first : {true, false}) {
          const double abs_err = modes[m].abs_err_for(exact);
          fcl::DistanceRequestd req(true, false, modes[m].rel_err, abs_err);
          fcl::DistanceResultd res;
          const double d =
              sphere_first
                  ? medspheres::fcl::distance(g.get(), X_WA, target.g.get(), X_WB, req, res)
                  : medspheres::fcl::distance(target.g.get(), X_WB, g.get(), X_WA, req, res);
          const double tol = 1e-9;
          tally.check(m, d, exact, abs_err, tol, sphere_first);
          const intptr_t s = sphere_first ? res.b1 : res.b2;
          const intptr_t id = sphere_first ? res.b2 : res.b1;
          REQUIRE(s >= 0);
          const auto& by_id = answers[static_cast<std::size_t>(s)].by_id;
          REQUIRE(by_id.count(id) == 1);
          CHECK(by_id.at(id) == Approx(d).margin(tol));
        }
      }
    }
    tally.check_totals(10);
  }
}

TEST_CASE("Many threads query a sphere set against every target kind", "[fcl][threads]") {
  // Every target kind, queried from many threads at once, answers exactly as serially.
  std::mt19937 rng(25);
  const medspheres::TriangleMesh mesh = mt::bumpy_sphere(9, 13, 1.0);
  const RandomOctree octree = random_octree(rng);
  const std::vector<std::shared_ptr<fcl::CollisionGeometryd>> targets = {
      std::make_shared<SphereSetGeometry>(mt::random_sheet_set(rng, 80)),
      std::make_shared<fcl::Boxd>(0.8, 0.5, 1.1),
      std::make_shared<fcl::Sphered>(0.6),
      std::make_shared<fcl::Ellipsoidd>(0.5, 0.3, 0.7),
      std::make_shared<fcl::Capsuled>(0.3, 0.9),
      std::make_shared<fcl::Coned>(0.7, 1.4),
      std::make_shared<fcl::Cylinderd>(0.4, 0.8),
      tetrahedron(),
      std::make_shared<fcl::Planed>(Eigen::Vector3d(0.3, -0.2, 1.0).normalized(), 0.1),
      std::make_shared<fcl::Halfspaced>(Eigen::Vector3d(-0.5, 0.2, 1.0).normalized(), -0.2),
      mt::make_bvh<fcl::OBBRSSd>(mesh),
      mt::make_bvh<fcl::RSSd>(mesh),
      mt::make_bvh<fcl::AABBd>(mesh),
      octree.octree,
  };
  auto spheres =
      std::make_shared<SphereSetGeometry>(mt::random_sphere_set(rng, 60, 0.6, 0.03, 0.15));
  struct Task {
    const fcl::CollisionGeometryd* other;
    fcl::Transform3d X_WA, X_WB;
    bool sphere_first;
  };
  std::vector<Task> tasks;
  for (const auto& t : targets)
    for (int k = 0; k < 6; ++k)
      tasks.push_back({t.get(), mt::random_pose(rng, 1.2), mt::random_pose(rng, 0.5), k % 2 == 0});
  // Everything a task returns, compared exactly.
  using Contact =
      std::tuple<intptr_t, intptr_t, double, double, double, double, double, double, double>;
  struct Answer {
    std::vector<double> distances;  // value, nearest points, per distance query
    std::vector<intptr_t> ids;
    std::vector<Contact> contacts;
    bool operator==(const Answer& o) const {
      return distances == o.distances && ids == o.ids && contacts == o.contacts;
    }
  };
  auto run = [&](const Task& t) {
    Answer a;
    const fcl::CollisionGeometryd* o1 = t.sphere_first ? spheres.get() : t.other;
    const fcl::CollisionGeometryd* o2 = t.sphere_first ? t.other : spheres.get();
    const fcl::Transform3d& X1 = t.sphere_first ? t.X_WA : t.X_WB;
    const fcl::Transform3d& X2 = t.sphere_first ? t.X_WB : t.X_WA;
    for (bool is_signed : {false, true}) {
      fcl::DistanceRequestd req(true, is_signed);
      fcl::DistanceResultd res;
      a.distances.push_back(medspheres::fcl::distance(o1, X1, o2, X2, req, res));
      for (const Eigen::Vector3d& p : res.nearest_points)
        a.distances.insert(a.distances.end(), p.data(), p.data() + 3);
      a.ids.push_back(res.b1);
      a.ids.push_back(res.b2);
    }
    fcl::CollisionRequestd creq(64, true);
    fcl::CollisionResultd cres;
    medspheres::fcl::collide(o1, X1, o2, X2, creq, cres);
    for (std::size_t k = 0; k < cres.numContacts(); ++k) {
      const fcl::Contactd& c = cres.getContact(k);
      a.contacts.emplace_back(c.b1, c.b2, c.penetration_depth, c.normal.x(), c.normal.y(),
                              c.normal.z(), c.pos.x(), c.pos.y(), c.pos.z());
    }
    return a;
  };
  std::vector<Answer> expected;
  std::size_t colliding = 0;
  for (const Task& t : tasks) {
    expected.push_back(run(t));
    colliding += expected.back().contacts.empty() ? 0 : 1;
  }
  CHECK(colliding > tasks.size() / 5);
  CHECK(colliding < tasks.size());
  constexpr int kThreads = 8;
  std::vector<int> mismatches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int th = 0; th < kThreads; ++th) {
    threads.emplace_back([&, th] {
      for (std::size_t k = 0; k < tasks.size(); ++k) {
        const std::size_t i = (k + 11 * static_cast<std::size_t>(th)) % tasks.size();
        if (!(run(tasks[i]) == expected[i])) ++mismatches[static_cast<std::size_t>(th)];
      }
    });
  }
  for (std::thread& th : threads) th.join();
  for (int m : mismatches) CHECK(m == 0);
}
