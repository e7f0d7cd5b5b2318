#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <set>

#include "engine/geometry/embedding.hpp"
#include "engine/geometry/hex_lattice.hpp"
#include "engine/geometry/obj_reader.hpp"
#include "engine/geometry/surface_mesher.hpp"

using sinew::HexLattice;
using sinew::Mat3;
using sinew::Primitive;
using sinew::PrimitiveKind;
using sinew::Shape;
using sinew::TriMesh;
using sinew::Vec3;

namespace {

using Coords = std::array<int, 3>;

Shape one_part(PrimitiveKind kind, const Vec3& size, const Vec3& center = Vec3::Zero(),
               const Mat3& rotation = Mat3::Identity()) {
  Primitive p;
  p.kind = kind;
  p.size = size;
  p.center = center;
  p.rotation = rotation;
  Shape s;
  s.parts.push_back(p);
  return s;
}

std::set<Coords> kept_cells(const HexLattice& lat) {
  return std::set<Coords>(lat.cell_coords.begin(), lat.cell_coords.end());
}

// Node n = 4a + 2b + c of cell (i, j, k) sits at origin + h (i + a, j + b, k + c); nodes are
// unique and each is used by some cell. Positions are origin + h * small integers: 1e-12
// relative covers the rounding.
void check_lattice_structure(const HexLattice& lat) {
  const double tol = 1e-12 * (1 + lat.origin.norm() + lat.cell_size * 1e3);
  REQUIRE(lat.cells.size() == lat.cell_coords.size());
  std::vector<int> uses(lat.nodes.size(), 0);
  for (std::size_t c = 0; c < lat.cells.size(); ++c) {
    const Coords& g = lat.cell_coords[c];
    const Vec3 corner = lat.origin + lat.cell_size * Vec3(g[0], g[1], g[2]);
    for (int n = 0; n < 8; ++n) {
      const int node = lat.cells[c][n];
      REQUIRE(node >= 0);
      REQUIRE(node < int(lat.nodes.size()));
      ++uses[node];
      const Vec3 abc((n >> 2) & 1, (n >> 1) & 1, n & 1);
      CHECK((lat.nodes[node] - corner - lat.cell_size * abc).norm() < tol);
    }
  }
  CHECK(std::count(uses.begin(), uses.end(), 0) == 0);
  std::set<std::array<long long, 3>> distinct;  // nodes on the grid: round to grid units
  for (const Vec3& x : lat.nodes) {
    const Vec3 u = (x - lat.origin) / lat.cell_size;
    distinct.insert({std::llround(u.x()), std::llround(u.y()), std::llround(u.z())});
  }
  CHECK(distinct.size() == lat.nodes.size());
  CHECK(kept_cells(lat).size() == lat.cells.size());
}

// Natural coordinates of p in its embedding cell: t = 2 (p - x_0) / h - 1.
Vec3 natural_coords(const HexLattice& lat, int cell, const Vec3& p) {
  return 2 * (p - lat.nodes[lat.cells[cell][0]]) / lat.cell_size - Vec3::Ones();
}

}  // namespace

TEST_CASE("voxelize: box lattice counts, node order and shared nodes") {
  const int nx = 3, ny = 4, nz = 5;
  const HexLattice lat = sinew::make_box_lattice(Vec3(-1, 0.5, 2), 0.25, nx, ny, nz);
  CHECK(lat.cells.size() == std::size_t(nx * ny * nz));
  CHECK(lat.nodes.size() == std::size_t((nx + 1) * (ny + 1) * (nz + 1)));
  check_lattice_structure(lat);
  // Face neighbours along x share the 4 nodes with a = 1 / a = 0 (n -> n - 4); along y the
  // ones with b = 1 / b = 0 (n -> n - 2); along z with c (n -> n - 1).
  std::map<Coords, int> index;
  for (std::size_t c = 0; c < lat.cells.size(); ++c) index[lat.cell_coords[c]] = int(c);
  int shared_faces = 0;
  for (const auto& [g, c] : index)
    for (int axis = 0; axis < 3; ++axis) {
      Coords h = g;
      ++h[axis];
      const auto it = index.find(h);
      if (it == index.end()) continue;
      const int step = 4 >> axis;
      for (int n = 0; n < 8; ++n)
        if (n & step) CHECK(lat.cells[c][n] == lat.cells[it->second][n - step]);
      ++shared_faces;
    }
  CHECK(shared_faces == (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1));
}

