#pragma once
// Surface vertices embedded in lattice cells by trilinear weights (paper 000, fig. 1).
#include "engine/geometry/hex_lattice.hpp"

namespace sinew {

struct Embedding {
  std::vector<int> cell;                      // per point: index into lattice.cells
  std::vector<std::array<double, 8>> weights;  // per point: trilinear weights, paper node order
};

// Each point goes to the cell that contains it; a point outside every cell goes to the
// nearest cell (weights then extrapolate). Weights sum to one.
Embedding embed_points(const HexLattice& lattice, const std::vector<Vec3>& points);

// Deformed positions of embedded points given node positions x (3 * nodes, xyz per node,
// starting at node_offset in x). Writes out[i] for every embedded point.
void compute_embedded_positions(const Embedding& embedding, const HexLattice& lattice,
                                const VecX& x, int node_offset, std::vector<Vec3>& out);

}  // namespace sinew
