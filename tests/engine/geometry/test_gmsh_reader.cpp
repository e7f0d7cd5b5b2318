#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "engine/core/error.hpp"
#include "engine/geometry/gmsh_reader.hpp"

namespace fs = std::filesystem;
using namespace sinew;

namespace {

// One file per test and process: ctest runs the cases of this binary in parallel.
std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() /
          ("sinew_gmsh_" + name + "_" + std::to_string(::getpid()) + ".msh"))
      .string();
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string p = temp_path(name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

TetMeshFile read_text(const std::string& name, const std::string& text) {
  const std::string path = write_temp(name, text);
  TetMeshFile f;
  try {
    f = read_gmsh(path);
  } catch (...) {
    fs::remove(path);
    throw;
  }
  fs::remove(path);
  return f;
}

// The message of the InputError that reading `text` throws ("" if none).
std::string read_error(const std::string& name, const std::string& text) {
  std::string what;
  try {
    read_text(name, text);
  } catch (const InputError& e) {
    what = e.what();
  }
  return what;
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}
bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// Two tets sharing the face {(1,0,0), (0,1,0), (0,0,1)}; the second is written inverted.
// Sparse node tags 10..50, plus a triangle, a line and a point.
const std::string kMsh22 =
    "$MeshFormat\n"
    "2.2 0 8\n"
    "$EndMeshFormat\n"
    "$PhysicalNames\n"
    "1\n"
    "3 1 \"the body\"\n"
    "$EndPhysicalNames\n"
    "$Nodes\n"
    "5\n"
    "10 0 0 0\n"
    "20 1 0 0\n"
    "30 0 1 0\n"
    "40 0 0 1\n"
    "50 1 1 1\n"
    "$EndNodes\n"
    "$Elements\n"
    "5\n"
    "1 15 2 0 1 10\n"
    "2 2 2 0 1 10 20 30\n"
    "3 4 2 1 1 10 20 30 40\n"
    "4 4 3 1 1 7 20 40 30 50\n"
    "5 1 2 0 1 10 20\n"
    "$EndElements\n";

// The same two tets in format 4.1: node blocks on a point, a parametric curve (one node
// no tet uses) and the volume; element blocks of triangles, tets and points.
const std::string kMsh41 =
    "$MeshFormat\r\n"
    "4.1 0 8\r\n"
    "$EndMeshFormat\r\n"
    "$Entities\n"
    "1 1 1 1\n"
    "1 0 0 0 0\n"
    "1 0 0 0 1 0 0 0\n"
    "1 0 0 0 1 1 1 0 1 1\n"
    "1 0 0 0 1 1 1 0 1 1\n"
    "$EndEntities\n"
    "$Nodes\n"
    "3 6 1 6\n"
    "0 1 0 1\n"
    "1\n"
    "0 0 0\n"
    "1 1 1 1\n"
    "6\n"
    "0.5 0 0 0.5\n"
    "3 1 0 4\n"
    "2\n"
    "3\n"
    "4\n"
    "5\n"
    "1 0 0\n"
    "0 1 0\n"
    "0 0 1\n"
    "1 1 1\n"
    "$EndNodes\n"
    "$Elements\n"
    "3 6 1 6\n"
    "2 1 2 2\n"
    "1 1 2 3\n"
    "2 1 2 4\n"
    "3 1 4 2\n"
    "3 1 2 3 4\n"
    "4 2 4 3 5\n"
    "0 1 15 2\n"
    "5 1\n"
    "6 5\n"
    "$EndElements\n";

void check_two_tets(const TetMeshFile& f) {
  REQUIRE(f.mesh.nodes.size() >= 5);
  REQUIRE(f.mesh.tets.size() == 2);
  CHECK(f.reoriented == 1);
  CHECK(f.mesh.tets[0] == std::array<int, 4>{0, 1, 2, 3});
  CHECK(f.mesh.tets[1] == std::array<int, 4>{1, 3, 4, 2});
  for (const auto& t : f.mesh.tets)
    CHECK(tet_signed_volume(f.mesh.nodes[t[0]], f.mesh.nodes[t[1]], f.mesh.nodes[t[2]],
                            f.mesh.nodes[t[3]]) > 0);
}

// kMsh22 with its tet elements replaced by `elements` (count and lines).
std::string msh22_with_elements(const std::string& elements) {
  return kMsh22.substr(0, kMsh22.find("$Elements\n")) + "$Elements\n" + elements + "$EndElements\n";
}

}  // namespace

