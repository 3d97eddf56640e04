#include "scene_element.h"

#include <algorithm>
#include <cmath>

namespace medspheres::check::detail {
namespace {

double sq(double x) {
  return x * x;
}

// Squared distance from p to the axis-aligned box of centre c and half sides h.
double box_distance_sq(const Eigen::Vector3d& local, const Eigen::Vector3d& h) {
  double s = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::abs(local[k]) - h[k];
    if (d > 0.0) s += d * d;
  }
  return s;
}

Element make(ElementKind kind, std::uint32_t object) {
  Element e;
  e.kind = kind;
  e.object = object;
  return e;
}

void add_primitive(const SceneObject& o, std::uint32_t id, std::vector<Element>& out) {
  const Eigen::Vector3d c = o.X_WO.translation();
  const Eigen::Matrix3d R = o.X_WO.linear();
  Element e = make(ElementKind::sphere, id);
  switch (o.kind) {
    case ShapeKind::sphere:
      e.a = c;
      e.radius = o.radius;
      e.box = Eigen::AlignedBox3d(c.array() - o.radius, c.array() + o.radius);
      break;
    case ShapeKind::box: {
      e.kind = ElementKind::box;
      e.a = c;
      e.b = o.size / 2;
      e.R = R;
      const Eigen::Vector3d ext = R.cwiseAbs() * e.b;
      e.box = Eigen::AlignedBox3d(c - ext, c + ext);
      break;
    }
    case ShapeKind::capsule: {
      e.kind = ElementKind::capsule;
      const Eigen::Vector3d half = R.col(2) * (o.length / 2);
      e.a = c - half;
      e.b = 2 * half;
      e.length2 = e.b.squaredNorm();
      e.radius = o.radius;
      e.box = Eigen::AlignedBox3d(c - half.cwiseAbs(), c + half.cwiseAbs());
      e.box.min().array() -= o.radius;
      e.box.max().array() += o.radius;
      break;
    }
    case ShapeKind::cylinder: {
      e.kind = ElementKind::cylinder;
      e.a = c;
      e.b = R.col(2);
      e.length2 = o.length / 2;
      e.cylinder_radius = o.radius;
      // Bounds of the two end discs: per axis half-length |u_k| + radius sqrt(1 - u_k^2).
      Eigen::Vector3d ext;
      for (int k = 0; k < 3; ++k)
        ext[k] = e.length2 * std::abs(e.b[k]) + o.radius * std::sqrt(std::max(0.0, 1 - sq(e.b[k])));
      e.box = Eigen::AlignedBox3d(c - ext, c + ext);
      break;
    }
    default:
      return;
  }
  out.push_back(e);
}

void add_mesh(const SceneObject& o, std::uint32_t id, std::vector<Element>& out) {
  std::vector<Eigen::Vector3d> v;
  v.reserve(o.mesh.vertices.size());
  for (const Eigen::Vector3d& p : o.mesh.vertices) v.push_back(o.X_WO * p);
  for (const auto& t : o.mesh.triangles) {
    Element e = make(ElementKind::triangle, id);
    const auto& a = v[static_cast<std::size_t>(t[0])];
    const auto& b = v[static_cast<std::size_t>(t[1])];
    const auto& c = v[static_cast<std::size_t>(t[2])];
    const medspheres::detail::PreparedTriangle p = medspheres::detail::prepare_triangle(a, b, c);
    e.triangle = p.triangle;
    e.normal = p.plane.normal;
    e.box.extend(a);
    e.box.extend(b);
    e.box.extend(c);
    out.push_back(e);
  }
}

void add_points(const SceneObject& o, std::uint32_t id, std::vector<Element>& out) {
  const bool cells = o.kind == ShapeKind::cells;
  const Eigen::Vector3d h = Eigen::Vector3d::Constant(cells ? o.cell_side / 2 : 0.0);
  for (const Eigen::Vector3d& p : o.points) {
    Element e = make(cells ? ElementKind::cell : ElementKind::point, id);
    e.a = p;
    e.b = h;
    e.box = Eigen::AlignedBox3d(p - h, p + h);
    out.push_back(e);
  }
}

}  // namespace

double core_distance_sq(const Element& e, const Eigen::Vector3d& p) {
  switch (e.kind) {
    case ElementKind::sphere:
    case ElementKind::point:
      return (p - e.a).squaredNorm();
    case ElementKind::cell:
      return box_distance_sq(p - e.a, e.b);
    case ElementKind::box:
      return box_distance_sq(e.R.transpose() * (p - e.a), e.b);
    case ElementKind::capsule: {
      const Eigen::Vector3d ap = p - e.a;
      const double t = e.length2 > 0.0 ? std::clamp(ap.dot(e.b) / e.length2, 0.0, 1.0) : 0.0;
      return (ap - t * e.b).squaredNorm();
    }
    case ElementKind::cylinder: {
      const Eigen::Vector3d ap = p - e.a;
      const double z = ap.dot(e.b);
      const double rho = (ap - z * e.b).norm();  // not sqrt(|ap|^2 - z^2): no cancellation
      const double dr = std::max(rho - e.cylinder_radius, 0.0);
      const double dz = std::max(std::abs(z) - e.length2, 0.0);
      return dr * dr + dz * dz;
    }
    case ElementKind::triangle:
      return (p - medspheres::detail::closest_on_triangle(p, e.triangle, e.normal)).squaredNorm();
  }
  return 0.0;
}

double element_distance(const Element& e, const Eigen::Vector3d& p) {
  return std::max(std::sqrt(core_distance_sq(e, p)) - e.radius, 0.0);
}

// A ball around the element: its box's for primitives and cells, the smallest about the
// centroid for a triangle; rounded up.
void enclose(Element& e) {
  if (e.kind == ElementKind::triangle) {
    const Eigen::Vector3d a = e.triangle.a, b = a + e.triangle.ab, c = a + e.triangle.ac;
    e.ball_centre = (a + b + c) / 3;
    e.ball_radius = std::max(
        {(a - e.ball_centre).norm(), (b - e.ball_centre).norm(), (c - e.ball_centre).norm()});
  } else if (e.kind == ElementKind::sphere || e.kind == ElementKind::point) {
    e.ball_centre = e.a;
    e.ball_radius = e.radius;
  } else {
    e.ball_centre = e.box.center();
    e.ball_radius = (e.box.max() - e.box.min()).norm() / 2;
  }
  e.ball_radius = e.ball_radius * (1 + 1e-12) + 1e-12 * e.ball_centre.cwiseAbs().maxCoeff();
}

std::vector<Element> scene_elements(const Scene& scene) {
  std::vector<Element> out;
  for (std::size_t i = 0; i < scene.size(); ++i) {
    const SceneObject& o = scene.objects()[i];
    const auto id = static_cast<std::uint32_t>(i);
    if (o.kind == ShapeKind::mesh)
      add_mesh(o, id, out);
    else if (o.kind == ShapeKind::points || o.kind == ShapeKind::cells)
      add_points(o, id, out);
    else
      add_primitive(o, id, out);
  }
  for (Element& e : out) enclose(e);
  return out;
}

}  // namespace medspheres::check::detail
