#include "engine/collision/surface_cells.hpp"

#include <algorithm>
#include <cmath>

namespace sinew {

SurfaceCells group_surface_by_cell(const Embedding& embedding, int num_cells) {
  SurfaceCells out;
  out.begin.assign(num_cells + 1, 0);
  out.spread.assign(num_cells, 0.0);
  const int n = static_cast<int>(embedding.cell.size());
  // Counting sort by cell keeps vertex order ascending inside each cell.
  for (int i = 0; i < n; ++i) ++out.begin[embedding.cell[i] + 1];
  for (int c = 0; c < num_cells; ++c) out.begin[c + 1] += out.begin[c];
  out.vertices.resize(n);
  std::vector<int> next(out.begin.begin(), out.begin.end() - 1);
  for (int i = 0; i < n; ++i) {
    const int c = embedding.cell[i];
    out.vertices[next[c]++] = i;
    double sum = 0;
    for (double w : embedding.weights[i]) sum += std::abs(w);
    out.spread[c] = std::max(out.spread[c], 0.5 * (sum - 1));
  }
  for (double s : out.spread) out.max_spread = std::max(out.max_spread, s);
  return out;
}

Aabb grow_by_spread(const Aabb& nodes, double s) {
  const Vec3 grow = s * (nodes.hi - nodes.lo);
  return {nodes.lo - grow, nodes.hi + grow};
}

}  // namespace sinew
