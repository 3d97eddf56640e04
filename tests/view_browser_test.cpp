// view in a real browser: `medspheres view` writes a page, headless Chromium (software
// WebGL) loads it from disk, and the test reads back the status the page set in the DOM
// and the screenshot's pixels (libpng). Exit 77 (ctest: skipped) only when no Chromium is
// installed.
//
// Scenes and oracles: a cube with one ball inside it (an inner set: every point of the
// surface lies outside the ball, so certify_cover leaves all of it uncertified and the
// page must draw red over the whole cube), and the same cube with a ball that contains
// it (every triangle certified: no red at all, the blue ball seen through the mesh).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <png.h>
#include <nlohmann/json.hpp>

#include "medspheres/io.h"
#include "medspheres/mesh/mesh_generators.h"
#include "support/chromium.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using namespace medspheres;
using medspheres::test::chromium_command;
using medspheres::test::find_chromium;
using medspheres::test::run_command;
using medspheres::test::shell_quote;

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  std::cout << (ok ? "ok:   " : "FAIL: ") << what << "\n";
  failures += ok ? 0 : 1;
}

struct Pixels {
  int width = 0, height = 0;
  std::vector<png_byte> rgb;
};

Pixels read_png(const std::string& path) {
  Pixels p;
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return p;
  image.format = PNG_FORMAT_RGB;
  p.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, p.rgb.data(), 0, nullptr)) {
    png_image_free(&image);
    return {};
  }
  p.width = int(image.width);
  p.height = int(image.height);
  return p;
}

struct Counts {
  std::size_t total = 0, drawn = 0, red = 0, blue = 0;
};

// The pixels of rows 140 .. 459: below the check boxes' panel (whose colour swatches are
// red and blue) and above the status line.
Counts count(const Pixels& p) {
  Counts c;
  const std::size_t row = std::size_t(3) * p.width;
  for (std::size_t i = 140 * row; i + 2 < std::min(p.rgb.size(), 460 * row); i += 3) {
    const int r = p.rgb[i], g = p.rgb[i + 1], b = p.rgb[i + 2];
    ++c.total;
    c.drawn += r < 245 || g < 245 || b < 245;
    c.red += r > 120 && r > g + 60 && r > b + 60;
    c.blue += b > 120 && b > r + 40 && b > g + 20;
  }
  return c;
}

struct PageResult {
  std::string status;       // the body's data-status
  nlohmann::json geometry;  // the body's data-geometry: what the page decoded
  Counts pixels;
};

// The value of the attribute \p name in the dumped DOM, its entities replaced.
std::string attribute(const std::string& dom, const std::string& name) {
  const std::size_t at = dom.find(name + "=\"");
  if (at == std::string::npos) return {};
  const std::size_t from = at + name.size() + 2;
  std::string v = dom.substr(from, dom.find('"', from) - from);
  for (const auto& [entity, c] : {std::pair<std::string, std::string>{"&quot;", "\""},
                                  {"&lt;", "<"},
                                  {"&gt;", ">"},
                                  {"&amp;", "&"}})
    for (std::size_t k = v.find(entity); k != std::string::npos; k = v.find(entity, k + 1))
      v.replace(k, entity.size(), c);
  return v;
}

// One Chromium run: the DOM after the page ran, and a 640 x 480 screenshot.
PageResult load_page_once(const std::string& chromium, const std::string& html,
                          const std::string& dir) {
  PageResult out;
  const std::string shot = dir + "/shot.png";
  std::filesystem::remove(shot);
  const test::CommandResult dom = run_command(
      chromium_command(chromium, "--window-size=640,480 --screenshot=" + shell_quote(shot) +
                                     " --dump-dom " + shell_quote("file://" + html)));
  out.status = attribute(dom.out, "data-status");
  out.geometry = nlohmann::json::parse(attribute(dom.out, "data-geometry"), nullptr, false);
  if (out.status.empty()) {
    out.status = "(no status; chromium exit " + std::to_string(dom.exit_code) + ": " +
                 dom.err.substr(0, 400) + ")";
  }
  const Pixels p = read_png(shot);
  check(p.width == 640 && p.height == 480, "the screenshot is a 640x480 PNG");
  out.pixels = count(p);
  return out;
}

// Whether a screenshot shows the page's drawing: more than 1/200 of the counted pixels.
bool drew_enough(const Counts& c) {
  return c.drawn > c.total / 200;
}

