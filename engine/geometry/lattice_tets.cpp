// Kuhn split of every lattice cell into 6 tets (see lattice_tets.hpp).
#include "engine/geometry/lattice_tets.hpp"

#include <algorithm>

namespace sinew {

namespace {

// Cell node of grid offset (a, b, c): n = 4a + 2b + c.
constexpr int cell_node(int a, int b, int c) { return 4 * a + 2 * b + c; }

std::array<std::array<int, 4>, 6> build_kuhn_tets() {
  std::array<std::array<int, 4>, 6> tets{};
  std::array<int, 3> axes{0, 1, 2};
  int t = 0;
  do {
    // Walk (0,0,0) -> (1,1,1) stepping along axes[0], then axes[1], then axes[2].
    std::array<int, 3> g{0, 0, 0};
    std::array<int, 4> tet{};
    tet[0] = cell_node(0, 0, 0);
    for (int s = 0; s < 3; ++s) {
      g[axes[s]] = 1;
      tet[s + 1] = cell_node(g[0], g[1], g[2]);
    }
    // Edge vectors e_axes[0], e_axes[0] + e_axes[1], (1,1,1): det = sign of the
    // permutation (unit volume / 6 in cell units). Odd permutations are swapped.
    const int inversions = (axes[0] > axes[1]) + (axes[0] > axes[2]) + (axes[1] > axes[2]);
    if (inversions % 2) std::swap(tet[2], tet[3]);
    tets[t++] = tet;
  } while (std::next_permutation(axes.begin(), axes.end()));
  return tets;
}

}  // namespace

const std::array<std::array<int, 4>, 6>& kuhn_cell_tets() {
  static const std::array<std::array<int, 4>, 6> tets = build_kuhn_tets();
  return tets;
}

LatticeTets split_lattice_into_tets(const HexLattice& lattice) {
  LatticeTets out;
  out.mesh.nodes = lattice.nodes;
  out.mesh.tets.reserve(lattice.cells.size() * 6);
  out.tet_cell.reserve(lattice.cells.size() * 6);
  const auto& local = kuhn_cell_tets();
  for (std::size_t c = 0; c < lattice.cells.size(); ++c)
    for (const auto& lt : local) {
      out.mesh.tets.push_back({lattice.cells[c][lt[0]], lattice.cells[c][lt[1]],
                               lattice.cells[c][lt[2]], lattice.cells[c][lt[3]]});
      out.tet_cell.push_back(int(c));
    }
  return out;
}

}  // namespace sinew
