#pragma once
// Tetrahedralization of a hex lattice: every cell is split into the same 6 tets (the Kuhn /
// Freudenthal split), sharing the lattice's nodes.
//
// With cell node n = 4a + 2b + c at grid offset (a, b, c) (hex_lattice.hpp), the 6 tets are
// the monotone paths from node 0 = (0,0,0) to node 7 = (1,1,1) that add one unit step per
// axis, one tet per order of the axes: {0, e_i, e_i + e_j, 7} for the 6 permutations (i, j, k).
// All 6 share the main diagonal 0-7 and have volume h^3 / 6. On a cell face the split draws
// the diagonal from the face's lowest to its highest corner, the same as the neighbouring
// cell draws it, because the split is the same in every cell: the tets conform across
// cells (no hanging edges, each interior face shared by exactly 2 tets).
#include <vector>

#include "engine/geometry/hex_lattice.hpp"
#include "engine/geometry/tet_mesh.hpp"

namespace sinew {

struct LatticeTets {
  TetMesh mesh;                  // nodes = lattice.nodes; tets positively oriented
  std::vector<int> tet_cell;  // tet -> lattice cell it came from (6 per cell, in order)
};

LatticeTets split_lattice_into_tets(const HexLattice& lattice);

// The 6 tets of one cell as cell node numbers (0..7), positively oriented.
const std::array<std::array<int, 4>, 6>& kuhn_cell_tets();

}  // namespace sinew
