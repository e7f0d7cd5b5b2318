#include <doctest/doctest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/core/error.hpp"
#include "engine/geometry/tetgen_reader.hpp"

namespace fs = std::filesystem;
using namespace sinew;

namespace {

// One base name per test and process: ctest runs the cases of this binary in parallel.
std::string temp_base(const std::string& name) {
  return (fs::temp_directory_path() / ("sinew_tetgen_" + name + "_" + std::to_string(::getpid())))
      .string();
}

// Writes BASE.node (and BASE.ele unless `ele` is null); returns BASE.
std::string write_mesh(const std::string& name, const std::string& node, const char* ele) {
  const std::string base = temp_base(name);
  std::ofstream(base + ".node", std::ios::binary) << node;
  if (ele) std::ofstream(base + ".ele", std::ios::binary) << ele;
  return base;
}

void remove_mesh(const std::string& base) {
  fs::remove(base + ".node");
  fs::remove(base + ".ele");
}

// The message of the InputError that reading the files throws ("" if none).
std::string read_error(const std::string& name, const std::string& node, const char* ele) {
  const std::string base = write_mesh(name, node, ele);
  std::string what;
  try {
    read_tetgen(base);
  } catch (const InputError& e) {
    what = e.what();
  }
  remove_mesh(base);
  return what;
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

double volume_of(const TetMesh& m, int t) {
  const auto& k = m.tets[t];
  return tet_signed_volume(m.nodes[k[0]], m.nodes[k[1]], m.nodes[k[2]], m.nodes[k[3]]);
}

// Two tets sharing a face; the second one is written inverted.
const char* kNode0 =
    "# five points, 0-based, one attribute and boundary markers\n"
    "5 3 1 1\n"
    "0 0 0 0 7.5 1\n"
    "1 1.0 0 0 7.5 1   # trailing comment\n"
    "\n"
    "2 0 1 0 7.5 1\n"
    "3 0 0 +1e0 7.5 1\n"
    "4 1 1 1 7.5 0\r\n";
const char* kEle0 =
    "2 4 1\n"
    "0 0 1 2 3 -1\n"
    "1 1 3 2 4 -1\n";

}  // namespace

TEST_CASE("tetgen_reader: 0-based files with attributes, markers and comments") {
  const std::string base = write_mesh("zero", kNode0, kEle0);
  for (const std::string& path : {base, base + ".node", base + ".ele"}) {
    const TetMeshFile f = read_tetgen(path);
    REQUIRE(f.mesh.nodes.size() == 5);
    REQUIRE(f.mesh.tets.size() == 2);
    CHECK(f.mesh.nodes[1] == Vec3(1, 0, 0));
    CHECK(f.mesh.nodes[3] == Vec3(0, 0, 1));
    CHECK(f.mesh.tets[0] == std::array<int, 4>{0, 1, 2, 3});
    CHECK(f.mesh.tets[1] == std::array<int, 4>{1, 3, 4, 2});  // nodes 2 and 3 swapped
    CHECK(f.reoriented == 1);
    CHECK(f.unreferenced_nodes == 0);
    for (int t = 0; t < 2; ++t) CHECK(volume_of(f.mesh, t) > 0);
  }
  remove_mesh(base);
}

TEST_CASE("tetgen_reader: 1-based files and omitted header fields") {
  const std::string base = write_mesh("one",
                                      "5\n"
                                      "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n",
                                      "2\n"
                                      "1 1 2 3 4\n"
                                      "2 2 3 4 5\n");
  const TetMeshFile f = read_tetgen(base + ".node");
  remove_mesh(base);
  REQUIRE(f.mesh.tets.size() == 2);
  CHECK(f.mesh.tets[0] == std::array<int, 4>{0, 1, 2, 3});
  CHECK(f.mesh.tets[1] == std::array<int, 4>{1, 2, 3, 4});
  CHECK(f.reoriented == 0);
}

TEST_CASE("tetgen_reader: 10-node tets keep their corners") {
  const std::string base = write_mesh("quadratic", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n",
                                      "1 10 0\n0 0 1 2 3 0 1 2 3 0 1\n");
  const TetMeshFile f = read_tetgen(base);
  remove_mesh(base);
  REQUIRE(f.mesh.tets.size() == 1);
  CHECK(f.mesh.tets[0] == std::array<int, 4>{0, 1, 2, 3});
}

TEST_CASE("tetgen_reader: errors name the file, the line and what was expected") {
  SUBCASE("truncated .node") {
    const std::string what =
        read_error("trunc_node", "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n", kEle0);
    CHECK(starts_with(what, temp_base("trunc_node") + ".node:4: expected 5 points"));
  }
  SUBCASE("garbled coordinate") {
    const std::string what = read_error("garbled", "3 3 0 0\n0 0 0 0\n1 1 0x 0\n2 0 1 0\n", kEle0);
    CHECK(starts_with(what,
                      temp_base("garbled") + ".node:3: expected a finite coordinate, got '0x'"));
  }
  SUBCASE("missing field") {
    const std::string what = read_error("fields", "2 3 0 1\n0 0 0 0 1\n1 1 0 0\n", kEle0);
    CHECK(starts_with(what, temp_base("fields") + ".node:3: expected 5 fields"));
  }
  SUBCASE("non-consecutive node indices") {
    const std::string what = read_error("gap", "2 3 0 0\n1 0 0 0\n3 1 0 0\n", kEle0);
    CHECK(starts_with(what, temp_base("gap") + ".node:3: expected point index 2"));
  }
  SUBCASE("bad dimension") {
    const std::string what = read_error("dim", "2 2 0 0\n0 0 0\n1 1 0\n", kEle0);
    CHECK(starts_with(what, temp_base("dim") + ".node:1: expected dimension 3"));
  }
  SUBCASE("extra data after the announced count") {
    const std::string what = read_error("extra", "1 3 0 0\n0 0 0 0\n1 1 0 0\n", kEle0);
    CHECK(starts_with(what, temp_base("extra") + ".node:3: expected the end of the file"));
  }
  SUBCASE("truncated .ele") {
    const std::string what =
        read_error("trunc_ele", kNode0, "# comment\n3 4 1\n0 0 1 2 3 0\n1 1 2 3 4 0\n");
    CHECK(starts_with(what, temp_base("trunc_ele") + ".ele:4: expected 3 tetrahedra"));
  }
  SUBCASE(".ele refers to a missing node") {
    const std::string what = read_error("missing_node", kNode0, "1 4 0\n0 0 1 2 5\n");
    CHECK(starts_with(what, temp_base("missing_node") + ".ele:2: expected a node index in [0, 4]"));
  }
  SUBCASE("1-based .node with a 0 in the .ele") {
    const std::string what =
        read_error("base_mismatch", "4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", "1\n1 0 1 2 3\n");
    CHECK(
        starts_with(what, temp_base("base_mismatch") + ".ele:2: expected a node index in [1, 4]"));
  }
  SUBCASE("degenerate tet") {
    const std::string what = read_error("flat", "4 3\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 1 1 0\n",
                                        "# flat\n\n1 4\n0 0 1 2 3\n");
    CHECK(
        starts_with(what, temp_base("flat") + ".ele:4: expected a tetrahedron of nonzero volume"));
  }
  SUBCASE("repeated node") {
    const std::string what = read_error("repeat", kNode0, "1 4 0\n0 0 1 1 3\n");
    CHECK(starts_with(what, temp_base("repeat") + ".ele:2: expected 4 distinct nodes"));
  }
  SUBCASE(".node without .ele") {
    const std::string what = read_error("no_ele", kNode0, nullptr);
    CHECK(starts_with(what, temp_base("no_ele") + ".node: expected its tetrahedra in " +
                                temp_base("no_ele") + ".ele"));
  }
  SUBCASE("no files") {
    std::string what;
    try {
      read_tetgen(temp_base("nothing") + ".ele");
    } catch (const InputError& e) {
      what = e.what();
    }
    CHECK(starts_with(what, temp_base("nothing") + ".node: cannot open file"));
  }
  SUBCASE("empty .ele") {
    const std::string what = read_error("empty", kNode0, "# nothing\n");
    CHECK(starts_with(what, temp_base("empty") + ".ele:1: expected the header"));
  }
}

TEST_CASE("tetgen_reader: shared meshes bunny_5, cube_10, cube_20") {
  struct Expected {
    const char* name;
    std::size_t nodes, tets;  // the headers (shared/meshes/SOURCES.md)
  };
  for (const Expected& e : {Expected{"bunny_5", 1356, 5266}, Expected{"cube_10", 491, 1800},
                            Expected{"cube_20", 2931, 13200}}) {
    const std::string base = std::string(SINEW_SOURCE_DIR "/../shared/meshes/tet/") + e.name;
    if (!fs::exists(base + ".node")) {
      MESSAGE("skipped: " << base << ".node not found");
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const TetMeshFile f = read_tetgen(base);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    MESSAGE(std::string(e.name) << ": read " << f.mesh.nodes.size() << " nodes, "
                                << f.mesh.tets.size() << " tets in " << secs << " s ("
                                << f.reoriented << " reoriented, " << f.unreferenced_nodes
                                << " unreferenced nodes)");
    CHECK(f.mesh.nodes.size() == e.nodes);
    CHECK(f.mesh.tets.size() == e.tets);
    double volume = 0;
    int non_positive = 0;
    for (int t = 0; t < int(f.mesh.tets.size()); ++t) {
      const double v = volume_of(f.mesh, t);
      non_positive += v <= 0;
      volume += v;
    }
    CHECK(non_positive == 0);
    const TetSurface s = tet_boundary_surface(f.mesh);
    CHECK(count_open_edges(s.mesh) == 0);
    // The outward surface encloses the same volume as the tets (divergence theorem).
    double enclosed = 0;
    for (const auto& t : s.mesh.triangles)
      enclosed += s.mesh.vertices[t[0]].dot(s.mesh.vertices[t[1]].cross(s.mesh.vertices[t[2]])) / 6;
    CHECK(enclosed == doctest::Approx(volume).epsilon(1e-9));
    if (e.name[0] == 'c') {
      // The cubes fill their bounding box (some coordinates carry float rounding, ~1e-8).
      const Aabb b = s.mesh.bounds();
      CHECK(volume == doctest::Approx((b.hi - b.lo).prod()).epsilon(1e-6));
    }
  }
}

// Found by tools/fuzz (fuzz_tetgen_reader): a header announcing 2^31 - 1 points or tets
// reserved that many (about 50 GB) before the file ran out.
TEST_CASE("tetgen_reader: a forged count in a header is an error, not a huge allocation") {
  const std::string node = "4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  CHECK(starts_with(read_error("bignode", "2147483647\n", "1\n1 1 2 3 4\n"),
                    temp_base("bignode") + ".node:1: expected 2147483647 points as the header says, "
                                           "the file ends after 0"));
  CHECK(starts_with(read_error("bigele", node, "2147483647 4 0\n1 1 2 3 4\n"),
                    temp_base("bigele") + ".ele:2: expected 2147483647 tetrahedra as the header says, "
                                          "the file ends after 1"));
}
