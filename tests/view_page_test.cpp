// view: the page's data, decoded against what the scene holds and what certify_cover decides,
// and the CLI's page and bad input. (test_view_browser loads such pages in Chromium.)
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "../src/render/view_data.h"
#include "medspheres/io.h"
#include "medspheres/render/scene.h"
#include "medspheres/render/view_html.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::render;
using Catch::Matchers::Contains;

namespace {

// The JSON of the page's data script (web/viewer.html).
nlohmann::json page_data(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"medspheres-data\">";
  const std::size_t a = page.find(open);
  REQUIRE(a != std::string::npos);
  const std::size_t b = page.find("</script>", a);
  REQUIRE(b != std::string::npos);
  return nlohmann::json::parse(page.substr(a + open.size(), b - a - open.size()));
}

// Little-endian bytes of \p values, written out byte by byte.
template <typename T>
std::string little_endian(const std::vector<T>& values, int bytes_each) {
  std::string out;
  for (T v : values)
    for (int b = 0; b < bytes_each; ++b)
      out += static_cast<char>((static_cast<std::uint64_t>(v) >> (8 * b)) & 0xff);
  return out;
}

std::uint32_t float_bits(float f) {
  std::uint32_t u;
  static_assert(sizeof u == sizeof f, "32-bit floats");
  std::memcpy(&u, &f, sizeof u);
  return u;
}

SphereSet one_ball(double r) {
  SphereSet s;
  s.spheres.push_back({Eigen::Vector3d::Zero(), r});
  return s;
}

}  // namespace

TEST_CASE("view: base64 gives RFC 4648's test vectors", "[render][view]") {
  using detail::base64;
  CHECK(base64("").empty());
  CHECK(base64("f") == "Zg==");
  CHECK(base64("fo") == "Zm8=");
  CHECK(base64("foo") == "Zm9v");
  CHECK(base64("foob") == "Zm9vYg==");
  CHECK(base64("fooba") == "Zm9vYmE=");
  CHECK(base64("foobar") == "Zm9vYmFy");
  CHECK(base64(std::string("\xff\xfe\x00", 3)) == "//4A");
}

TEST_CASE("view: the page carries the scene, red exactly where no ball covers", "[render][view]") {
  using detail::base64;
  const TriangleMesh cube = test::cube_mesh(-0.5, 0.5);
  REQUIRE(cube.num_triangles() == 12);
  // One ball inside the cube covers none of its surface; one of radius 0.9 > sqrt(3) / 2
  // covers all of it.
  for (const double r : {0.4, 0.9}) {
    INFO("radius " << r);
    ViewOptions o;
    o.title = "cube <&>";
    o.threads = 1;
    const std::string page = view_html(mesh_scene(cube, one_ball(r)), o);
    CHECK_THAT(page, Contains("<title>cube &lt;&amp;&gt;</title>"));
    const nlohmann::json data = page_data(page);
    CHECK(data["title"] == o.title);
    REQUIRE(data["parts"].size() == 1);
    const nlohmann::json& part = data["parts"][0];
    CHECK(part["triangle_count"] == 12);
    CHECK(part["vertex_count"] == cube.vertices.size());
    CHECK(part["box"] == std::vector<double>{-0.5, -0.5, -0.5, 0.5, 0.5, 0.5});
    // Each coordinate at a side of the box: 0 or 2^16 - 1.
    std::vector<std::uint16_t> q;
    for (const Eigen::Vector3d& v : cube.vertices)
      for (int k = 0; k < 3; ++k) q.push_back(v[k] < 0.0 ? 0 : 65535);
    CHECK(part["positions"] == base64(little_endian(q, 2)));
    CHECK(part["index_bytes"] == 2);
    std::vector<int> corners;
    for (const auto& t : cube.triangles) corners.insert(corners.end(), t.begin(), t.end());
    CHECK(part["triangles"] == base64(little_endian(corners, 2)));
    const float f = static_cast<float>(r);
    CHECK(part["inner"] ==
          base64(little_endian(std::vector<std::uint32_t>{0, 0, 0, float_bits(f)}, 4)));
    CHECK(part["outer"] == "");
    // A bit per triangle, each whole triangle uncovered or none.
    const std::string bits = r < 0.5 ? std::string("\xff\x0f", 2) : std::string(2, '\0');
    CHECK(part["uncovered_inner"]["whole"] == base64(bits));
    CHECK(part["uncovered_inner"]["pieces"] == "");
    CHECK(part["uncovered_outer"]["whole"] == base64(std::string(2, '\0')));
  }
  ViewOptions deep;
  deep.cover_depth = 11;
  CHECK_THROWS_AS(view_html(mesh_scene(cube, one_ball(0.4)), deep), std::invalid_argument);
}

TEST_CASE("view: the CLI writes the page, and bad input exits 2 with no page", "[render][view]") {
  using test::run_cli;
  using test::shell_quote;
  test::TempDir dir;
  const std::string mesh = dir.write("cube.off", test::to_off(test::cube_mesh(-0.5, 0.5)));
  const std::string spheres = dir.file("s.json");
  save_sphere_set(one_ball(0.4), spheres);
  const std::string inputs = shell_quote(mesh) + " " + shell_quote(spheres);
  const std::string out = dir.file("page.html");
  const auto ok = run_cli("view " + inputs + " -o " + shell_quote(out) + " --threads 1");
  INFO(ok.err);
  CHECK(ok.exit_code == 0);
  CHECK_THAT(ok.out, Contains("1 part, 12 triangles, 1 inner and 0 outer spheres"));
  const nlohmann::json data = page_data(test::read_file(out));
  CHECK(data["parts"][0]["uncovered_inner"]["whole"] == detail::base64("\xff\x0f"));

  for (const std::string bad : {"--cover-depth 11", "--threads -3"}) {
    const std::string target = dir.file("bad.html");
    const auto r = run_cli("view " + inputs + " -o " + shell_quote(target) + " " + bad);
    CAPTURE(bad, r.err);
    CHECK(r.exit_code == 2);
    CHECK(!std::filesystem::exists(target));
  }
  const std::string target = dir.file("bad.html");
  const auto r = run_cli("view " + shell_quote(dir.file("missing.off")) + " " +
                         shell_quote(spheres) + " -o " + shell_quote(target));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("missing.off"));
  CHECK(!std::filesystem::exists(target));
}
