// render: pictures of known scenes checked by pixel statistics against closed forms, and
// the CLI's bad input.
#include <cmath>
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/io.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/render/bitmap_font.h"
#include "medspheres/render/legend_overlay.h"
#include "medspheres/render/png_write.h"
#include "medspheres/render/render.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::render;
using Catch::Matchers::Contains;

namespace {

const double kPi = std::acos(-1.0);

SphereSet one_sphere(const Eigen::Vector3d& c, double r) {
  SphereSet s;
  s.spheres.push_back({c, r});
  return s;
}

// The pixel side of a single view of \p scene (the framing render() uses).
double pixel_size(const RayScene& scene, View view, int w, int h) {
  return frame_camera(view, scene.mesh_lo().cwiseMin(scene.spheres_lo()),
                      scene.mesh_hi().cwiseMax(scene.spheres_hi()), w, h)
      .pixel;
}

bool is_red(const Rgb& c) {
  return c[0] > 80 && c[0] > 1.5 * c[1] && c[0] > 1.5 * c[2];
}

std::size_t count_pixels(const Image& im, bool (*pred)(const Rgb&)) {
  std::size_t n = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) n += pred(im.at(x, y));
  return n;
}

}  // namespace

TEST_CASE("a sphere's silhouette has the projected circle's area in every view", "[render]") {
  // A box well inside a unit ball: the image outside the background is the ball's disk.
  const RayScene scene(make_box({0.4, 0.4, 0.4}, 3), one_sphere({0.2, -0.1, 0.3}, 1.0));
  for (View view : {View::iso, View::front, View::side, View::top}) {
    RenderOptions o;
    o.view = view;
    o.width = 400;
    o.height = 300;
    const Rendering r = render::render(scene, o);
    const double px = pixel_size(scene, view, o.width, o.height);
    const double expected = kPi / (px * px);  // pi r^2 over a pixel's area, r = 1
    CAPTURE(to_string(view), r.counts.spheres, expected);
    CHECK(std::abs(r.counts.spheres - expected) < 0.02 * expected);
    const Rgb bg = o.palette.background;
    std::size_t not_background = 0;
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x) not_background += r.image.at(x, y) != bg;
    CHECK(not_background == r.counts.spheres);
    for (auto [x, y] :
         {std::pair{0, 0}, {o.width - 1, 0}, {0, o.height - 1}, {o.width - 1, o.height - 1}})
      CHECK(r.image.at(x, y) == bg);
    // The box is inside the ball: nothing uncovered, and no red anywhere.
    CHECK(r.counts.uncovered == 0);
    CHECK(count_pixels(r.image, is_red) == 0);
    CHECK(r.mismatch.empty());
  }
}

TEST_CASE("surface poking out of the sphere is drawn uncovered, with the right area", "[render]") {
  // Box [-1.4, 1.4] x [-0.3, 0.3]^2 through a unit ball at the origin, seen from the front
  // (along +y): its face y = -0.3 is uncovered where x^2 + z^2 > 1 - 0.09.
  const RayScene scene(make_box({1.4, 0.3, 0.3}, 8), one_sphere({0, 0, 0}, 1.0));
  RenderOptions o;
  o.view = View::front;
  o.width = o.height = 600;
  const Rendering r = render::render(scene, o);
  double area = 0.0;  // midpoint rule over z of the two ends' widths
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double z = -0.3 + 0.6 * (i + 0.5) / n;
    area += 2.0 * (1.4 - std::sqrt(0.91 - z * z)) * 0.6 / n;
  }
  const double px = pixel_size(scene, o.view, o.width, o.height);
  const double expected = area / (px * px);
  CAPTURE(r.counts.uncovered, expected);
  CHECK(std::abs(r.counts.uncovered - expected) < 0.03 * expected);
  CHECK(count_pixels(r.image, is_red) >= r.counts.uncovered * 9 / 10);
}

