#pragma once
// A tetrahedral mesh: the simulation mesh of a tet body (paper 001, sec. 3.1).
//
// Every tet (X0, X1, X2, X3) is positively oriented: det[X1-X0, X2-X0, X3-X0] = 6 V > 0.
// (Paper 001 eq. 1 builds its volume matrix from x4 as the base node; here node 0 is the
// base. The two differ by a relabelling of the nodes only.)
#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "engine/core/types.hpp"
#include "engine/geometry/tri_mesh.hpp"

namespace sinew {

struct TetMesh {
  std::vector<Vec3> nodes;               // rest positions
  std::vector<std::array<int, 4>> tets;  // node indices, positively oriented
};

// V = det[x1-x0, x2-x0, x3-x0] / 6 (negative for an inverted tet).
inline double tet_signed_volume(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  return (x1 - x0).dot((x2 - x0).cross(x3 - x0)) / 6;
}

// A tet is degenerate when |6 V| <= kDegenerateTet * L^3, L its longest edge (a flat or
// needle tet, or repeated nodes): no orientation makes it usable.
inline constexpr double kDegenerateTet = 1e-12;

// Makes every tet positively oriented by swapping its nodes 2 and 3 where det < 0, and
// returns how many were swapped. Degenerate tets are left as they are; their indices are
// appended to `degenerate` when given (readers turn the first one into an InputError).
int orient_tets_positively(TetMesh& mesh, std::vector<int>* degenerate = nullptr);

// Nodes no tet uses (they would get no mass and no stiffness).
int count_unreferenced_nodes(const TetMesh& mesh);

// What a tet mesh reader returns: the mesh, positively oriented, and what it fixed.
struct TetMeshFile {
  TetMesh mesh;
  int reoriented = 0;          // tets given with det < 0, their nodes 2 and 3 swapped
  int unreferenced_nodes = 0;  // nodes of the file no tet uses (kept, in file order)
};

// Boundary of a tet mesh: the faces used by exactly one tet, wound counter-clockwise seen
// from outside, over the nodes that lie on the boundary, renumbered 0..m-1 in node order.
struct TetSurface {
  TriMesh mesh;                     // vertices = rest positions of the boundary nodes
  std::vector<int> node_of_vertex;  // surface vertex -> tet node (size m, increasing)
};
TetSurface tet_boundary_surface(const TetMesh& mesh);

// The 4 faces of tet (0, 1, 2, 3), each wound CCW seen from outside when the tet is
// positively oriented (face f is opposite node 3 - f).
inline constexpr std::array<std::array<int, 3>, 4> kTetOutwardFaces{
    {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};

}  // namespace sinew
