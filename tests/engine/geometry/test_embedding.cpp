#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <random>

#include "engine/geometry/embedding.hpp"
#include "engine/geometry/hex_lattice.hpp"

using sinew::Embedding;
using sinew::HexLattice;
using sinew::Mat3;
using sinew::Primitive;
using sinew::PrimitiveKind;
using sinew::Shape;
using sinew::Vec3;
using sinew::VecX;

namespace {

// Positions are O(1) and every result is a sum of 8 products of O(1) numbers, so rounding
// stays far below 1e-12; the weights' sum is 1 to a few ulps.
constexpr double kTol = 1e-12;

HexLattice capsule_lattice() {
  Primitive p;
  p.kind = PrimitiveKind::Capsule;
  p.size = Vec3(0.3, 0.5, 0);
  p.center = Vec3(0.1, 0.2, -0.3);
  Shape s;
  s.parts.push_back(p);
  return sinew::voxelize_shape(s, 0.2);
}

VecX flatten(const std::vector<Vec3>& nodes, int offset, double fill) {
  VecX x = VecX::Constant(3 * (offset + int(nodes.size()) + 2), fill);
  for (std::size_t n = 0; n < nodes.size(); ++n) x.segment<3>(3 * (offset + n)) = nodes[n];
  return x;
}

struct CellSamples {
  std::vector<Vec3> points;
  std::vector<int> cells;
  std::vector<Vec3> t;  // natural coordinates in the cell
};

// Random points strictly inside random cells: p = x_0 + h (1 + t) / 2, t in (-1, 1)^3.
CellSamples sample_cells(const HexLattice& lat, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, int(lat.cells.size()) - 1);
  std::uniform_real_distribution<double> u(-0.999, 0.999);
  CellSamples s;
  for (int i = 0; i < count; ++i) {
    const int c = pick(rng);
    const Vec3 t(u(rng), u(rng), u(rng));
    s.points.push_back(lat.nodes[lat.cells[c][0]] + lat.cell_size * 0.5 * (t + Vec3::Ones()));
    s.cells.push_back(c);
    s.t.push_back(t);
  }
  return s;
}

}  // namespace

TEST_CASE("embedding: cells, paper-order weights, partition of unity") {
  const HexLattice lat = capsule_lattice();
  REQUIRE(lat.cells.size() > 10);
  const CellSamples s = sample_cells(lat, 2000, 11);
  const Embedding emb = sinew::embed_points(lat, s.points);
  REQUIRE(emb.cell.size() == s.points.size());
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    CHECK(emb.cell[i] == s.cells[i]);
    double sum = 0;
    for (int n = 0; n < 8; ++n) {
      // w_n = (1 + s1 t1)(1 + s2 t2)(1 + s3 t3) / 8 with s = (2a-1, 2b-1, 2c-1), n = 4a + 2b + c.
      const Vec3 sn(2 * ((n >> 2) & 1) - 1, 2 * ((n >> 1) & 1) - 1, 2 * (n & 1) - 1);
      const double w = (1 + sn.x() * s.t[i].x()) * (1 + sn.y() * s.t[i].y()) * (1 + sn.z() * s.t[i].z()) / 8;
      CHECK(std::abs(emb.weights[i][n] - w) < kTol);
      CHECK(emb.weights[i][n] >= 0);
      sum += emb.weights[i][n];
    }
    CHECK(std::abs(sum - 1) < kTol);
  }
}

TEST_CASE("embedding: rest positions and affine deformations are reproduced exactly") {
  const HexLattice lat = capsule_lattice();
  const CellSamples s = sample_cells(lat, 2000, 12);
  const Embedding emb = sinew::embed_points(lat, s.points);
  const int offset = 5;  // other bodies' nodes come first in x
  std::vector<Vec3> out;

  sinew::compute_embedded_positions(emb, lat, flatten(lat.nodes, offset, 1e6), offset, out);
  REQUIRE(out.size() == s.points.size());
  for (std::size_t i = 0; i < out.size(); ++i) CHECK((out[i] - s.points[i]).norm() < kTol);

  // Trilinear interpolation reproduces every affine map x -> A x + b.
  Mat3 A;
  A << 1.3, -0.4, 0.2, 0.5, 0.8, -0.7, 0.1, 0.6, 1.1;
  const Vec3 b(0.3, -2.0, 0.7);
  std::vector<Vec3> moved;
  for (const Vec3& x : lat.nodes) moved.push_back(A * x + b);
  sinew::compute_embedded_positions(emb, lat, flatten(moved, offset, -1e6), offset, out);
  for (std::size_t i = 0; i < out.size(); ++i) CHECK((out[i] - (A * s.points[i] + b)).norm() < kTol);
}

