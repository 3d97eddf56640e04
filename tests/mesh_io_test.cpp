#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/sha256.h"
#include "support/mesh_writers.h"
#include "support/temp_dir.h"

using namespace medspheres;
using Catch::Matchers::Contains;
using medspheres::test::TempDir;

namespace {

// The loaded mesh must be the generated one up to vertex order: same triangle count,
// same welded vertex count, closed, outward, same volume and bounds.
void check_same_solid(const LoadedMesh& got, const TriangleMesh& want, double tol) {
  const MeshReport w = analyze_mesh(want);
  CHECK(got.report.triangles == w.triangles);
  CHECK(got.report.vertices == w.vertices);
  CHECK(got.report.closed);
  CHECK(got.report.is_closed_outward());
  CHECK(got.report.signed_volume == Approx(w.signed_volume).epsilon(tol));
  CHECK((got.report.bbox_min - w.bbox_min).norm() < tol);
  CHECK((got.report.bbox_max - w.bbox_max).norm() < tol);
}

std::string error_of(const std::string& path, const MeshLoadOptions& options = {}) {
  try {
    load_mesh(path, options);
  } catch (const InputError& e) {
    CHECK(e.source() == path);
    return e.what();
  }
  return "";
}

// The unit cube as PLY with \p end_header as the last header line: misspelled, it makes
// assimp 5.2.5 segfault on the binary file and loop forever on the ASCII one.
std::string cube_ply(bool binary, const std::string& end_header) {
  const float v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::string s = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                  " 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty "
                  "float z\nelement face 12\nproperty list uchar int vertex_indices\n" +
                  end_header + "\n";
  if (binary) {
    for (const auto& p : v) s.append(reinterpret_cast<const char*>(p), sizeof p);
    for (const auto& t : f) {
      s.push_back('\3');
      s.append(reinterpret_cast<const char*>(t), sizeof t);
    }
  } else {
    for (const auto& p : v)
      s += std::to_string(int(p[0])) + " " + std::to_string(int(p[1])) + " " +
           std::to_string(int(p[2])) + "\n";
    for (const auto& t : f)
      s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) +
           "\n";
  }
  return s;
}

// A COLLADA cube with a stray letter in <p> ("7G2"): it makes assimp 5.2.5 loop while
// allocating without bound.
const char* const kRunawayDae = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
 <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
 <library_geometries>
  <geometry id="cube" name="cube"><mesh>
   <source id="cube-pos"><float_array id="cube-pos-arr" count="24">0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1</float_array>
    <technique_common><accessor source="#cube-pos-arr" count="8" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
   <vertices id="cube-vtx"><input semantic="POSITION" source="#cube-pos"/></vertices>
   <triangles count="12"><input semantic="VERTEX" source="#cube-vtx" offset="0"/><p>0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7G2 7 6 3 0 4 3 4 7</p></triangles>
  </mesh></geometry>
 </library_geometries>
 <library_visual_scenes><visual_scene id="Scene">
  <node id="A"><instance_geometry url="#cube"/></node>
 </visual_scene></library_visual_scenes>
 <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";

MeshLoadOptions with_timeout(double seconds) {
  MeshLoadOptions o;
  o.import_timeout_seconds = seconds;
  return o;
}

std::size_t open_descriptors() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

}  // namespace

TEST_CASE("each supported format loads, welds and validates", "[mesh_io]") {
  TempDir dir;
  // assimp keeps single-precision coordinates, hence the 1e-6 relative tolerances.
  const TriangleMesh m = make_torus(1.0, 0.375, 24, 12);
  SECTION("OFF") {
    check_same_solid(load_mesh(dir.write("m.off", test::to_off(m))), m, 1e-6);
  }
  SECTION("OBJ, indexed") {
    check_same_solid(load_mesh(dir.write("m.obj", test::to_obj(m))), m, 1e-6);
  }
  SECTION("OBJ, one vertex per corner, welded back") {
    check_same_solid(load_mesh(dir.write("m.obj", test::to_obj(m, true))), m, 1e-6);
  }
  SECTION("STL, ASCII") {
    check_same_solid(load_mesh(dir.write("m.stl", test::to_stl_ascii(m))), m, 1e-6);
  }
  SECTION("STL, binary") {
    check_same_solid(load_mesh(dir.write("m.stl", test::to_stl_binary(m))), m, 1e-6);
  }
  SECTION("PLY, ASCII") {
    check_same_solid(load_mesh(dir.write("m.ply", test::to_ply_ascii(m))), m, 1e-6);
  }
  SECTION("glTF 2, embedded buffer") {
    check_same_solid(load_mesh(dir.write("m.gltf", test::to_gltf(m, {{0, 0, 0}}))), m, 1e-6);
  }
}