TEST_CASE("caps sticking out of the solid are counted with the circular segment's area",
          "[render]") {
  // A ball of radius 0.5 inside the box [-1, 1]^3 protrudes nowhere; moved to x = 0.9 it
  // sticks out past x = 1 by a circular segment (seen from the front).
  const TriangleMesh box = make_box({1, 1, 1}, 4);
  RenderOptions o;
  o.view = View::front;
  o.width = o.height = 600;
  const Rendering inside = render::render(RayScene(box, one_sphere({0, 0, 0}, 0.5)), o);
  CHECK(inside.counts.spheres > 0);
  CHECK(inside.counts.protruding == 0);
  const RayScene scene(box, one_sphere({0.9, 0, 0}, 0.5));
  const Rendering out = render::render(scene, o);
  const double r = 0.5, d = 0.1;
  const double segment = r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d);
  const double px = pixel_size(scene, o.view, o.width, o.height);
  const double expected = segment / (px * px);
  CAPTURE(out.counts.protruding, expected);
  CHECK(std::abs(out.counts.protruding - expected) < 0.03 * expected);

  // With a tolerance of 0.05 only the points farther than that from the face x = 1 count:
  // the segment beyond x = 1.05.
  o.protrusion_tolerance = 0.05;
  const Rendering tolerant = render::render(scene, o);
  const double d2 = 0.15;
  const double segment2 = r * r * std::acos(d2 / r) - d2 * std::sqrt(r * r - d2 * d2);
  const double expected2 = segment2 / (px * px);
  CAPTURE(tolerant.counts.protruding, expected2);
  CHECK(std::abs(tolerant.counts.protruding - expected2) < 0.03 * expected2);
  CHECK(tolerant.counts.spheres == out.counts.spheres);
}

TEST_CASE("a sphere set far from its mesh is framed with it and warned about", "[render]") {
  const RayScene scene(make_box({1, 1, 1}), one_sphere({50, 0, 0}, 1.0));
  RenderOptions o;
  o.view = View::grid;
  o.width = 400;
  o.height = 400;
  const Rendering r = render::render(scene, o);
  CHECK_THAT(r.mismatch, Contains("does not overlap"));
  CHECK(r.counts.mesh > 0);
  CHECK(r.counts.spheres > 0);
  const std::string png = encode_png(r.image, {{"Description", "x"}});
  CHECK(png.substr(1, 3) == "PNG");
}

TEST_CASE("render on the command line: a PNG, the legend, and bad input", "[render][cli]") {
  using test::run_cli;
  using test::shell_quote;
  test::TempDir dir;
  const std::string mesh = dir.write("box.off", test::to_off(make_box({1.4, 0.3, 0.3}, 4)));
  const std::string spheres = dir.file("s.json");
  save_sphere_set(one_sphere({0, 0, 0}, 1.0), spheres);
  const std::string out = dir.file("out.png");
  const std::string inputs = shell_quote(mesh) + " " + shell_quote(spheres);
  const auto ok = run_cli("render " + inputs + " -o " + shell_quote(out) +
                          " --view grid --size 320x240 --threads 2");
  CHECK(ok.exit_code == 0);
  CHECK_THAT(ok.out, Contains("uncovered surface"));
  const std::string png = test::read_file(out);
  REQUIRE(png.size() > 8);
  CHECK(png.substr(1, 3) == "PNG");
  CHECK(png.find("tEXtDescription") != std::string::npos);

  for (const std::string bad : {"--size 0x10", "--size 640", "--size 10x10x10", "--view back",
                                "--tolerance -1", "--threads -3"}) {
    const std::string target = dir.file("bad.png");
    const auto r = run_cli("render " + inputs + " -o " + shell_quote(target) + " " + bad);
    CAPTURE(bad, r.err);
    CHECK(r.exit_code == 2);
    CHECK(!std::filesystem::exists(target));
  }
  const std::string missing = dir.file("no-such-dir/out.png");
  const auto r = run_cli("render " + inputs + " -o " + shell_quote(missing));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("no-such-dir"));
  CHECK(!std::filesystem::exists(missing));
  CHECK(std::distance(std::filesystem::directory_iterator(dir.path()), {}) == 3);
}

TEST_CASE("the legend's font: lit pixels inside their cells, scale 2 lights four times as many",
          "[render]") {
  const auto lit = [](const Image& im) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < im.rgb.size(); i += 3) n += im.rgb[i] == 0;
    return n;
  };
  const auto blank = [](int w, int h) {
    Image im;
    im.width = w, im.height = h;
    im.rgb.assign(std::size_t(3) * w * h, 255);
    return im;
  };
  const std::string text = "uncovered 12.5 %";
  Image one = blank(200, 40), two = blank(400, 80);
  draw_text(one, 3, 5, text, Rgb{0, 0, 0}, 1);
  draw_text(two, 6, 10, text, Rgb{0, 0, 0}, 2);
  CHECK(lit(one) > 0);
  CHECK(lit(two) == 4 * lit(one));
  for (int y = 0; y < one.height; ++y)
    for (int x = 0; x < one.width; ++x)
      if (one.at(x, y)[0] == 0) {
        CHECK(x >= 3);
        CHECK(x < 3 + kCellWidth * int(text.size()));
        CHECK(y >= 5);
        CHECK(y < 5 + kCellHeight);
      }
  // Different characters are different glyphs.
  Image a = blank(20, 12), b = blank(20, 12);
  draw_text(a, 0, 0, "8", Rgb{0, 0, 0});
  draw_text(b, 0, 0, "0", Rgb{0, 0, 0});
  CHECK(a.rgb != b.rgb);
}

