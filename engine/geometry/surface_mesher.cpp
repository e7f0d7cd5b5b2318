// Surface meshing of an SDF by marching tetrahedra.
//
// Each grid cube is split into 6 tetrahedra around its main diagonal (0,0,0)-(1,1,1)
// (Kuhn triangulation). Neighbouring cubes then split their shared face the same way, so
// the piecewise-linear SDF is continuous and its zero set is a closed, manifold surface:
// no lookup tables and no ambiguous cases. Vertices sit on tetrahedron edges by linear
// interpolation and are shared through the edge's id. Grid values that are exactly 0
// count as outside (nudged to a tiny positive value), so no vertex sits on a grid point
// where several surface pieces would meet.
#include "engine/geometry/surface_mesher.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace sinew {

namespace {

using Int3 = std::array<int, 3>;

// Corner offsets (bit 2 = x, bit 1 = y, bit 0 = z) of the 6 Kuhn tetrahedra: each walks
// from corner 0 to corner 7 adding one axis at a time, in one of the 6 axis orders.
constexpr int kTets[6][4] = {{0, 4, 6, 7}, {0, 4, 5, 7}, {0, 2, 6, 7},
                             {0, 2, 3, 7}, {0, 1, 5, 7}, {0, 1, 3, 7}};

Int3 corner_offset(int c) { return {(c >> 2) & 1, (c >> 1) & 1, c & 1}; }

struct SampleGrid {
  Vec3 origin = Vec3::Zero();
  double h = 0;
  Int3 m{0, 0, 0};  // grid points per axis
  std::vector<double> f;

  std::int64_t index(int i, int j, int k) const { return i + std::int64_t(m[0]) * (j + std::int64_t(m[1]) * k); }
  Vec3 point(int i, int j, int k) const { return origin + h * Vec3(i, j, k); }
};

// Grid over the bounds with at least one spacing of margin on each side: every grid
// point on the border is outside the solid, so the iso-surface cannot reach the border
// and comes out closed.
SampleGrid sample_shape(const Shape& shape, double h) {
  if (!(h > 0) || !std::isfinite(h))
    throw std::invalid_argument("mesh_shape_surface: resolution must be positive, got " + std::to_string(h));
  const Aabb b = shape.bounds();
  if (b.empty()) throw std::invalid_argument("mesh_shape_surface: the shape has no parts");
  SampleGrid g;
  g.h = h;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::ceil((b.hi[a] - b.lo[a]) / h) + 2;
    if (!(cells < 1e5)) throw std::invalid_argument("mesh_shape_surface: resolution too fine for the shape");
    g.m[a] = int(cells) + 1;
    g.origin[a] = 0.5 * (b.lo[a] + b.hi[a]) - 0.5 * cells * h;
  }
  const double total = double(g.m[0]) * g.m[1] * g.m[2];
  if (total > double(std::int64_t(1) << 28))
    throw std::invalid_argument("mesh_shape_surface: resolution " + std::to_string(h) + " needs too many samples");
  g.f.resize(std::size_t(total));
  const double nudge = 1e-12 * h;
  tbb::parallel_for(tbb::blocked_range<int>(0, g.m[2]), [&](const tbb::blocked_range<int>& r) {
    for (int k = r.begin(); k < r.end(); ++k)
      for (int j = 0; j < g.m[1]; ++j)
        for (int i = 0; i < g.m[0]; ++i) {
          const double d = shape.sdf(g.point(i, j, k));
          g.f[g.index(i, j, k)] = d == 0 ? nudge : d;
        }
  });
  return g;
}

class TetMarcher {
 public:
  explicit TetMarcher(const SampleGrid& g) : g_(g) {}

  void march_cube(int i, int j, int k) {
    double f[8];
    std::int64_t id[8];
    int inside = 0;
    for (int c = 0; c < 8; ++c) {
      const Int3 o = corner_offset(c);
      id[c] = g_.index(i + o[0], j + o[1], k + o[2]);
      f[c] = g_.f[id[c]];
      inside += f[c] < 0;
    }
    if (inside == 0 || inside == 8) return;
    for (const auto& tet : kTets) march_tet(tet, f, id);
  }

  TriMesh take() { return std::move(mesh_); }

