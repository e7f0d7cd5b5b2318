#include <doctest/doctest.h>

#include "engine/geometry/tet_mesh.hpp"

using namespace sinew;

namespace {

// Volume enclosed by a closed triangle surface, sum of a . (b x c) / 6 (divergence
// theorem): positive when the triangles are wound CCW seen from outside.
double enclosed_volume(const TriMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles)
    v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
  return v;
}

double total_volume(const TetMesh& m) {
  double v = 0;
  for (const auto& t : m.tets)
    v += tet_signed_volume(m.nodes[t[0]], m.nodes[t[1]], m.nodes[t[2]], m.nodes[t[3]]);
  return v;
}

// Two tets sharing the face (1, 2, 3), plus an unused node 5 and the origin moved off 0.
TetMesh two_tets() {
  TetMesh m;
  m.nodes = {Vec3(0.1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
             Vec3(0, 0, 1),   Vec3(1, 1, 1), Vec3(9, 9, 9)};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  return m;
}

}  // namespace

TEST_CASE("tet_mesh: outward face table") {
  // Unit corner tet: face f is opposite node 3 - f and its normal points away from it.
  const std::array<Vec3, 4> X{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  for (int f = 0; f < 4; ++f) {
    const auto& face = kTetOutwardFaces[f];
    for (int i : face) CHECK(i != 3 - f);
    const Vec3 n = (X[face[1]] - X[face[0]]).cross(X[face[2]] - X[face[0]]);
    CHECK(n.dot(X[3 - f] - X[face[0]]) < 0);
  }
}

TEST_CASE("tet_mesh: orient_tets_positively swaps inverted tets and reports degenerate ones") {
  TetMesh m = two_tets();
  m.tets[1] = {1, 3, 2, 4};               // inverted
  m.tets.push_back({0, 1, 2, 2});         // repeated node: zero volume
  m.nodes.push_back(Vec3(0.55, 0.5, 0));  // node 6: in the plane of nodes 0, 1, 2
  m.tets.push_back({0, 1, 2, 6});         // flat
  std::vector<int> degenerate;
  CHECK(orient_tets_positively(m, &degenerate) == 1);
  CHECK(degenerate == std::vector<int>{2, 3});
  CHECK(m.tets[1] == std::array<int, 4>{1, 3, 4, 2});
  for (int t : {0, 1})
    CHECK(tet_signed_volume(m.nodes[m.tets[t][0]], m.nodes[m.tets[t][1]], m.nodes[m.tets[t][2]],
                            m.nodes[m.tets[t][3]]) > 0);
  CHECK(orient_tets_positively(m) == 0);  // idempotent
}

TEST_CASE("tet_mesh: boundary surface of one and two tets") {
  TetMesh one;
  one.nodes = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  one.tets = {{0, 1, 2, 3}};
  const TetSurface s1 = tet_boundary_surface(one);
  CHECK(s1.mesh.triangles.size() == 4);
  CHECK(s1.mesh.vertices.size() == 4);
  CHECK(count_open_edges(s1.mesh) == 0);
  CHECK(enclosed_volume(s1.mesh) == doctest::Approx(1.0 / 6));

  const TetMesh two = two_tets();
  const TetSurface s2 = tet_boundary_surface(two);
  CHECK(s2.mesh.triangles.size() == 6);   // the shared face is interior
  REQUIRE(s2.mesh.vertices.size() == 5);  // node 5 is used by no tet
  CHECK(s2.node_of_vertex == std::vector<int>{0, 1, 2, 3, 4});
  for (std::size_t v = 0; v < s2.mesh.vertices.size(); ++v)
    CHECK(s2.mesh.vertices[v] == two.nodes[s2.node_of_vertex[v]]);
  CHECK(count_open_edges(s2.mesh) == 0);
  CHECK(enclosed_volume(s2.mesh) == doctest::Approx(total_volume(two)).epsilon(1e-14));
  CHECK(count_unreferenced_nodes(two) == 1);
}

TEST_CASE("tet_mesh: boundary renumbering skips interior nodes") {
  // A tet split into 4 around an interior node 4: the boundary is the outer tet only.
  TetMesh m;
  m.nodes = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0.2, 0.2, 0.2)};
  for (const auto& f : kTetOutwardFaces)
    m.tets.push_back({f[0], f[2], f[1], 4});  // inward face + apex
  CHECK(orient_tets_positively(m) == 0);
  const TetSurface s = tet_boundary_surface(m);
  CHECK(s.mesh.triangles.size() == 4);
  CHECK(s.node_of_vertex == std::vector<int>{0, 1, 2, 3});
  CHECK(count_open_edges(s.mesh) == 0);
  CHECK(enclosed_volume(s.mesh) == doctest::Approx(1.0 / 6));
  CHECK(total_volume(m) == doctest::Approx(1.0 / 6));
}
