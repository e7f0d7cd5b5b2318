// Voxelization: which cells of a regular grid become hexahedra of the simulation lattice.
//
// Grid. Axis-aligned, cubic cells of edge h. Along each axis the grid has
// n = max(1, ceil(extent / h)) cells and is centred on the solid's bounding box, so a box
// whose sides are whole multiples of h is covered exactly by its cells (1 m x 0.1 m x
// 0.1 m at h = 0.05 gives 20 x 2 x 2), and a cylinder of diameter 0.12 m at h = 1/14 m gives
// two cells across, as in paper 000's 56-hex beam. Points that must be embedded but fall
// outside the grid grow it by whole cells.
//
// Shapes (voxelize_shape). A cell is kept when the solid may overlap it, decided with the
// SDF as a lower bound of the distance to the solid: sdf(c) <= 0 at a point c of the cell
// keeps it; sdf(c) > (half diagonal of a box around c) proves that box empty. Undecided
// boxes are split into 8 octants, down to 4 levels (boxes of h/16); a box still undecided
// there is kept. So every cell that holds a point of the solid, in particular of its
// surface, is kept; so are a few cells that only come within sqrt(3) h / 32 of it.
// Points passed as `must_cover` farther than 0.05 h from every kept cell (e.g. vertices of
// the surface mesh, which are off the exact surface by the meshing error) also keep the
// cell that holds them.
//
// Meshes (voxelize_mesh). A cell is kept when its centre is inside the closed surface
// (odd number of crossings of a ray along +x), or when it holds a mesh vertex, so that
// the whole surface can be embedded. Each ray is moved by a tiny fixed offset in y and z
// so that it almost never passes through an edge or vertex; if it does, a top-left
// tie-break on edges evaluated in a canonical order counts the hit exactly once.
//
// Numbering. Cells are ordered by grid coordinates with k slowest and i fastest; nodes
// are the corners of kept cells, numbered in the same grid order.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "engine/geometry/hex_lattice.hpp"

namespace sinew {

namespace {

struct Grid {
  Vec3 origin = Vec3::Zero();
  double h = 0;
  std::array<int, 3> n{0, 0, 0};  // cells per axis