TEST_CASE("gmsh_reader: ASCII 2.2 keeps 4-node tets and maps sparse node tags") {
  const TetMeshFile f = read_text("v22", kMsh22);
  CHECK(f.mesh.nodes.size() == 5);
  CHECK(f.mesh.nodes[4] == Vec3(1, 1, 1));
  CHECK(f.unreferenced_nodes == 0);
  check_two_tets(f);
}

TEST_CASE("gmsh_reader: ASCII 4.1 with entity blocks, parametric nodes and CRLF") {
  const TetMeshFile f = read_text("v41", kMsh41);
  REQUIRE(f.mesh.nodes.size() == 6);
  // File order: tag 1, tag 6 (the curve node), then tags 2..5.
  CHECK(f.mesh.nodes[1] == Vec3(0.5, 0, 0));
  CHECK(f.mesh.nodes[5] == Vec3(1, 1, 1));
  CHECK(f.unreferenced_nodes == 1);
  REQUIRE(f.mesh.tets.size() == 2);
  CHECK(f.reoriented == 1);
  CHECK(f.mesh.tets[0] == std::array<int, 4>{0, 2, 3, 4});
  CHECK(f.mesh.tets[1] == std::array<int, 4>{2, 4, 5, 3});
  // The same mesh as the 2.2 file, node for node.
  const TetMeshFile g = read_text("v41_vs_22", kMsh22);
  const std::array<int, 6> g_of_f{0, -1, 1, 2, 3, 4};
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 4; ++k) CHECK(g.mesh.tets[t][k] == g_of_f[f.mesh.tets[t][k]]);
}

TEST_CASE("gmsh_reader: a surface-only mesh is a clear error") {
  const std::string what =
      read_error("surface", msh22_with_elements("2\n1 2 2 0 1 10 20 30\n2 2 2 0 1 10 20 40\n"));
  CHECK(starts_with(
      what, temp_path("surface") + ":16: expected 4-node tetrahedra (element type 4), found none"));
  CHECK(contains(what, "surface-only"));
  CHECK(contains(what, "2 triangles"));
  const std::string quadratic =
      read_error("tet10", msh22_with_elements("1\n1 11 0 10 20 30 40 10 20 30 40 10 20\n"));
  CHECK(contains(quadratic, "1 10-node tetrahedra"));
  CHECK(!contains(quadratic, "surface-only"));
}

