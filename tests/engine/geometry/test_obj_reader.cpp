#include <doctest/doctest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/core/error.hpp"
#include "engine/geometry/obj_reader.hpp"

namespace fs = std::filesystem;
using sinew::InputError;
using sinew::read_obj;
using sinew::TriMesh;

namespace {

// One file per test and process: ctest runs the cases of this binary in parallel.
std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("sinew_obj_" + name + "_" + std::to_string(::getpid()) + ".obj")).string();
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string p = temp_path(name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// The message of the InputError that reading `text` throws ("" if none).
std::string read_error(const std::string& name, const std::string& text) {
  const std::string path = write_temp(name, text);
  std::string what;
  try {
    read_obj(path);
  } catch (const InputError& e) {
    what = e.what();
  }
  fs::remove(path);
  return what;
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

TEST_CASE("obj_reader: vertices, triangles and index formats") {
  const std::string path = write_temp("formats",
                                      "# a comment\n"
                                      "o thing\n"
                                      "v 0 0 0\n"
                                      "v 1.5 -2e-1 +3\n"
                                      "vt 0.5 0.5\n"
                                      "vn 0 0 1\n"
                                      "v 0 1 0 1.0\n"  // optional w is ignored
                                      "v 0 0 1  # trailing comment\n"
                                      "f 1/1/1 2/1/1 3/1/1\n"
                                      "f 1//1 3//1 4//1\n"
                                      "f 2/1 3/1 4/1\n"
                                      "f -4 -2 -1\n"  // relative: vertices 1, 3, 4
                                      "s off\n"
                                      "usemtl x\n");
  const TriMesh m = read_obj(path);
  fs::remove(path);
  REQUIRE(m.vertices.size() == 4);
  CHECK(m.vertices[1].x() == 1.5);
  CHECK(m.vertices[1].y() == -0.2);
  CHECK(m.vertices[1].z() == 3.0);
  CHECK(m.vertices[3].z() == 1.0);
  REQUIRE(m.triangles.size() == 4);
  CHECK(m.triangles[0] == std::array<int, 3>{0, 1, 2});
  CHECK(m.triangles[1] == std::array<int, 3>{0, 2, 3});
  CHECK(m.triangles[2] == std::array<int, 3>{1, 2, 3});
  CHECK(m.triangles[3] == std::array<int, 3>{0, 2, 3});
}

TEST_CASE("obj_reader: polygons are fan-triangulated with their winding kept") {
  const std::string path = write_temp("fan",
                                      "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nv -1 0.5 0\r\n"
                                      "f 1 2 3 4\r\n"
                                      "f 1 2 3 4 5\r\n");
  const TriMesh m = read_obj(path);
  fs::remove(path);
  REQUIRE(m.triangles.size() == 2 + 3);
  CHECK(m.triangles[0] == std::array<int, 3>{0, 1, 2});
  CHECK(m.triangles[1] == std::array<int, 3>{0, 2, 3});
  CHECK(m.triangles[2] == std::array<int, 3>{0, 1, 2});
  CHECK(m.triangles[3] == std::array<int, 3>{0, 2, 3});
  CHECK(m.triangles[4] == std::array<int, 3>{0, 3, 4});
}

TEST_CASE("obj_reader: faces may refer to vertices defined later") {
  const std::string path = write_temp("forward", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
  const TriMesh m = read_obj(path);
  fs::remove(path);
  CHECK(m.vertices.size() == 3);
  CHECK(m.triangles.size() == 1);
}

TEST_CASE("obj_reader: errors name the file and the line") {
  SUBCASE("missing file") {
    const std::string path = (fs::temp_directory_path() / "sinew_obj_does_not_exist.obj").string();
    std::string what;
    try {
      read_obj(path);
    } catch (const InputError& e) {
      what = e.what();
    }
    CHECK(starts_with(what, path + ": cannot open"));
  }
  SUBCASE("bad number") {
    const std::string what = read_error("badnum", "v 0 0 0\nv 1 0 0\nv 0 x1 0\nf 1 2 3\n");
    CHECK(starts_with(what, temp_path("badnum") + ":3: "));
    CHECK(what.find("number") != std::string::npos);
  }
  SUBCASE("missing coordinate") {
    const std::string what = read_error("short_v", "v 0 0 0\nv 1 0\n");
    CHECK(starts_with(what, temp_path("short_v") + ":2: "));
  }
  SUBCASE("index out of range") {
    const std::string what = read_error("range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n");
    CHECK(starts_with(what, temp_path("range") + ":5: "));
    CHECK(what.find("out of range") != std::string::npos);
  }
  SUBCASE("negative index out of range") {
    const std::string what = read_error("negrange", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n");
    CHECK(starts_with(what, temp_path("negrange") + ":3: "));
  }
  SUBCASE("zero index") {
    const std::string what = read_error("zero", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    CHECK(starts_with(what, temp_path("zero") + ":4: "));
  }
  SUBCASE("face with two vertices") {
    const std::string what = read_error("two", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2\n");
    CHECK(starts_with(what, temp_path("two") + ":5: "));
    CHECK(what.find("at least 3") != std::string::npos);
  }
  SUBCASE("no triangles") {
    const std::string what = read_error("empty", "v 0 0 0\nv 1 0 0\n");
    CHECK(starts_with(what, temp_path("empty") + ":"));
    CHECK(what.find("face") != std::string::npos);
  }
}

TEST_CASE("obj_reader: armadillo") {
  const std::string path = SINEW_SOURCE_DIR "/../shared/meshes/armadillo.obj";
  if (!fs::exists(path)) {
    MESSAGE("skipped: " << path << " not found");
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const TriMesh m = read_obj(path);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  MESSAGE("read " << m.triangles.size() << " triangles in " << secs << " s");
  // Counts documented in shared/meshes/SOURCES.md.
  CHECK(m.vertices.size() == 43243);
  CHECK(m.triangles.size() == 86482);
  CHECK(count_open_edges(m) == 0);
}

// Found by tools/fuzz (fuzz_obj_reader): negating the index -2^63 overflowed (UBSan).
TEST_CASE("obj_reader: the most negative face index is out of range, not undefined behaviour") {
  const std::string what =
      read_error("longmin", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n");
  CHECK(starts_with(what, temp_path("longmin") + ":4: face index -9223372036854775808 is out of range"));
}