// The page, loaded again (twice at most) when it reports ok but its screenshot fails
// \p drew (by default, shows almost nothing): on a loaded machine headless Chromium can take
// the screenshot before the first frame that software WebGL draws. Every retry is printed,
// so that a page that draws only sometimes shows in the log, and one that never draws still
// fails.
PageResult load_page(const std::string& chromium, const std::string& html, const std::string& dir,
                     bool (*drew)(const Counts&) = drew_enough) {
  PageResult out = load_page_once(chromium, html, dir);
  for (int retry = 1; retry <= 2; ++retry) {
    if (out.status.rfind("ok:", 0) != 0 || drew(out.pixels)) break;
    std::cout << "      retry " << retry << ": " << html << " drew " << out.pixels.drawn
              << " pixels of " << out.pixels.total << "\n";
    out = load_page_once(chromium, html, dir);
  }
  return out;
}

// The page decoded \p mesh: its vertex and triangle counts; the box and the mean of its
// vertices within the quantization's half step (the box's side / 65535 / 2, view_data.h)
// plus the float32 rounding of a decoded coordinate; its area within what moving every
// vertex by that much can change (|dA| <= d * perimeter per triangle, d the longest move);
// \p uncovered_inner pieces of the inner set.
void check_geometry(const PageResult& page, const TriangleMesh& mesh, std::size_t uncovered_inner,
                    const std::string& what) {
  const nlohmann::json& g = page.geometry;
  if (!g.is_object() || !g.contains("box"))
    return check(false, what + ": the page says what it decoded");
  check(g["vertices"] == mesh.vertices.size() && g["triangles"] == mesh.num_triangles(),
        what + ": " + g["vertices"].dump() + " vertices and " + g["triangles"].dump() +
            " triangles decoded, as written");
  Eigen::AlignedBox3d box;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : mesh.vertices) box.extend(v), mean += v;
  mean /= static_cast<double>(mesh.vertices.size());
  Eigen::Vector3d half_step;
  double worst = 0.0;  // in half steps
  for (int k = 0; k < 3; ++k) {
    const double round = 1.2e-7 * std::max(std::abs(box.min()[k]), std::abs(box.max()[k]));
    half_step[k] = (box.max()[k] - box.min()[k]) / 65535 / 2 + round;
    for (const auto& [decoded, exact] :
         {std::pair{g["box"][k], box.min()[k]}, std::pair{g["box"][k + 3], box.max()[k]},
          std::pair{g["mean"][k], mean[k]}}) {
      worst = std::max(worst, std::abs(decoded.get<double>() - exact) / half_step[k]);
    }
  }
  check(worst <= 1.0, what +
                          ": the decoded box and mean are the mesh's within half a "
                          "quantization step (off by " +
                          std::to_string(worst) + " of it)");
  double area = 0.0, bound = 0.0;
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
    area += 0.5 * (b - a).cross(c - a).norm();
    bound += half_step.norm() * ((b - a).norm() + (c - b).norm() + (a - c).norm());
  }
  check(std::abs(g["area"].get<double>() - area) <= bound,
        what + ": the decoded area " + g["area"].dump() + " is the mesh's " + std::to_string(area) +
            " within " + std::to_string(bound));
  check(
      g["uncovered"]["inner"] == uncovered_inner,
      what + ": " + g["uncovered"]["inner"].dump() + " uncovered pieces of the inner set decoded");
}

void write_set(const std::string& path, const Eigen::Vector3d& c, double r) {
  SphereSet s;
  s.spheres.push_back({c, r});
  save_sphere_set(s, path);
}

}  // namespace

