// Embedding of points in lattice cells: cell lookup and trilinear weights.
#include "engine/geometry/embedding.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace sinew {

namespace {

// Grid coordinates are packed 21 bits each; lattices are far smaller than 2^20 cells wide.
constexpr int kCoordBias = 1 << 20;

bool pack_coords(const std::array<int, 3>& c, std::uint64_t& key) {
  key = 0;
  for (int a = 0; a < 3; ++a) {
    const long v = long(c[a]) + kCoordBias;
    if (v < 0 || v >= 2L * kCoordBias) return false;
    key = (key << 21) | std::uint64_t(v);
  }
  return true;
}

using CellMap = std::unordered_map<std::uint64_t, int>;

CellMap map_cells(const HexLattice& lattice) {
  CellMap map;
  map.reserve(lattice.cells.size());
  for (int c = 0; c < int(lattice.cell_coords.size()); ++c) {
    std::uint64_t key = 0;
    if (!pack_coords(lattice.cell_coords[c], key))
      throw std::invalid_argument("embed_points: lattice cell coordinates out of range");
    map.emplace(key, c);  // first cell wins if a lattice ever repeats coordinates
  }
  return map;
}

int find_cell(const CellMap& map, const std::array<int, 3>& c) {
  std::uint64_t key = 0;
  if (!pack_coords(c, key)) return -1;
  const auto it = map.find(key);
  return it == map.end() ? -1 : it->second;
}

// Rest box of a cell: node 0 (s = -1,-1,-1) to node 7 (s = +1,+1,+1).
double box_distance_sq(const HexLattice& lat, int cell, const Vec3& p) {
  const Vec3& lo = lat.nodes[lat.cells[cell][0]];
  const Vec3& hi = lat.nodes[lat.cells[cell][7]];
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}

double centre_distance_sq(const HexLattice& lat, int cell, const Vec3& p) {
  return (0.5 * (lat.nodes[lat.cells[cell][0]] + lat.nodes[lat.cells[cell][7]]) - p).squaredNorm();
}

// Nearer by box distance, then by centre distance, then lower index: a total order, so the
// choice does not depend on search order.
bool nearer(const HexLattice& lat, const Vec3& p, int a, int b) {
  if (b < 0) return true;
  const double da = box_distance_sq(lat, a, p), db = box_distance_sq(lat, b, p);
  if (da != db) return da < db;
  const double ca = centre_distance_sq(lat, a, p), cb = centre_distance_sq(lat, b, p);
  if (ca != cb) return ca < cb;
  return a < b;
}

// Cell for a point outside every kept cell (or on the outer face of one). A cell of the
// 3x3x3 block around the point's grid cell within distance h beats every cell outside the
// block (those are at least h away); otherwise search all cells.
int nearest_cell(const HexLattice& lat, const CellMap& map, const std::array<int, 3>& c, const Vec3& p) {
  int best = -1;
  for (int dk = -1; dk <= 1; ++dk)
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const int cell = find_cell(map, {c[0] + di, c[1] + dj, c[2] + dk});
        if (cell >= 0 && nearer(lat, p, cell, best)) best = cell;
      }
  const double h = lat.cell_size;
  if (best >= 0 && box_distance_sq(lat, best, p) < h * h) return best;
  for (int cell = 0; cell < int(lat.cells.size()); ++cell)
    if (nearer(lat, p, cell, best)) best = cell;
  return best;
}

// Trilinear shape functions in paper order:
// w_n = (1 + s_n1 t1)(1 + s_n2 t2)(1 + s_n3 t3) / 8,  s_n = (2a-1, 2b-1, 2c-1), n = 4a + 2b + c.
std::array<double, 8> trilinear_weights(const Vec3& t) {
  std::array<double, 8> w{};
  for (int n = 0; n < 8; ++n) {
    const double s1 = (n & 4) ? 1 : -1, s2 = (n & 2) ? 1 : -1, s3 = (n & 1) ? 1 : -1;
    w[n] = (1 + s1 * t.x()) * (1 + s2 * t.y()) * (1 + s3 * t.z()) / 8;
  }
  return w;
}

}  // namespace

Embedding embed_points(const HexLattice& lattice, const std::vector<Vec3>& points) {
  if (lattice.cells.empty()) throw std::invalid_argument("embed_points: the lattice has no cells");
  if (lattice.cell_coords.size() != lattice.cells.size())
    throw std::invalid_argument("embed_points: lattice cell_coords and cells differ in size");
  const CellMap map = map_cells(lattice);
  Embedding emb;
  emb.cell.resize(points.size());
  emb.weights.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    if (!p.allFinite()) throw std::invalid_argument("embed_points: point " + std::to_string(i) + " is not finite");
    const auto c = grid_cell_of(lattice.origin, lattice.cell_size, p);
    int cell = find_cell(map, c);
    if (cell < 0) cell = nearest_cell(lattice, map, c, p);
    // Natural coordinates t in [-1, 1]^3 inside the cell (beyond it for the fallback).
    const Vec3& lo = lattice.nodes[lattice.cells[cell][0]];
    const Vec3& hi = lattice.nodes[lattice.cells[cell][7]];
    const Vec3 t = (2 * (p - lo)).cwiseQuotient(hi - lo) - Vec3::Ones();
    emb.cell[i] = cell;
    emb.weights[i] = trilinear_weights(t);
  }
  return emb;
}

void compute_embedded_positions(const Embedding& embedding, const HexLattice& lattice, const VecX& x,
                                int node_offset, std::vector<Vec3>& out) {
  if (node_offset < 0 || x.size() < 3 * (Eigen::Index(node_offset) + Eigen::Index(lattice.nodes.size())))
    throw std::invalid_argument("compute_embedded_positions: x is too short for the lattice nodes");
  const std::size_t n = embedding.cell.size();
  out.resize(n);
  // Each point is written by one task only: results do not depend on the thread count.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      const auto& cell = lattice.cells[embedding.cell[i]];
      const auto& w = embedding.weights[i];
      Vec3 sum = Vec3::Zero();
      for (int k = 0; k < 8; ++k)
        if (cell[k] >= 0) sum += w[k] * x.segment<3>(3 * (Eigen::Index(node_offset) + cell[k]));
      out[i] = sum;
    }
  });
}

}  // namespace sinew