TEST_CASE("voxelize: box shape fills its centred grid") {
  // Extents (1, 0.6, 0.2) are whole multiples of h = 0.1, so each axis gets extent/h cells
  // that tile the box exactly. (In floating point 0.2 / 0.1 can come out a hair above 2:
  // it must not round up to 3.)
  const Shape box = one_part(PrimitiveKind::Box, Vec3(0.5, 0.3, 0.1), Vec3(0.3, -0.2, 0.2));
  const HexLattice lat = sinew::voxelize_shape(box, 0.1);
  CHECK(lat.cells.size() == 10u * 6u * 2u);
  CHECK(lat.nodes.size() == 11u * 7u * 3u);
  check_lattice_structure(lat);
}

TEST_CASE("voxelize: sphere cells cover the sphere and converge to its volume from above") {
  const double r = 1.0;
  const Shape sphere = one_part(PrimitiveKind::Sphere, Vec3(r, 0, 0), Vec3(0.1, -0.2, 0.3));
  const double exact = 4.0 / 3.0 * M_PI * r * r * r;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  double previous_excess = 1e300;
  for (const double h : {0.5, 0.25, 0.125, 0.0625}) {
    const HexLattice lat = sinew::voxelize_shape(sphere, h);
    const double volume = double(lat.cells.size()) * h * h * h;
    MESSAGE("h = " << h << ": " << lat.cells.size() << " cells, volume " << volume << " (exact " << exact << ")");
    // Kept cells cover the ball, and each reaches at most its diagonal sqrt(3) h past it.
    CHECK(volume >= exact);
    CHECK(volume <= 4.0 / 3.0 * M_PI * std::pow(r + std::sqrt(3.0) * h, 3));
    CHECK(volume - exact < previous_excess);
    previous_excess = volume - exact;
    if (h == 0.125) check_lattice_structure(lat);
    // Every surface point lies in a kept cell.
    const auto kept = kept_cells(lat);
    int missing = 0;
    for (int n = 0; n < 5000; ++n) {
      const Vec3 p = sphere.parts[0].center + r * Vec3(normal(rng), normal(rng), normal(rng)).normalized();
      missing += !kept.count(sinew::grid_cell_of(lat.origin, h, p));
    }
    CHECK(missing == 0);
  }
}

TEST_CASE("voxelize: 1 m beam of 12 cm diameter") {
  // Cylinder along x (local y turned onto x). With h = 0.1 the centred grid has
  // ceil(0.12/0.1) = 2 cells across, spanning [-0.1, 0.1] around the axis: the circle
  // (r = 0.06) reaches all four. Along the axis ceil(1/0.1) = 10 cells. So 4 * 10 = 40.
  const Mat3 r = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  const Shape beam = one_part(PrimitiveKind::Cylinder, Vec3(0.06, 0.5, 0), Vec3(0.2, 1.0, 0.5), r);
  const double h = 0.1;
  const HexLattice lat = sinew::voxelize_shape(beam, h);
  MESSAGE("beam: cell size " << h << " m -> " << lat.cells.size() << " cells, " << lat.nodes.size() << " nodes");
  CHECK(lat.cells.size() == 40);
  check_lattice_structure(lat);
}

TEST_CASE("voxelize: must_cover keeps the cells of the surface mesh vertices") {
  Shape s = one_part(PrimitiveKind::Capsule, Vec3(0.3, 0.4, 0));
  s.parts.push_back(one_part(PrimitiveKind::Ellipsoid, Vec3(0.5, 0.2, 0.3), Vec3(0.4, 0.3, 0)).parts[0]);
  const TriMesh surface = sinew::mesh_shape_surface(s, 0.04);
  const double h = 0.15;
  const HexLattice plain = sinew::voxelize_shape(s, h);
  const HexLattice lat = sinew::voxelize_shape(s, h, surface.vertices);
  check_lattice_structure(lat);
  // Same grid, a superset of cells.
  CHECK((lat.origin - plain.origin).norm() < 1e-12);
  const auto kept = kept_cells(lat);
  for (const Coords& c : plain.cell_coords) CHECK(kept.count(c) == 1);
  const sinew::Embedding emb = sinew::embed_points(lat, surface.vertices);
  for (std::size_t i = 0; i < surface.vertices.size(); ++i) {
    const Vec3 t = natural_coords(lat, emb.cell[i], surface.vertices[i]);
    CHECK(t.cwiseAbs().maxCoeff() <= 1 + 1e-9);
  }
}