TEST_CASE("gmsh_reader: errors name the file, the line and what was expected") {
  SUBCASE("binary") {
    const std::string what =
        read_error("binary", "$MeshFormat\n4.1 1 8\n\x01\x00\x00\x00\n$EndMeshFormat\n");
    CHECK(starts_with(what, temp_path("binary") + ":2: expected an ASCII file (file-type 0)"));
    CHECK(contains(what, "binary .msh files are not supported"));
  }
  SUBCASE("unsupported version") {
    const std::string what = read_error("v40", "$MeshFormat\n4 0 8\n$EndMeshFormat\n");
    CHECK(
        starts_with(what, temp_path("v40") + ":2: expected MSH format version 2.2 or 4.1, got 4"));
  }
  SUBCASE("not a msh file") {
    const std::string what = read_error("obj", "v 0 0 0\n");
    CHECK(starts_with(what, temp_path("obj") + ":1: expected a section header"));
  }
  SUBCASE("truncated nodes") {
    const std::string text = kMsh22.substr(0, kMsh22.find("40 0 0 1\n"));
    const std::string what = read_error("trunc", text);
    CHECK(starts_with(what,
                      temp_path("trunc") + ":12: expected node 4 of 5, found the end of the file"));
  }
  SUBCASE("garbled coordinate") {
    std::string text = kMsh22;
    text.replace(text.find("30 0 1 0"), 8, "30 0 1,0");
    const std::string what = read_error("garbled", text);
    CHECK(starts_with(
        what, temp_path("garbled") + ":12: expected '<tag> <x> <y> <z>' (4 fields), got 3 fields"));
  }
  SUBCASE("tet with too few nodes") {
    const std::string what = read_error("short", msh22_with_elements("1\n1 4 2 0 1 10 20 30\n"));
    CHECK(starts_with(what,
                      temp_path("short") + ":18: expected '<tag> 4 <#tags> <tags> <4 node tags>'"));
  }
  SUBCASE("unknown node tag") {
    const std::string what = read_error("tag", msh22_with_elements("1\n1 4 0 10 20 30 60\n"));
    CHECK(
        starts_with(what, temp_path("tag") + ":18: expected the tag of a node of $Nodes, got 60"));
  }
  SUBCASE("missing end tag") {
    std::string text = kMsh22;
    text.replace(text.find("$EndNodes"), 9, "$EndNode");
    const std::string what = read_error("endtag", text);
    CHECK(starts_with(what, temp_path("endtag") + ":15: expected $EndNodes"));
  }
  SUBCASE("4.1 block counts disagree with the header") {
    std::string text = kMsh41;
    text.replace(text.find("3 6 1 6\n2 1 2 2"), 7, "3 7 1 7");
    const std::string what = read_error("count41", text);
    CHECK(contains(what, "expected 7 elements as the section header says, the blocks hold 6"));
  }
  SUBCASE("4.1 truncated element block") {
    const std::string text = kMsh41.substr(0, kMsh41.find("4 2 4 3 5\n"));
    const std::string what = read_error("trunc41", text);
    CHECK(starts_with(what, temp_path("trunc41") + ":35: expected element 2 of 2 in block 2"));
  }
  SUBCASE("no elements section") {
    const std::string text = kMsh22.substr(0, kMsh22.find("$Elements"));
    const std::string what = read_error("noelem", text);
    CHECK(contains(what, "expected an $Elements section"));
  }
  SUBCASE("unclosed unknown section") {
    const std::string what =
        read_error("unclosed", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Comments\nhello\n");
    CHECK(starts_with(what, temp_path("unclosed") +
                                ":5: expected $EndComments to close the section opened on line 4"));
  }
  SUBCASE("degenerate tet") {
    std::string text = kMsh22;
    text.replace(text.find("50 1 1 1"), 8, "50 1 1 0");
    text.replace(text.find("4 4 3 1 1 7 20 40 30 50"), 23, "4 4 3 1 1 7 10 20 30 50");
    const std::string what = read_error("flat", text);
    CHECK(starts_with(what, temp_path("flat") + ":21: expected a tetrahedron of nonzero volume"));
  }
}

// The count of a $Nodes header is checked against the file, not reserved up front: a forged
// 2^31 - 1 would reserve about 50 GB (the same bug tools/fuzz found in the TetGen reader).
TEST_CASE("gmsh_reader: a forged node count is an error, not a huge allocation") {
  const std::string v22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2147483647\n1 0 0 0\n";
  CHECK(starts_with(read_error("big22", v22),
                    temp_path("big22") + ":6: expected node 2 of 2147483647, found the end of the file"));
  const std::string v41 =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2147483647 1 2147483647\n3 1 0 1\n1\n0 0 0\n$EndNodes\n";
  CHECK(contains(read_error("big41", v41),
                 "expected 2147483647 nodes as the section header says, the blocks hold 1"));
}