TEST_CASE("embedding: points outside the lattice go to the nearest cell and extrapolate") {
  const HexLattice lat = capsule_lattice();
  // Far away, just off a face, and exactly on the boundary of the lattice.
  Vec3 lo = lat.nodes[0], hi = lat.nodes[0];
  for (const Vec3& x : lat.nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const std::vector<Vec3> points{Vec3(10, 0.2, -0.3), hi + Vec3(0.01, 0.02, 0.03), Vec3(hi.x(), 0.25, -0.25),
                                 Vec3(lo.x() - 1e-3, 0.2, -0.3)};
  const Embedding emb = sinew::embed_points(lat, points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    double sum = 0;
    for (double w : emb.weights[i]) sum += w;
    CHECK(std::abs(sum - 1) < 1e-9);  // extrapolated weights reach |t| ~ 100 for the far point
  }
  // The far point's nearest cells are the ones at x max; their box is closest to it.
  const auto& c0 = lat.cells[emb.cell[0]];
  CHECK(std::abs(lat.nodes[c0[7]].x() - hi.x()) < kTol);
  // A point on the outer face lies in its cell with t_x = +1: weights of the a = 0 nodes vanish.
  for (int n = 0; n < 4; ++n) CHECK(std::abs(emb.weights[2][n]) < kTol);

  Mat3 A;
  A << 0.9, 0.1, 0, -0.2, 1.2, 0.3, 0, 0.4, 0.7;
  const Vec3 b(1, 2, 3);
  std::vector<Vec3> moved;
  for (const Vec3& x : lat.nodes) moved.push_back(A * x + b);
  std::vector<Vec3> out;
  sinew::compute_embedded_positions(emb, lat, flatten(moved, 0, 0), 0, out);
  for (std::size_t i = 0; i < points.size(); ++i)
    CHECK((out[i] - (A * points[i] + b)).norm() < 1e-9 * (1 + points[i].norm()));
}

TEST_CASE("embedding: the fallback picks the nearest cell box") {
  // Cells of edge 10 chosen from a 3 x 2 x 2 block; distances are whole numbers, so the
  // comparisons below are exact.
  const HexLattice block = sinew::make_box_lattice(Vec3::Zero(), 10, 3, 2, 2);
  auto subset = [&](const std::vector<std::array<int, 3>>& keep) {
    HexLattice lat = block;
    lat.cells.clear();
    lat.cell_coords.clear();
    for (const auto& g : keep)
      for (std::size_t c = 0; c < block.cells.size(); ++c)
        if (block.cell_coords[c] == g) lat.cells.push_back(block.cells[c]), lat.cell_coords.push_back(g);
    REQUIRE(lat.cells.size() == keep.size());
    return lat;
  };
  SUBCASE("equal box distance: nearer centre wins") {
    // p = (5, 7, 6) is in the missing cell (0, 0, 0). Box distance to cell (1, 0, 0) is 5,
    // to cell (0, 1, 1) sqrt(3^2 + 4^2) = 5 too; centres are sqrt(105) and sqrt(145) away.
    const HexLattice lat = subset({{0, 1, 1}, {1, 0, 0}});
    const Embedding emb = sinew::embed_points(lat, {Vec3(5, 7, 6)});
    CHECK(emb.cell[0] == 1);
  }
  SUBCASE("nearest cell outside the 3x3x3 neighbourhood") {
    // p = (9.5, 0.5, 0.5): cell (2, 0, 0) is 10.5 away, the neighbour (1, 1, 1) 13.4.
    const HexLattice lat = subset({{1, 1, 1}, {2, 0, 0}});
    const Embedding emb = sinew::embed_points(lat, {Vec3(9.5, 0.5, 0.5)});
    CHECK(emb.cell[0] == 1);
  }
}

TEST_CASE("embedding: results do not depend on the thread count") {
  const HexLattice lat = capsule_lattice();
  const CellSamples s = sample_cells(lat, 200000, 13);
  const Embedding emb = sinew::embed_points(lat, s.points);
  std::vector<Vec3> moved;
  for (const Vec3& x : lat.nodes) moved.push_back(x + 0.1 * Vec3(std::sin(7 * x.y()), x.x() * x.z(), std::cos(x.x())));
  const VecX x = flatten(moved, 0, 0);
  std::vector<Vec3> serial, parallel;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    sinew::compute_embedded_positions(emb, lat, x, 0, serial);
  }
  sinew::compute_embedded_positions(emb, lat, x, 0, parallel);
  REQUIRE(serial.size() == parallel.size());
  bool identical = true;
  for (std::size_t i = 0; i < serial.size(); ++i) identical = identical && serial[i] == parallel[i];
  CHECK(identical);
}