TEST_CASE("voxelize: mesh cells are the inside centres plus the vertex cells") {
  SUBCASE("unit cube of 12 triangles") {
    // h = 0.3 over [0, 1]^3: ceil(1/0.3) = 4 cells from -0.1, centres at 0.05, 0.35,
    // 0.65, 0.95: all 4^3 centres inside; the corner vertices lie in corner cells already.
    TriMesh cube;
    for (int n = 0; n < 8; ++n) cube.vertices.emplace_back((n >> 2) & 1, (n >> 1) & 1, n & 1);
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads) {
      cube.triangles.push_back({q[0], q[1], q[2]});
      cube.triangles.push_back({q[0], q[2], q[3]});
    }
    REQUIRE(sinew::count_open_edges(cube) == 0);
    const HexLattice lat = sinew::voxelize_mesh(cube, 0.3);
    CHECK(lat.cells.size() == 64);
    check_lattice_structure(lat);
  }
  SUBCASE("meshed sphere against the exact sphere") {
    const double R = 1.0, res = 0.05, h = 0.2;
    const Shape sphere = one_part(PrimitiveKind::Sphere, Vec3(R, 0, 0));
    const TriMesh mesh = sinew::mesh_shape_surface(sphere, res);
    const HexLattice lat = sinew::voxelize_mesh(mesh, h);
    check_lattice_structure(lat);
    // The mesh lies within delta of the sphere: vertices within dv = 3 res^2 / (8 (R - sqrt3 res))
    // and faces at most res^2 / (R - dv) further in (see test_surface_mesher.cpp). Centres
    // farther than that from the sphere are classified like the exact sphere.
    const double dv = 3 * res * res / (8 * (R - std::sqrt(3.0) * res));
    const double delta = dv + res * res / (R - dv) + 1e-12;
    std::set<Coords> vertex_cells;
    for (const Vec3& v : mesh.vertices) vertex_cells.insert(sinew::grid_cell_of(lat.origin, h, v));
    const auto kept = kept_cells(lat);
    int inside = 0, checked = 0;
    for (int k = -1; k < 15; ++k)
      for (int j = -1; j < 15; ++j)
        for (int i = -1; i < 15; ++i) {
          const Coords c{i, j, k};
          const double d = sphere.sdf(lat.origin + h * Vec3(i + 0.5, j + 0.5, k + 0.5));
          if (std::abs(d) <= delta) continue;
          ++checked;
          inside += d < 0;
          CHECK(kept.count(c) == ((d < 0 || vertex_cells.count(c)) ? 1u : 0u));
        }
    MESSAGE("sphere mesh: " << lat.cells.size() << " cells, " << inside << " centres inside of " << checked);
    CHECK(inside > 0);
  }
}

TEST_CASE("voxelize: armadillo scaled to 2 m") {
  const std::string path = SINEW_SOURCE_DIR "/../shared/meshes/armadillo.obj";
  if (!std::filesystem::exists(path)) {
    MESSAGE("skipped: " << path << " not found");
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  TriMesh mesh = sinew::read_obj(path);
  const auto b = mesh.bounds();
  const double scale = 2.0 / (b.hi.y() - b.lo.y());
  for (Vec3& v : mesh.vertices) v = (v - b.lo) * scale;
  const auto t1 = std::chrono::steady_clock::now();
  // 0.163 m is the cell size at which this rule and grid give about 365 cells (found by a
  // scan: 0.15 m gives 431, 0.16 m 380, 0.17 m 324).
  const double h = 0.163;
  const HexLattice lat = sinew::voxelize_mesh(mesh, h);
  const auto t2 = std::chrono::steady_clock::now();
  const sinew::Embedding emb = sinew::embed_points(lat, mesh.vertices);
  const auto t3 = std::chrono::steady_clock::now();
  auto secs = [](auto a, auto z) { return std::chrono::duration<double>(z - a).count(); };
  MESSAGE("armadillo 2 m: cell size " << h << " m -> " << lat.cells.size() << " cells, " << lat.nodes.size()
                                      << " nodes; read " << secs(t0, t1) << " s, voxelize " << secs(t1, t2)
                                      << " s, embed " << secs(t2, t3) << " s");
  check_lattice_structure(lat);

  // Volume and area by the divergence theorem / triangle areas.
  double volume = 0, area = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 &p = mesh.vertices[t[0]], &q = mesh.vertices[t[1]], &r = mesh.vertices[t[2]];
    volume += p.dot(q.cross(r)) / 6;
    area += 0.5 * (q - p).cross(r - p).norm();
  }
  // Kept cells cover the solid (inside centres, plus every cell the dense surface passes
  // through holds vertices), and each is within its diagonal of the surface or inside it:
  // V <= N h^3 <= V + A sqrt(3) h.
  const double cells_volume = double(lat.cells.size()) * h * h * h;
  CHECK(cells_volume >= volume);
  CHECK(cells_volume <= volume + area * std::sqrt(3.0) * h);

  // Every vertex embeds inside its own cell.
  double worst = 0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    worst = std::max(worst, natural_coords(lat, emb.cell[i], mesh.vertices[i]).cwiseAbs().maxCoeff());
  CHECK(worst <= 1 + 1e-9);
}