int main() {
  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    std::cout << "SKIP: no chromium on PATH (.ci/install-deps installs it)\n";
    return 77;
  }
  test::TempDir tmp;
  const std::string dir = tmp.path().string();
  const TriangleMesh cube = test::cube_mesh(-0.5, 0.5);
  { std::ofstream(dir + "/cube.off") << test::to_off(cube); }
  write_set(dir + "/inside.json", {0.0, 0.0, 0.0}, 0.4);  // in the cube: nothing covered
  write_set(dir + "/around.json", {0.0, 0.0, 0.0}, 0.9);  // > sqrt(3) / 2: all covered
  write_set(dir + "/far.json", {40.0, 0.0, 0.0}, 0.4);    // a set in another frame

  const std::string cli = shell_quote(MEDSPHERES_CLI);
  for (const std::string set : {"inside", "around"}) {
    const std::string html = dir + "/" + set + ".html";
    const test::CommandResult r =
        run_command(cli + " view " + shell_quote(dir + "/cube.off") + " " +
                    shell_quote(dir + "/" + set + ".json") + " -o " + shell_quote(html));
    check(r.exit_code == 0, "view exits 0 for the " + set + " set (" + r.err + ")");
    const PageResult page = load_page(chromium, html, dir);
    std::cout << "      status: " << page.status << "\n      pixels: " << page.pixels.drawn
              << " drawn, " << page.pixels.red << " red, " << page.pixels.blue << " blue of "
              << page.pixels.total << "\n";
    check(page.status.rfind("ok:", 0) == 0, "the page reports ok for the " + set + " set");
    const std::string counts = ", 1 part, " + std::to_string(cube.num_triangles()) + " triangles,";
    check(page.status.find(counts) != std::string::npos,
          "the status counts the cube's one part and its triangles (" + page.status + ")");
    // Inside: every triangle uncovered, as a whole; around: none.
    check_geometry(page, cube, set == "inside" ? cube.num_triangles() : 0, "the " + set + " page");
    // The cube fills a good part of the window, but not all of it.
    check(
        page.pixels.drawn > page.pixels.total / 20 && page.pixels.drawn < page.pixels.total * 3 / 4,
        "the " + set + " page draws the cube, not a blank or a full window");
    if (set == "inside")
      check(page.pixels.red > page.pixels.drawn / 2, "uncovered surface is red");
    else
      check(page.pixels.red == 0 && page.pixels.blue > page.pixels.drawn / 4,
            "covered surface is not red, and the ball shows through");
  }
  {
    const std::string html = dir + "/far.html";
    const test::CommandResult r =
        run_command(cli + " view " + shell_quote(dir + "/cube.off") + " " +
                    shell_quote(dir + "/far.json") + " -o " + shell_quote(html));
    check(r.exit_code == 0 && r.err.find("warning") != std::string::npos,
          "a set far from its mesh gets a warning, and the page is written");
    // The view frames both, 40 units apart: the cube (uncovered, so red) and the ball
    // (blue) each a dozen pixels or so across, 100 to 200 pixels each. Counted by colour,
    // not by all pixels drawn, which the panel's border and the antialiasing dominate.
    const auto drew_both = [](const Counts& c) { return c.red >= 20 && c.blue >= 20; };
    const PageResult page = load_page(chromium, html, dir, drew_both);
    std::cout << "      pixels: " << page.pixels.drawn << " drawn, " << page.pixels.red << " red, "
              << page.pixels.blue << " blue\n";
    check(page.status.rfind("ok:", 0) == 0 && drew_both(page.pixels),
          "the mismatched page still draws both, the cube red and the ball blue (" + page.status +
              "; " + std::to_string(page.pixels.red) + " red and " +
              std::to_string(page.pixels.blue) + " blue pixels)");
  }
  {
    // More vertices than 16-bit indices hold, none on the quantization's lattice: an
    // icosphere of 163842 vertices, turned, inside a ball that covers it.
    TriangleMesh ball = make_icosphere(1.0, 7);
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    for (Eigen::Vector3d& v : ball.vertices) v = turn * v + Eigen::Vector3d(0.1, -2.0, 30.0);
    { std::ofstream(dir + "/ball.off") << test::to_off(ball); }
    write_set(dir + "/ball.json", {0.1, -2.0, 30.0}, 1.01);
    const std::string html = dir + "/ball.html";
    const test::CommandResult r =
        run_command(cli + " view " + shell_quote(dir + "/ball.off") + " " +
                    shell_quote(dir + "/ball.json") + " -o " + shell_quote(html));
    check(r.exit_code == 0, "view exits 0 for the large ball (" + r.err + ")");
    const PageResult page = load_page(chromium, html, dir);
    std::cout << "      status: " << page.status << "\n";
    check(page.status.rfind("ok:", 0) == 0, "the large ball's page reports ok");
    check_geometry(page, ball, 0, "the large ball's page");
  }
  std::cout << (failures == 0 ? "all passed\n" : std::to_string(failures) + " failed\n");
  return failures == 0 ? 0 : 1;
}