TEST_CASE("node transforms are applied and instanced meshes kept", "[mesh_io]") {
  TempDir dir;
  const TriangleMesh box = make_box({1, 1, 1});
  SECTION("COLLADA node matrix: scale 2 and translate") {
    Eigen::Matrix4d X = Eigen::Matrix4d::Identity();
    X.topLeftCorner<3, 3>() *= 2.0;
    X.topRightCorner<3, 1>() = Eigen::Vector3d(10, 0, -5);
    const LoadedMesh l = load_mesh(dir.write("box.dae", test::to_dae(box, X)));
    CHECK(l.report.triangles == 12);
    CHECK(l.report.closed);
    CHECK(l.report.signed_volume == Approx(64.0));
    CHECK((l.report.bbox_min - Eigen::Vector3d(8, -2, -7)).norm() < 1e-5);
    CHECK((l.report.bbox_max - Eigen::Vector3d(12, 2, -3)).norm() < 1e-5);
  }
  SECTION("glTF: one mesh placed by two nodes gives two components") {
    const LoadedMesh l =
        load_mesh(dir.write("two.gltf", test::to_gltf(box, {{0, 0, 0}, {5, 0, 0}})));
    CHECK(l.report.triangles == 24);
    CHECK(l.report.components == 2);
    CHECK(l.report.closed);
    CHECK(l.report.signed_volume == Approx(16.0));
    CHECK(l.report.bbox_max.x() == Approx(6.0));
  }
}

TEST_CASE("inward-wound meshes are flipped with a warning", "[mesh_io]") {
  TempDir dir;
  TriangleMesh m = make_icosphere(1.0, 2);
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  const LoadedMesh l = load_mesh(dir.write("in.off", test::to_off(m)));
  CHECK(l.orientation_fix.components_flipped_outward == 1);
  CHECK(l.report.is_closed_outward());
  REQUIRE_FALSE(l.warnings.empty());
  CHECK_THAT(l.warnings[0], Contains("inward"));
  MeshLoadOptions keep;
  keep.fix_orientation = false;
  CHECK(load_mesh(dir.file("in.off"), keep).report.signed_volume < 0);
}

