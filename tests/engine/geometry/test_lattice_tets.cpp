#include <doctest/doctest.h>

#include <algorithm>
#include <map>

#include "engine/geometry/lattice_tets.hpp"

using namespace sinew;

namespace {

double volume_of(const TetMesh& m, int t) {
  const auto& k = m.tets[t];
  return tet_signed_volume(m.nodes[k[0]], m.nodes[k[1]], m.nodes[k[2]], m.nodes[k[3]]);
}

// Uses of each face (sorted node triple) and, per use, the face's outward orientation as
// the sign of its permutation from the sorted triple.
struct FaceUses {
  int count = 0;
  int orientation_sum = 0;  // +1 / -1 per use: 0 for an interior face seen from both sides
};

std::map<std::array<int, 3>, FaceUses> face_uses(const TetMesh& m) {
  std::map<std::array<int, 3>, FaceUses> uses;
  for (const auto& tet : m.tets)
    for (const auto& f : kTetOutwardFaces) {
      std::array<int, 3> face{tet[f[0]], tet[f[1]], tet[f[2]]};
      // Rotate the smallest node first; then the triple is sorted or odd.
      std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
      const int sign = face[1] < face[2] ? 1 : -1;
      std::array<int, 3> key = face;
      std::sort(key.begin(), key.end());
      FaceUses& u = uses[key];
      ++u.count;
      u.orientation_sum += sign;
    }
  return uses;
}

void check_conforming(const LatticeTets& lt, const HexLattice& lat) {
  const double h = lat.cell_size;
  REQUIRE(lt.mesh.tets.size() == 6 * lat.cells.size());
  REQUIRE(lt.tet_cell.size() == lt.mesh.tets.size());
  CHECK(lt.mesh.nodes.size() == lat.nodes.size());
  double total = 0;
  for (int t = 0; t < int(lt.mesh.tets.size()); ++t) {
    const double v = volume_of(lt.mesh, t);
    CHECK(v == doctest::Approx(h * h * h / 6).epsilon(1e-12));
    total += v;
    // Every node of the tet is a node of its source cell.
    const auto& cell = lat.cells[lt.tet_cell[t]];
    for (int n : lt.mesh.tets[t]) CHECK(std::find(cell.begin(), cell.end(), n) != cell.end());
  }
  CHECK(total == doctest::Approx(double(lat.cells.size()) * h * h * h).epsilon(1e-12));
  // Conformity: no face is used more than twice, and an interior face is seen with opposite
  // orientations by its two tets.
  int interior = 0, boundary = 0;
  for (const auto& [key, u] : face_uses(lt.mesh)) {
    CHECK(u.count <= 2);
    if (u.count == 2) {
      ++interior;
      CHECK(u.orientation_sum == 0);
    } else {
      ++boundary;
    }
  }
  MESSAGE(interior << " interior faces, " << boundary << " boundary faces");
}

}  // namespace

TEST_CASE("lattice_tets: the Kuhn split of one cell") {
  const auto& tets = kuhn_cell_tets();
  std::array<Vec3, 8> X;
  for (int n = 0; n < 8; ++n) X[n] = Vec3((n >> 2) & 1, (n >> 1) & 1, n & 1);
  double total = 0;
  for (const auto& t : tets) {
    const double v = tet_signed_volume(X[t[0]], X[t[1]], X[t[2]], X[t[3]]);
    CHECK(v == doctest::Approx(1.0 / 6));
    total += v;
    // All 6 share the main diagonal 0 - 7.
    CHECK(std::count(t.begin(), t.end(), 0) == 1);
    CHECK(std::count(t.begin(), t.end(), 7) == 1);
  }
  CHECK(total == doctest::Approx(1.0));
}

TEST_CASE("lattice_tets: a box lattice splits into conforming tets with a closed boundary") {
  const int nx = 3, ny = 2, nz = 4;
  const double h = 0.25;
  const Vec3 origin(-1, 0.5, 2);
  const HexLattice lat = make_box_lattice(origin, h, nx, ny, nz);
  const LatticeTets lt = split_lattice_into_tets(lat);
  check_conforming(lt, lat);
  // Each cell face on the box boundary is split into 2 triangles.
  const TetSurface s = tet_boundary_surface(lt.mesh);
  CHECK(s.mesh.triangles.size() == std::size_t(4 * (nx * ny + ny * nz + nz * nx)));
  CHECK(count_open_edges(s.mesh) == 0);
  // The boundary vertices are the lattice nodes on the box faces.
  const Vec3 hi = origin + h * Vec3(nx, ny, nz);
  int on_box = 0;
  for (const Vec3& p : lat.nodes)
    on_box +=
        ((p - origin).cwiseAbs().minCoeff() < 1e-12 || (p - hi).cwiseAbs().minCoeff() < 1e-12);
  CHECK(s.mesh.vertices.size() == std::size_t(on_box));
  for (const Vec3& p : s.mesh.vertices)
    CHECK(std::min((p - origin).cwiseAbs().minCoeff(), (p - hi).cwiseAbs().minCoeff()) < 1e-12);
  double enclosed = 0;
  for (const auto& t : s.mesh.triangles)
    enclosed += s.mesh.vertices[t[0]].dot(s.mesh.vertices[t[1]].cross(s.mesh.vertices[t[2]])) / 6;
  CHECK(enclosed == doctest::Approx(nx * ny * nz * h * h * h).epsilon(1e-12));
}

TEST_CASE("lattice_tets: a voxelized sphere splits into conforming tets") {
  Shape sphere;
  Primitive p;
  p.kind = PrimitiveKind::Sphere;
  p.size = Vec3(0.5, 0, 0);
  p.center = Vec3(0.1, -0.2, 0.3);
  sphere.parts.push_back(p);
  const HexLattice lat = voxelize_shape(sphere, 0.125);
  const LatticeTets lt = split_lattice_into_tets(lat);
  check_conforming(lt, lat);
  CHECK(count_open_edges(tet_boundary_surface(lt.mesh).mesh) == 0);
}