  std::size_t cell_count() const { return std::size_t(n[0]) * n[1] * n[2]; }
  std::size_t cell_index(int i, int j, int k) const {
    return std::size_t(i) + std::size_t(n[0]) * (std::size_t(j) + std::size_t(n[1]) * k);
  }
  Vec3 cell_center(int i, int j, int k) const { return origin + h * Vec3(i + 0.5, j + 0.5, k + 0.5); }
};

constexpr std::size_t kMaxCells = std::size_t(1) << 28;  // dense masks stay below ~300 MB

void check_cell_size(double h) {
  if (!(h > 0) || !std::isfinite(h))
    throw std::invalid_argument("voxelize: cell size must be positive, got " + std::to_string(h));
}

void check_grid_size(const Grid& g) {
  const double cells = double(g.n[0]) * g.n[1] * g.n[2];
  if (cells > double(kMaxCells))
    throw std::invalid_argument("voxelize: cell size " + std::to_string(g.h) +
                                " gives a grid of " + std::to_string(cells) + " cells, too many");
}

// Centred grid with n = max(1, ceil(extent / h)) cells per axis (see the top of the file).
Grid grid_over(const Aabb& b, double h) {
  check_cell_size(h);
  if (b.empty()) throw std::invalid_argument("voxelize: the solid has empty bounds");
  Grid g;
  g.h = h;
  const Vec3 extent = b.hi - b.lo;
  for (int a = 0; a < 3; ++a) {
    // The 1e-9 keeps extent = m h (up to rounding) at m cells, not m + 1.
    const double cells = std::max(1.0, std::ceil(extent[a] / h - 1e-9));
    if (!(cells < 1e9)) throw std::invalid_argument("voxelize: grid too large for cell size");
    g.n[a] = int(cells);
    g.origin[a] = 0.5 * (b.lo[a] + b.hi[a]) - 0.5 * g.n[a] * h;
  }
  check_grid_size(g);
  return g;
}

// Surface-mesh vertices sit off the exact surface by the meshing error, or exactly on a
// grid plane; a point within this many cells of a kept cell embeds there with weights a
// hair outside [0, 1], which is harmless, while a new layer of cells is not.
constexpr double kCoverSlack = 0.05;

// Grows the grid by whole cells so that every point lies in it, one spare cell beyond the
// farthest point so that rounding against the shifted origin cannot leave the grid.
Grid grow_to_cover(Grid g, const std::vector<Vec3>& points) {
  std::array<int, 3> lo{0, 0, 0};
  std::array<int, 3> hi{g.n[0] - 1, g.n[1] - 1, g.n[2] - 1};
  for (const Vec3& p : points) {
    if (!p.allFinite()) throw std::invalid_argument("voxelize: a point to cover is not finite");
    auto c = grid_cell_of(g.origin, g.h, p);
    for (int a = 0; a < 3; ++a) {
      // A point within the slack of the grid's faces (e.g. a vertex on a box face that
      // lies on the last grid plane) needs no new layer of cells.
      const double t = (p[a] - g.origin[a]) / g.h;
      if (t >= -kCoverSlack && t < 0) c[a] = 0;
      if (t >= g.n[a] && t <= g.n[a] + kCoverSlack) c[a] = g.n[a] - 1;
      if (c[a] < lo[a]) lo[a] = c[a] - 1;
      if (c[a] > hi[a]) hi[a] = c[a] + 1;
    }
  }
  for (int a = 0; a < 3; ++a) {
    g.origin[a] += g.h * lo[a];
    g.n[a] = hi[a] - lo[a] + 1;
  }
  check_grid_size(g);
  return g;
}

void mark_cells_holding(const Grid& g, const std::vector<Vec3>& points, std::vector<char>& keep) {
  for (const Vec3& p : points) {
    auto c = grid_cell_of(g.origin, g.h, p);
    // Points on the grid's far faces (e.g. mesh vertices at the bounds' maximum) floor to
    // the cell past the grid: they belong to the last cell, whose closed box holds them.
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(c[a], 0, g.n[a] - 1);
    keep[g.cell_index(c[0], c[1], c[2])] = 1;
  }
}

// Keeps the cell of each point that is farther than kCoverSlack cells from every kept
// cell (see kCoverSlack).

void mark_uncovered_cells(const Grid& g, const std::vector<Vec3>& points, std::vector<char>& keep) {
  const std::vector<char> solid = keep;
  auto kept = [&](const std::array<int, 3>& c) {
    for (int a = 0; a < 3; ++a)
      if (c[a] < 0 || c[a] >= g.n[a]) return false;
    return solid[g.cell_index(c[0], c[1], c[2])] != 0;
  };
  for (const Vec3& p : points) {
    bool covered = false;
    for (int n = 0; n < 27 && !covered; ++n) {
      const Vec3 shift = kCoverSlack * g.h * Vec3(n % 3 - 1, (n / 3) % 3 - 1, n / 9 - 1);
      covered = kept(grid_cell_of(g.origin, g.h, p + shift));
    }
    if (!covered) mark_cells_holding(g, {p}, keep);
  }
}

// Lattice of the kept cells; node ids in grid order over the (n+1)^3 grid points.
HexLattice build_lattice(const Grid& g, const std::vector<char>& keep) {
  HexLattice lat;
  lat.cell_size = g.h;
  lat.origin = g.origin;
  const std::array<int, 3> m{g.n[0] + 1, g.n[1] + 1, g.n[2] + 1};
  auto point_index = [&](int i, int j, int k) {
    return std::size_t(i) + std::size_t(m[0]) * (std::size_t(j) + std::size_t(m[1]) * k);
  };
  std::vector<int> node_id(std::size_t(m[0]) * m[1] * m[2], -1);
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i)
        if (keep[g.cell_index(i, j, k)])
          for (int n = 0; n < 8; ++n) node_id[point_index(i + (n >> 2), j + ((n >> 1) & 1), k + (n & 1))] = 0;
  for (int k = 0; k < m[2]; ++k)
    for (int j = 0; j < m[1]; ++j)
      for (int i = 0; i < m[0]; ++i) {
        int& id = node_id[point_index(i, j, k)];
        if (id < 0) continue;
        id = int(lat.nodes.size());
        lat.nodes.push_back(g.origin + g.h * Vec3(i, j, k));
      }
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i) {
        if (!keep[g.cell_index(i, j, k)]) continue;
        std::array<int, 8> cell{};
        // Paper order: node n = 4a + 2b + c sits at grid point (i + a, j + b, k + c).
        for (int n = 0; n < 8; ++n) cell[n] = node_id[point_index(i + (n >> 2), j + ((n >> 1) & 1), k + (n & 1))];
        lat.cells.push_back(cell);
        lat.cell_coords.push_back({i, j, k});
      }
  return lat;
}