 private:
  // Polygon of a tetrahedron's iso-surface as (inside corner, outside corner) edges in
  // cyclic order, oriented so that its normal points from the inside corners to the
  // outside ones (towards increasing SDF).
  void march_tet(const int (&tet)[4], const double (&f)[8], const std::int64_t (&id)[8]) {
    int in[4], out[4], n_in = 0, n_out = 0;
    for (int c : tet) (f[c] < 0 ? in[n_in++] : out[n_out++]) = c;
    if (n_in == 0 || n_out == 0) return;
    int edges[4][2];
    int n_edges = 0;
    if (n_in == 1) {
      for (int o = 0; o < 3; ++o) edges[n_edges][0] = in[0], edges[n_edges++][1] = out[o];
    } else if (n_in == 3) {
      for (int a = 0; a < 3; ++a) edges[n_edges][0] = in[a], edges[n_edges++][1] = out[0];
    } else {
      // Quad: each consecutive pair shares a corner, so this is its boundary in order.
      const int q[4][2] = {{in[0], out[0]}, {in[0], out[1]}, {in[1], out[1]}, {in[1], out[0]}};
      for (const auto& e : q) edges[n_edges][0] = e[0], edges[n_edges++][1] = e[1];
    }
    if (!points_outward(edges, in, n_in, out, n_out)) {
      std::reverse(edges, edges + n_edges);
    }
    int v[4];
    for (int e = 0; e < n_edges; ++e) v[e] = edge_vertex(edges[e][0], edges[e][1], f, id);
    if (n_edges == 3) {
      mesh_.triangles.push_back({v[0], v[1], v[2]});
    } else {
      // Split the quad along its shorter diagonal; either keeps the mesh closed.
      const auto& P = mesh_.vertices;
      if ((P[v[0]] - P[v[2]]).squaredNorm() <= (P[v[1]] - P[v[3]]).squaredNorm()) {
        mesh_.triangles.push_back({v[0], v[1], v[2]});
        mesh_.triangles.push_back({v[0], v[2], v[3]});
      } else {
        mesh_.triangles.push_back({v[0], v[1], v[3]});
        mesh_.triangles.push_back({v[1], v[2], v[3]});
      }
    }
  }

  // Orientation is decided on the polygon through the edge midpoints, in exact integer
  // arithmetic on doubled corner offsets: it has the same orientation as the real polygon
  // (both separate the same corners) but never degenerates, even where the real one does.
  // Test: ((m1 - m0) x (m2 - m0)) . (n_in sum(out) - n_out sum(in)) > 0.
  static bool points_outward(const int (&edges)[4][2], const int* in, int n_in, const int* out, int n_out) {
    auto mid2 = [](int a, int b) {
      const Int3 oa = corner_offset(a), ob = corner_offset(b);
      return Int3{oa[0] + ob[0], oa[1] + ob[1], oa[2] + ob[2]};
    };
    const Int3 m0 = mid2(edges[0][0], edges[0][1]), m1 = mid2(edges[1][0], edges[1][1]),
               m2 = mid2(edges[2][0], edges[2][1]);
    const Int3 u{m1[0] - m0[0], m1[1] - m0[1], m1[2] - m0[2]};
    const Int3 w{m2[0] - m0[0], m2[1] - m0[1], m2[2] - m0[2]};
    const Int3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    Int3 d{0, 0, 0};
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < n_out; ++c) d[a] += n_in * corner_offset(out[c])[a];
      for (int c = 0; c < n_in; ++c) d[a] -= n_out * corner_offset(in[c])[a];
    }
    return n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > 0;
  }

  // Vertex where the linear SDF vanishes on the edge between corners a (inside) and
  // b (outside): x = x_a + t (x_b - x_a), t = f_a / (f_a - f_b). Shared by edge id.
  int edge_vertex(int a, int b, const double (&f)[8], const std::int64_t (&id)[8]) {
    // Kuhn edges go from a corner to one with all offsets >= : the lower corner and the
    // offset bits name the edge uniquely.
    const int lo = std::min(a, b), hi = std::max(a, b);
    const std::int64_t key = id[lo] * 8 + (hi - lo);
    const auto [it, fresh] = vertex_of_edge_.try_emplace(key, int(mesh_.vertices.size()));
    if (fresh) {
      const double t = f[lo] / (f[lo] - f[hi]);
      const Vec3 x_lo = grid_point(id[lo]);
      const Vec3 x_hi = grid_point(id[hi]);
      mesh_.vertices.push_back(x_lo + t * (x_hi - x_lo));
    }
    return it->second;
  }

  Vec3 grid_point(std::int64_t idx) const {
    const int i = int(idx % g_.m[0]);
    const int j = int((idx / g_.m[0]) % g_.m[1]);
    const int k = int(idx / (std::int64_t(g_.m[0]) * g_.m[1]));
    return g_.point(i, j, k);
  }

  const SampleGrid& g_;
  TriMesh mesh_;
  std::unordered_map<std::int64_t, int> vertex_of_edge_;
};

}  // namespace

TriMesh mesh_shape_surface(const Shape& shape, double resolution) {
  const SampleGrid g = sample_shape(shape, resolution);
  TetMarcher marcher(g);
  // Serial, in grid order: vertex and triangle numbering is deterministic.
  for (int k = 0; k + 1 < g.m[2]; ++k)
    for (int j = 0; j + 1 < g.m[1]; ++j)
      for (int i = 0; i + 1 < g.m[0]; ++i) marcher.march_cube(i, j, k);
  return marcher.take();
}

}  // namespace sinew
