#pragma once
// Embedded surface vertices grouped by the lattice cell that carries them, so that the
// contact broad phase tests a few hundred cells instead of every surface vertex.
#include "engine/geometry/embedding.hpp"

namespace sinew {

struct SurfaceCells {
  std::vector<int> begin;      // cells + 1: each cell's range in `vertices`
  std::vector<int> vertices;   // surface vertex indices, ascending within a cell
  // Per cell, s = max over its vertices of (sum_n |w_n| - 1) / 2: 0 when every weight is
  // in [0, 1], larger for vertices embedded by extrapolation (outside every cell).
  std::vector<double> spread;
  double max_spread = 0;
};

SurfaceCells group_surface_by_cell(const Embedding& embedding, int num_cells);

// Box that holds every vertex of a cell (or body) whose nodes span `nodes` and whose
// spread is s. With P = sum of the positive weights = 1 + s and N = s the negative ones,
// p = sum_n w_n x_n = a + s (a - b) with a, b convex combinations of the nodes, both in
// `nodes`; so p lies in `nodes` grown by s times its extent on each axis.
Aabb grow_by_spread(const Aabb& nodes, double s);

}  // namespace sinew