// May the solid overlap the cube of centre c and half edge `half`? The SDF never exceeds
// the distance to the solid, so sdf(c) > sqrt(3) half (the half diagonal) proves the cube
// empty; sdf(c) <= 0 proves it occupied.
bool may_overlap(const Shape& shape, const Vec3& c, double half, int levels_left) {
  const double d = shape.sdf(c);
  if (d <= 0) return true;
  if (d > std::sqrt(3.0) * half) return false;
  if (levels_left == 0) return true;  // undecided at the finest level: keep (conservative)
  const double q = 0.5 * half;
  for (int n = 0; n < 8; ++n) {
    const Vec3 child = c + q * Vec3((n & 4) ? 1 : -1, (n & 2) ? 1 : -1, (n & 1) ? 1 : -1);
    if (may_overlap(shape, child, q, levels_left - 1)) return true;
  }
  return false;
}

constexpr int kOverlapLevels = 4;  // finest test boxes have edge h / 16

HexLattice voxelize_shape_on(const Shape& shape, const Grid& g, const std::vector<Vec3>& must_cover) {
  std::vector<char> keep(g.cell_count(), 0);
  // Cells are independent, so the result does not depend on the thread count.
  tbb::parallel_for(tbb::blocked_range<int>(0, g.n[2]), [&](const tbb::blocked_range<int>& r) {
    for (int k = r.begin(); k < r.end(); ++k)
      for (int j = 0; j < g.n[1]; ++j)
        for (int i = 0; i < g.n[0]; ++i)
          keep[g.cell_index(i, j, k)] = may_overlap(shape, g.cell_center(i, j, k), 0.5 * g.h, kOverlapLevels);
  });
  mark_uncovered_cells(g, must_cover, keep);
  return build_lattice(g, keep);
}

// --- ray parity for meshes -------------------------------------------------------------

struct P2 {
  double y, z;
};

bool lex_less(const P2& a, const P2& b) { return a.y < b.y || (a.y == b.y && a.z < b.z); }

// e(a -> b, x) = (b - a) x (x - a): positive when x is left of a -> b. Always evaluated
// from the lexicographically smaller end, so two triangles sharing an edge get exactly
// opposite values and a ray on the edge is counted by one of them only.
double edge_function(const P2& a, const P2& b, const P2& x) {
  if (lex_less(b, a)) return -edge_function(b, a, x);
  return (b.y - a.y) * (x.z - a.z) - (b.z - a.z) * (x.y - a.y);
}

// Tie-break for a point exactly on edge a -> b of a counter-clockwise triangle: exactly one
// of a -> b and b -> a is "top-left", so a shared edge counts once.
bool top_left(const P2& a, const P2& b) { return b.z < a.z || (b.z == a.z && b.y < a.y); }

bool covers(double e, const P2& a, const P2& b) { return e > 0 || (e == 0 && top_left(a, b)); }

// Fraction of a cell the rays are moved by in y and z: irrational-looking and tiny, so
// that grid-aligned meshes do not put rays through their edges.
constexpr double kRayShiftY = 1.2345678e-7;
constexpr double kRayShiftZ = 2.7182818e-7;