TEST_CASE("bad mesh files get an error naming the file and the problem", "[mesh_io]") {
  TempDir dir;
  CHECK_THAT(error_of(dir.file("missing.stl")), Contains("no such file"));
  CHECK_THAT(error_of(dir.path().string()), Contains("directory"));
  CHECK_THAT(error_of(dir.write("empty.stl", "")), Contains("empty"));
  CHECK_THAT(error_of(dir.write("m.xyz", "1 2 3\n")), Contains("unsupported mesh format"));
  CHECK_THAT(error_of(dir.write("m.txt", "hello")), Contains("unsupported mesh format"));
  CHECK_THAT(error_of(dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n")),
             Contains("cannot parse") || Contains("no triangles"));
  CHECK_THAT(error_of(dir.write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")),
             Contains("non-finite") || Contains("cannot parse"));
  CHECK_THAT(error_of(dir.write("inf.off", "OFF\n3 1 0\n0 0 0\ninf 0 0\n0 1 0\n3 0 1 2\n")),
             Contains("non-finite") || Contains("cannot parse"));
  CHECK_THAT(error_of(dir.write("flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n")),
             Contains("degenerate"));
  CHECK_THAT(error_of(dir.write("garbage.stl", std::string(200, '\x07'))),
             Contains("cannot parse") || Contains("no triangles"));
  CHECK_THAT(error_of(dir.write("bad.off", "OFF\n3 1 0\n0 0 0\n")),
             Contains("truncated") && Contains("3 vertices"));
}

TEST_CASE("assimp's errors read as parse failures", "[mesh_io]") {
  TempDir dir;
  CHECK_THAT(error_of(dir.write("garbage.ply", "plx\nnot a ply file\n")),
             Contains("cannot parse the file (assimp: ") && Contains("magic number"));
  CHECK_THAT(error_of(dir.write("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")),
             Contains("cannot parse the file (assimp: ") && Contains("out of range"));
}

TEST_CASE("only regular files are read", "[mesh_io]") {
  TempDir dir;
  const std::string fifo = dir.file("pipe.obj");
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  // Without the check this blocks for ever in open(), waiting for a writer.
  CHECK_THAT(error_of(fifo), Contains("not a regular file"));
  const std::string dev = dir.file("null.stl");
  std::filesystem::create_symlink("/dev/null", dev);
  CHECK_THAT(error_of(dev), Contains("not a regular file"));
  std::filesystem::create_symlink(dir.file("nowhere.obj"), dir.file("dangling.obj"));
  CHECK_THAT(error_of(dir.file("dangling.obj")), Contains("no such file"));
}

TEST_CASE("non-finite coordinates are named by mesh and vertex as read", "[mesh_io]") {
  TempDir dir;
  // The file's coordinates are checked before any transform: inf stays inf, no -nan.
  const std::string inf =
      error_of(dir.write("inf.off", "OFF\n3 1 0\n0 0 0\ninf 0 0\n0 1 0\n3 0 1 2\n"));
  CHECK_THAT(inf,
             Contains("vertex 1 of mesh 0") && Contains("non-finite") && Contains("(inf, 0, 0)"));
  CHECK_THAT(inf, !Contains("nan"));
  // 1e60 overflows assimp's single precision to inf.
  const std::string big =
      error_of(dir.write("big.obj", "v 0 0 0\nv 1e60 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n"));
  CHECK_THAT(big, Contains("vertex 1 of mesh 0") && Contains("inf") && !Contains("nan"));
  // An unreferenced vertex of an OFF file counts too.
  CHECK_THAT(
      error_of(dir.write("unref.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 -nan\n3 0 1 2\n")),
      Contains("vertex 3 of mesh 0") && Contains("non-finite"));
  // Finite in the file, non-finite only through a scene node's matrix.
  Eigen::Matrix4d X = Eigen::Matrix4d::Identity();
  X(0, 0) = 1e308;
  X(0, 1) = 1e308;
  CHECK_THAT(error_of(dir.write("huge.dae", test::to_dae(make_box({1, 1, 1}), X))),
             Contains("not after the transform"));
}

TEST_CASE("OFF faces must name existing vertices", "[mesh_io]") {
  TempDir dir;
  const std::string head = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n";
  // assimp clamps 7 to vertex 3 and reads -5 as 0, silently.
  CHECK_THAT(error_of(dir.write("oor.off", head + "3 0 1 7\n")),
             Contains("face 1") && Contains("vertex 7") && Contains("out of range"));
  CHECK_THAT(error_of(dir.write("neg.off", head + "3 0 1 -5\n")),
             Contains("face 1") && Contains("vertex -5") && Contains("out of range"));
  CHECK_THAT(error_of(dir.write("short.off", head + "3 0 2\n")),
             Contains("face 1") && Contains("announces 3 vertices but lists 2"));
  CHECK_THAT(error_of(dir.write("word.off", head + "3 0 2 x\n")),
             Contains("face 1") && Contains("'x'"));
  // A comment line among the faces would make assimp drop it and lose the last face.
  CHECK_THAT(error_of(dir.write("comment.off", head + "# note\n3 0 2 3\n")),
             Contains("face 1") && Contains("vertex count"));
  CHECK_THAT(error_of(dir.write("few.off", head)),
             Contains("truncated") && Contains("2 faces") && Contains("only 1 face line"));
  std::string big = "OFF\n10 1 0\n";
  for (int i = 0; i < 10; ++i)
    big += std::to_string(std::cos(i * 0.6)) + " " + std::to_string(std::sin(i * 0.6)) + " 0\n";
  CHECK_THAT(error_of(dir.write("tenagon.off", big + "10 0 1 2 3 4 5 6 7 8 9\n")),
             Contains("face 0") && Contains("1 to 9"));
  // Numbers of any length are read without overflow (run under UBSan) and shown as
  // written.
  const std::string huge = "1234567890123456789012345";
  CHECK_THAT(error_of(dir.write("huge.off", head + "3 0 1 " + huge + "\n")),
             Contains("face 1") && Contains("vertex " + huge + ", out of range"));
  CHECK_THAT(error_of(dir.write("hugeneg.off", head + "3 0 1 -" + huge + "\n")),
             Contains("face 1") && Contains("vertex -" + huge + ", out of range"));
  CHECK_THAT(error_of(dir.write("hugecount.off", "OFF\n" + huge + " 1 0\n0 0 0\n")),
             Contains("truncated") && Contains("announces " + huge + " vertices"));

  // What assimp reads correctly still loads: header comments, blank lines, CRLF, trailing
  // colours and comments, counts on the keyword's line.
  const std::string quads =
      "OFF\n# a cube\n\n8 6 12\n\n-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n-1 -1 1\n1 -1 1\n1 1 1\n"
      "-1 1 1\n\n4 0 3 2 1 255 0 0\n4 4 5 6 7 # top\n  4\t0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n"
      "4 3 0 4 7\n";
  CHECK(load_mesh(dir.write("quads.off", quads)).report.signed_volume == Approx(8.0));
  std::string crlf;
  for (char c : quads) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  CHECK(load_mesh(dir.write("crlf.off", crlf)).report.signed_volume == Approx(8.0));
  CHECK(load_mesh(dir.write("oneline.off",
                            "OFF 4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n"
                            "3 0 1 3\n3 0 3 2\n3 1 2 3\n"))
            .report.signed_volume == Approx(1.0 / 6));
}

TEST_CASE("a file that crashes assimp is an input error, not a crash", "[mesh_io][isolation]") {
  TempDir dir;
  // The control: spelled right, the same bytes load.
  CHECK(load_mesh(dir.write("good.ply", cube_ply(true, "end_header"))).report.signed_volume ==
        Approx(1.0));
  const std::string message = error_of(dir.write("segv.ply", cube_ply(true, "end_headXr")));
  // The importer makes a stray read: killed by SIGSEGV or SIGBUS, depending on where it
  // lands; under AddressSanitizer its handler may turn either into exit status 1.
  CHECK_THAT(message, Contains("crashed on the file (signal 11: SIGSEGV)") ||
                          Contains("crashed on the file (signal 7: SIGBUS)") ||
                          Contains("failed on the file (exit status"));
  CHECK_THAT(message, Contains("malformed"));
}

TEST_CASE("a file that makes assimp loop is stopped at the timeout", "[mesh_io][isolation]") {
  TempDir dir;
  CHECK(load_mesh(dir.write("good.ply", cube_ply(false, "end_header"))).report.signed_volume ==
        Approx(1.0));
  // No memory limit: the COLLADA file also allocates without bound, and the memory
  // limit could stop it first, with another message.
  MeshLoadOptions o = with_timeout(1.0);
  o.import_memory_limit_bytes = 0;
  CHECK_THAT(error_of(dir.write("loop.ply", cube_ply(false, "end_headXr")), o),
             Contains("did not finish within 1 s") && Contains("may be malformed") &&
                 Contains("MeshLoadOptions::import_timeout_seconds"));
  CHECK_THAT(error_of(dir.write("loop.dae", kRunawayDae), o),
             Contains("did not finish within 1 s"));
}

TEST_CASE("the import timeout must be a number of seconds >= 0", "[mesh_io][isolation]") {
  TempDir dir;
  const std::string path = dir.write("box.off", test::to_off(make_box({1, 1, 1})));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double bad : {nan, -1.0, -inf, -1e-300}) {
    INFO(bad);
    for (const bool isolate : {true, false}) {
      MeshLoadOptions o = with_timeout(bad);
      o.isolate_import = isolate;
      std::string message;
      try {
        load_mesh(path, o);
      } catch (const std::invalid_argument& e) {
        message = e.what();
      }
      CHECK_THAT(message, Contains("MeshLoadOptions::import_timeout_seconds"));
    }
  }
  // +infinity and 0 mean no limit.
  CHECK(load_mesh(path, with_timeout(inf)).report.signed_volume == Approx(8.0));
  CHECK(load_mesh(path, with_timeout(0.0)).report.signed_volume == Approx(8.0));
}

TEST_CASE("an import that allocates without bound is stopped by the memory limit",
          "[mesh_io][isolation]") {
  TempDir dir;
  const std::string dae = dir.write("runaway.dae", kRunawayDae);
  MeshLoadOptions o;
  o.import_memory_limit_bytes = std::int64_t{256} << 20;
  if (!import_memory_limit_enforced()) {
    // Sanitizer builds: no address-space limit, the timeout stops it.
    o.import_timeout_seconds = 1.0;
    CHECK_THAT(error_of(dae, o), Contains("did not finish"));
  } else {
    o.import_timeout_seconds = 300.0;
    CHECK_THAT(error_of(dae, o), Contains("ran out of memory (256 MiB allowed)"));
  }
}

TEST_CASE("the isolated import returns what the in-process import returns",
          "[mesh_io][isolation]") {
  TempDir dir;
  // About 4 MB through the pipe, far more than its 64 KiB buffer: the parent must read
  // while the child writes.
  const TriangleMesh m = make_torus(1.0, 0.375, 400, 200);
  const std::string path = dir.write("big.obj", test::to_obj(m, true));
  MeshLoadOptions in_process;
  in_process.isolate_import = false;
  const LoadedMesh a = load_mesh(path);
  const LoadedMesh b = load_mesh(path, in_process);
  check_same_solid(a, m, 1e-6);
  CHECK(a.mesh.vertices == b.mesh.vertices);
  CHECK(a.mesh.triangles == b.mesh.triangles);
  CHECK(a.warnings == b.warnings);
  // No time limit at all.
  check_same_solid(load_mesh(path, with_timeout(0.0)), m, 1e-6);
  MeshLoadOptions unlimited;
  unlimited.import_memory_limit_bytes = 0;
  check_same_solid(load_mesh(path, unlimited), m, 1e-6);
}

TEST_CASE("a caller that ignores SIGCHLD gets the same outcomes", "[mesh_io][isolation]") {
  // The kernel reaps the child itself then: the parent can neither wait for it nor
  // rely on its pid, which may be reused, for the kill at the deadline.
  TempDir dir;
  const std::string good = dir.write("good.off", test::to_off(make_box({1, 1, 1})));
  const std::string loop = dir.write("loop.ply", cube_ply(false, "end_headXr"));
  struct sigaction ignore {
  }, old{};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  REQUIRE(::sigaction(SIGCHLD, &ignore, &old) == 0);
  std::string good_error, loop_error;
  double volume = 0.0;
  try {
    volume = load_mesh(good).report.signed_volume;
    loop_error = error_of(loop, with_timeout(0.5));
  } catch (const std::exception& e) {
    good_error = e.what();
  }
  ::sigaction(SIGCHLD, &old, nullptr);
  CHECK(good_error.empty());
  CHECK(volume == Approx(8.0));
  CHECK_THAT(loop_error, Contains("did not finish within 0.5 s"));
}

namespace {

// Lowers the soft limit on descriptors for its lifetime.
class DescriptorLimit {
 public:
  explicit DescriptorLimit(rlim_t soft) {
    REQUIRE(::getrlimit(RLIMIT_NOFILE, &old_) == 0);
    rlimit tight = old_;
    tight.rlim_cur = soft;
    REQUIRE(::setrlimit(RLIMIT_NOFILE, &tight) == 0);
  }
  ~DescriptorLimit() { ::setrlimit(RLIMIT_NOFILE, &old_); }
  DescriptorLimit(const DescriptorLimit&) = delete;
  DescriptorLimit& operator=(const DescriptorLimit&) = delete;

 private:
  rlimit old_{};
};

}  // namespace

TEST_CASE("an import process that cannot be started is an error naming the file",
          "[mesh_io][isolation]") {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  // The sanitizer runtimes open pipes of their own (UBSan's vptr check probes memory
  // through one), so under a descriptor limit they report errors that are theirs, not
  // ours. The plain build runs this test.
  WARN("skipped under sanitizers: their runtime needs free file descriptors");
  return;
#endif
  TempDir dir;
  const std::string path = dir.write("box.obj", test::to_obj(make_box({1, 1, 1})));
  // One free descriptor: enough to open the file, not for the pipe to the child.
  const int lowest = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  REQUIRE(lowest >= 0);
  ::close(lowest);
  std::string message;
  bool input_error = false;
  {
    DescriptorLimit limit(static_cast<rlim_t>(lowest) + 1);
    try {
      load_mesh(path);
    } catch (const InputError& e) {
      input_error = true;
      message = e.what();
    } catch (const Error& e) {
      message = e.what();
    }
  }
  CHECK_FALSE(input_error);  // not the file's fault: exit status 1 in the CLI
  CHECK_THAT(message, Contains(path + ": ") && Contains("cannot create a pipe"));
  CHECK(load_mesh(path).report.signed_volume == Approx(8.0));
}

TEST_CASE("the import process leaves nothing behind", "[mesh_io][isolation]") {
  TempDir dir;
  const std::string good = dir.write("good.off", test::to_off(make_box({1, 1, 1})));
  const std::string crash = dir.write("segv.ply", cube_ply(true, "end_headXr"));
  const std::string loop = dir.write("loop.ply", cube_ply(false, "end_headXr"));
  const std::string bad = dir.write("bad.off", "OFF\n3 1 0\n0 0 0\n");
  // Unflushed output of the caller: a child that left with exit() instead of _exit()
  // would flush it a second time.
  const std::string out_path = dir.file("stdio.txt");
  std::FILE* out = std::fopen(out_path.c_str(), "w");
  REQUIRE(out != nullptr);
  REQUIRE(std::setvbuf(out, nullptr, _IOFBF, 1 << 16) == 0);
  std::fputs("pending", out);

  const std::size_t fds = open_descriptors();
  CHECK_NOTHROW(load_mesh(good));
  CHECK_THROWS_AS(load_mesh(crash), InputError);
  CHECK_THROWS_AS(load_mesh(loop, with_timeout(0.5)), InputError);
  CHECK_THROWS_AS(load_mesh(bad), InputError);
  CHECK(open_descriptors() == fds);
  // Every child was reaped: none is left to wait for.
  errno = 0;
  CHECK(::waitpid(-1, nullptr, WNOHANG) == -1);
  CHECK(errno == ECHILD);

  CHECK(std::filesystem::file_size(out_path) == 0);
  std::fclose(out);
  CHECK(std::filesystem::file_size(out_path) == 7);
}

TEST_CASE("a hollow solid keeps its cavity wound inward", "[mesh_io]") {
  TempDir dir;
  TriangleMesh hollow = test::cube_mesh(0, 3);
  test::append_mesh(hollow, test::cube_mesh(1, 2), true);
  const LoadedMesh l = load_mesh(dir.write("hollow.off", test::to_off(hollow)));
  CHECK(l.orientation_fix.components_flipped_outward == 0);
  CHECK(l.report.signed_volume == Approx(26.0));
  CHECK(l.report.is_closed_outward());
  for (const std::string& w : l.warnings) CHECK_THAT(w, !Contains("inward"));
}

TEST_CASE("file_sha256 matches known digests", "[mesh_io]") {
  CHECK(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(sha256_hex(std::string(1000000, 'a')) ==
        "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  TempDir dir;
  CHECK(file_sha256(dir.write("abc", "abc")) == sha256_hex("abc"));
  CHECK_THROWS_AS(file_sha256(dir.file("nope")), InputError);
}

TEST_CASE("a mesh in memory with coordinates whose squares overflow is bad input", "[mesh_io]") {
  // Files cannot hold them (assimp reads single precision: they become inf), but arrays can.
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1e300, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  try {
    (void)prepare_mesh(m, "arrays");
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK_THAT(std::string(e.what()),
               Contains("arrays") && Contains("vertex 1") && Contains("overflow"));
  }
  m.vertices[1].x() = 1e150;  // the largest accepted
  CHECK(prepare_mesh(m, "arrays").mesh.num_triangles() == 1);
}