TEST_CASE("render draws the legend into the image's lower left corner", "[render]") {
  const RayScene scene(make_box({0.4, 0.4, 0.4}, 3), one_sphere({0, 0, 0}, 0.3));
  RenderOptions o;
  o.width = 480, o.height = 360;
  Rendering r = render::render(scene, o);
  const Image before = r.image;
  draw_legend(r.image, legend(scene, o, r.counts), "", o.palette);
  std::size_t changed_low = 0, changed_top = 0, dark = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const bool changed = r.image.at(x, y) != before.at(x, y);
      (y > o.height / 2 ? changed_low : changed_top) += changed;
      dark += y > o.height / 2 && r.image.at(x, y)[0] < 60 && r.image.at(x, y)[2] < 60;
    }
  CHECK(changed_top == 0);
  CHECK(changed_low > 0);
  CHECK(dark > 100);  // the text's pixels
}

TEST_CASE("render a robot file at a joint vector: each link's sphere where kinematics puts it",
          "[render][cli]") {
  using test::run_cli;
  using test::shell_quote;
  test::TempDir dir;
  // Two links, one ball of radius 0.5 each at the link's origin; a prismatic joint along x.
  const std::string robot = dir.write("two.robot.json", R"({
    "format": "medspheres.robot", "version": 1, "name": "two", "root_link": "a",
    "links": [{"name": "a", "inner": [[0, 0, 0, 0.5]], "outer": []},
              {"name": "b", "inner": [[0, 0, 0, 0.5]], "outer": []}],
    "joints": [{"name": "slide", "type": "prismatic", "parent": "a", "child": "b",
                "origin": {"xyz": [0, 0, 0], "quaternion_xyzw": [0, 0, 0, 1]},
                "axis": [1, 0, 0], "limits": {"lower": -1, "upper": 5}}],
    "metadata": {}})");
  const auto sphere_pixels = [](const std::string& out) {
    const std::size_t at = out.find(" sphere pixels");
    REQUIRE(at != std::string::npos);
    const std::size_t from = out.rfind("of ", at) + 3;
    return std::stod(out.substr(from, at - from));
  };
  const auto disk_pixels = [](double length_x, int disks) {
    // frame_camera: pixel = 2.1 * half diagonal / 300 of the box [-0.5, length_x - 0.5] x
    // [-0.5, 0.5]^2.
    const double half_diagonal = 0.5 * std::sqrt(length_x * length_x + 2.0);
    const double pixel = 2.1 * half_diagonal / 300.0;
    return disks * kPi * 0.25 / (pixel * pixel);
  };
  const std::string out = dir.file("r.png");
  const std::string base =
      "render " + shell_quote(robot) + " -o " + shell_quote(out) + " --view top --size 400x300 ";
  const auto zero = run_cli(base);
  REQUIRE(zero.exit_code == 0);
  CHECK(sphere_pixels(zero.out) == Approx(disk_pixels(1.0, 1)).epsilon(0.03));
  for (const std::string joints : {"3", "slide=3"}) {
    const auto moved = run_cli(base + "--joints " + joints);
    CAPTURE(joints, moved.err);
    REQUIRE(moved.exit_code == 0);
    CHECK(sphere_pixels(moved.out) == Approx(disk_pixels(4.0, 2)).epsilon(0.03));
    CHECK(moved.err.find("warning") == std::string::npos);
  }
  // Beyond the limits: drawn there, with a warning naming the joint and its limits.
  for (const std::string joints : {"6", "slide=-1.5"}) {
    const auto beyond = run_cli(base + "--joints " + joints);
    CAPTURE(joints, beyond.err);
    REQUIRE(beyond.exit_code == 0);
    CHECK_THAT(beyond.err,
               Contains("--joints: slide = ") && Contains("outside its limits [-1, 5]"));
  }
  for (const std::string bad : {"1,2", "x", "nope=1"}) {
    const auto r = run_cli(base + "--joints " + bad);
    CAPTURE(bad, r.err);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains("--joints"));
  }
}