void mark_inside_centres(const TriMesh& mesh, const Grid& g, std::vector<char>& keep) {
  const int ny = g.n[1], nz = g.n[2];
  const double y0 = g.origin.y() + (0.5 + kRayShiftY) * g.h;  // ray of row j is at y0 + j h
  const double z0 = g.origin.z() + (0.5 + kRayShiftZ) * g.h;
  std::vector<std::vector<double>> crossings(std::size_t(ny) * nz);
  const int nv = int(mesh.vertices.size());

  for (const auto& t : mesh.triangles) {
    for (int v : t)
      if (v < 0 || v >= nv) throw std::invalid_argument("voxelize_mesh: triangle index out of range");
    const Vec3& A = mesh.vertices[t[0]];
    Vec3 B = mesh.vertices[t[1]];
    Vec3 C = mesh.vertices[t[2]];
    P2 a{A.y(), A.z()}, b{B.y(), B.z()}, c{C.y(), C.z()};
    const double area2 = edge_function(a, b, c);
    if (area2 == 0) continue;  // parallel to the rays: its neighbours decide
    if (area2 < 0) {           // make the projection counter-clockwise
      std::swap(B, C);
      std::swap(b, c);
    }
    // Rows whose ray passes through the triangle's (y, z) bounding box.
    const double ylo = std::min({a.y, b.y, c.y}), yhi = std::max({a.y, b.y, c.y});
    const double zlo = std::min({a.z, b.z, c.z}), zhi = std::max({a.z, b.z, c.z});
    // One spare row each side: rounding here must not drop a ray that the exact edge tests
    // below would count (e.g. one through a vertex).
    const int j0 = std::max(0, int(std::ceil((ylo - y0) / g.h)) - 1);
    const int j1 = std::min(ny - 1, int(std::floor((yhi - y0) / g.h)) + 1);
    const int k0 = std::max(0, int(std::ceil((zlo - z0) / g.h)) - 1);
    const int k1 = std::min(nz - 1, int(std::floor((zhi - z0) / g.h)) + 1);
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j) {
        const P2 x{y0 + j * g.h, z0 + k * g.h};
        const double wa = edge_function(b, c, x), wb = edge_function(c, a, x), wc = edge_function(a, b, x);
        if (!covers(wa, b, c) || !covers(wb, c, a) || !covers(wc, a, b)) continue;
        // Barycentric weights of the hit are proportional to the edge functions.
        const double s = wa + wb + wc;
        crossings[std::size_t(j) + std::size_t(ny) * k].push_back((wa * A.x() + wb * B.x() + wc * C.x()) / s);
      }
  }

  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      auto& xs = crossings[std::size_t(j) + std::size_t(ny) * k];
      std::sort(xs.begin(), xs.end());
      std::size_t passed = 0;  // crossings left of the current centre
      for (int i = 0; i < g.n[0]; ++i) {
        const double xc = g.origin.x() + (i + 0.5) * g.h;
        while (passed < xs.size() && xs[passed] < xc) ++passed;
        if (passed % 2 == 1) keep[g.cell_index(i, j, k)] = 1;
      }
    }
}

}  // namespace

std::array<int, 3> grid_cell_of(const Vec3& origin, double cell_size, const Vec3& p) {
  std::array<int, 3> c{};
  // Clamped so that far-away points cannot overflow int; no lattice is 2^30 cells wide.
  for (int a = 0; a < 3; ++a) c[a] = int(std::clamp(std::floor((p[a] - origin[a]) / cell_size), -1e9, 1e9));
  return c;
}

HexLattice voxelize_shape(const Shape& shape, double cell_size) {
  return voxelize_shape_on(shape, grid_over(shape.bounds(), cell_size), {});
}

HexLattice voxelize_shape(const Shape& shape, double cell_size, const std::vector<Vec3>& must_cover) {
  const Grid g = grow_to_cover(grid_over(shape.bounds(), cell_size), must_cover);
  return voxelize_shape_on(shape, g, must_cover);
}

HexLattice voxelize_mesh(const TriMesh& mesh, double cell_size) {
  const Grid g = grid_over(mesh.bounds(), cell_size);
  std::vector<char> keep(g.cell_count(), 0);
  mark_inside_centres(mesh, g, keep);
  mark_cells_holding(g, mesh.vertices, keep);
  return build_lattice(g, keep);
}

HexLattice make_box_lattice(const Vec3& origin, double cell_size, int nx, int ny, int nz) {
  check_cell_size(cell_size);
  if (nx < 1 || ny < 1 || nz < 1) throw std::invalid_argument("make_box_lattice: need at least one cell per axis");
  Grid g;
  g.origin = origin;
  g.h = cell_size;
  g.n = {nx, ny, nz};
  check_grid_size(g);
  return build_lattice(g, std::vector<char>(g.cell_count(), 1));
}

}  // namespace sinew
