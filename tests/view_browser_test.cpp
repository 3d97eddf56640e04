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

#include "medspheres/io.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using namespace medspheres;
using medspheres::test::run_command;
using medspheres::test::shell_quote;

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  std::cout << (ok ? "ok:   " : "FAIL: ") << what << "\n";
  failures += ok ? 0 : 1;
}

std::string find_chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    const test::CommandResult r = run_command(std::string("command -v ") + name);
    if (r.exit_code == 0 && !r.out.empty()) return r.out.substr(0, r.out.find('\n'));
  }
  return {};
}

std::string chromium_command(const std::string& chromium, const std::string& args) {
  // Headless with software WebGL (SwiftShader through ANGLE); --no-sandbox because CI runs
  // as root; a virtual time budget lets the page's module scripts run before the dump.
  return "timeout 120 " + shell_quote(chromium) +
         " --headless --no-sandbox --disable-dev-shm-usage --use-angle=swiftshader"
         " --enable-unsafe-swiftshader --use-gl=angle --no-first-run --disable-extensions"
         " --hide-scrollbars --virtual-time-budget=20000 " +
         args;
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
  std::string status;  // the body's data-status
  Counts pixels;
};

// One Chromium run: the DOM after the page ran, and a 640 x 480 screenshot.
PageResult load_page(const std::string& chromium, const std::string& html, const std::string& dir) {
  PageResult out;
  const std::string shot = dir + "/shot.png";
  std::filesystem::remove(shot);
  const test::CommandResult dom = run_command(
      chromium_command(chromium, "--window-size=640,480 --screenshot=" + shell_quote(shot) +
                                     " --dump-dom " + shell_quote("file://" + html)));
  const std::size_t at = dom.out.find("data-status=\"");
  if (at != std::string::npos) {
    const std::size_t from = at + 13;
    out.status = dom.out.substr(from, dom.out.find('"', from) - from);
  } else {
    out.status = "(no status; chromium exit " + std::to_string(dom.exit_code) + ": " +
                 dom.err.substr(0, 400) + ")";
  }
  const Pixels p = read_png(shot);
  check(p.width == 640 && p.height == 480, "the screenshot is a 640x480 PNG");
  out.pixels = count(p);
  return out;
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
  { std::ofstream(dir + "/cube.off") << test::to_off(test::cube_mesh(-0.5, 0.5)); }
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
    const PageResult page = load_page(chromium, html, dir);
    check(page.status.rfind("ok:", 0) == 0 && page.pixels.drawn > page.pixels.total / 200,
          "the mismatched page still draws both (" + page.status + ")");
  }
  std::cout << (failures == 0 ? "all passed\n" : std::to_string(failures) + " failed\n");
  return failures == 0 ? 0 : 1;
}
