#include "medspheres/formats/sph_file.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "medspheres/error.h"
#include "number_text.h"

namespace medspheres::formats {

namespace {

std::string node_line(const Sphere& s) {
  return exact_numbers({s.center.x(), s.center.y(), s.center.z(), s.radius, 1.0}) + "\n";
}

// The non-blank lines of \p text, each with its line number.
std::vector<std::pair<std::size_t, std::string>> content_lines(const std::string& text) {
  std::vector<std::pair<std::size_t, std::string>> out;
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n)
    if (line.find_first_not_of(" \t\r") != std::string::npos) out.emplace_back(n, line);
  return out;
}

// Whether x is a whole number in [1, 2^53]: checked before any conversion to long, which
// is undefined beyond 2^63 (and above 2^53 a double holds no odd numbers anyway).
bool whole_count(double x) {
  return x >= 1 && x <= 0x1p53 && x == std::floor(x);
}

}  // namespace

std::string sph_text(const std::vector<Sphere>& spheres) {
  SphereSet set;
  set.spheres = spheres;
  validate_sphere_set(set, ".sph");
  if (spheres.empty()) throw InputError(".sph", "no spheres to write");
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Sphere& s : spheres) c += s.center / static_cast<double>(spheres.size());
  double r = 0.0;
  // stableNorm: coordinates beyond 1e154 would overflow a squared norm.
  for (const Sphere& s : spheres) r = std::max(r, (s.center - c).stableNorm() + s.radius);
  const double root = r * (1.0 + 1e-12);
  if (!std::isfinite(root))
    throw InputError(".sph",
                     "the spheres span more than a double holds; no root sphere bounds them");
  std::string out = "2 " + std::to_string(spheres.size()) + "\n";
  out += node_line({c, root});
  for (const Sphere& s : spheres) out += node_line(s);
  return out;
}

std::vector<std::vector<Sphere>> parse_sph_levels(const std::string& text,
                                                  const std::string& source) {
  const auto lines = content_lines(text);
  const auto header = lines.empty() ? std::nullopt : parse_numbers(lines[0].second);
  if (!header || header->size() != 2 || !whole_count((*header)[0]) || !whole_count((*header)[1]))
    throw InputError(source, "the first line is not \"levels degree\" (two whole numbers >= 1)");
  const long levels = static_cast<long>((*header)[0]), degree = static_cast<long>((*header)[1]);
  std::vector<std::vector<Sphere>> out;
  std::size_t next = 1;
  double count = 1;  // nodes on this level: degree^level
  for (long level = 0; level < levels; ++level, count *= static_cast<double>(degree)) {
    if (count > static_cast<double>(lines.size() - next))
      throw InputError(source, "level " + std::to_string(level) + " needs " +
                                   exact_number_text(count) + " node lines; the file has " +
                                   std::to_string(lines.size() - next) + " left");
    SphereSet set;
    for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i, ++next) {
      const auto& [number, line] = lines[next];
      const auto v = parse_numbers(line);
      if (!v || v->size() < 4 || v->size() > 10)
        throw InputError(source, "line " + std::to_string(number) + " (level " +
                                     std::to_string(level) + " node " + std::to_string(i) +
                                     ") is not \"x y z r [occupancy ...]\"");
      if ((*v)[3] <= 0) continue;  // an unused node
      set.spheres.push_back({{(*v)[0], (*v)[1], (*v)[2]}, (*v)[3]});
    }
    try {
      validate_sphere_set(set, source);
    } catch (const InputError& e) {
      throw InputError(source, "level " + std::to_string(level) + ": " + e.problem());
    }
    out.push_back(std::move(set.spheres));
  }
  return out;
}

}  // namespace medspheres::formats
