// Bounds used below. The mesher's surface is the zero set of the piecewise-linear
// interpolant F of the SDF f on tetrahedra whose edges are at most D = sqrt(3) res long,
// so the enclosed volume is vol{F < 0}. At a point x = sum l_j v_j of a tetrahedron:
//  - convex f: F(x) >= f(x) (chords lie above), so {F < 0} is inside the solid;
//  - f(x) = dist(x, C) - r for a convex core C (point, segment): dist^2 has Hessian <= 2 I,
//    so sum l_j dist(v_j)^2 <= dist(x)^2 + sum l_j |v_j - x|^2 <= dist(x)^2 + D^2, and
//    F(x) <= sqrt(dist(x)^2 + D^2) - r: {F < 0} holds the part shrunk to radius
//    sqrt(r^2 - D^2). On one edge (vertices of the mesh) D^2 becomes L^2 / 4 <= 3 res^2 / 4.
//  - a union, f = min f_i: F <= min F_i, so {F < 0} holds the union of the shrunk parts;
//    and any 1-Lipschitz f has |F - f| <= D, so {F < 0} lies within D of the solid.
//  - a mesh vertex is the root of the chord of a 1-Lipschitz f on an edge of length
//    L <= D, so |f| <= L / 2 there.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <utility>

#include "engine/geometry/surface_mesher.hpp"

using sinew::Mat3;
using sinew::Primitive;
using sinew::PrimitiveKind;
using sinew::Shape;
using sinew::TriMesh;
using sinew::Vec3;

namespace {

Primitive part(PrimitiveKind kind, const Vec3& size, const Vec3& center = Vec3::Zero(),
               const Mat3& rotation = Mat3::Identity()) {
  Primitive p;
  p.kind = kind;
  p.size = size;
  p.center = center;
  p.rotation = rotation;
  return p;
}

double signed_volume(const TriMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles)
    v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
  return v;
}

// Consistent orientation: every directed edge once, and its reverse once.
bool consistently_oriented(const TriMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto back = directed.find({edge.second, edge.first});
    if (back == directed.end() || back->second != 1) return false;
  }
  return true;
}

bool uses_every_vertex(const TriMesh& m) {
  std::vector<char> used(m.vertices.size(), 0);
  for (const auto& t : m.triangles)
    for (int v : t) used[v] = 1;
  return std::find(used.begin(), used.end(), 0) == used.end();
}

double sphere_volume(double r) { return 4.0 / 3.0 * M_PI * r * r * r; }

// Capsule of radius r and axis segment 2h.
double capsule_volume(double r, double h) { return M_PI * r * r * 2 * h + sphere_volume(r); }

}  // namespace

TEST_CASE("surface_mesher: count_open_edges, the closedness oracle used below") {
  TriMesh tet;
  tet.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 1, 1)};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  CHECK(sinew::count_open_edges(tet) == 0);
  TriMesh open = tet;
  open.triangles.pop_back();  // a hole: its 3 edges are used once
  CHECK(sinew::count_open_edges(open) == 3);
  TriMesh fin = tet;
  fin.triangles.push_back({1, 2, 4});  // edge 1-2 used 3 times, edges 2-4 and 4-1 once
  CHECK(sinew::count_open_edges(fin) == 3);
}

TEST_CASE("surface_mesher: sphere is closed, outward and on the surface") {
  const double R = 1.0;
  // res = 0.25 puts grid points exactly on the sphere (e.g. (1, 0, 0)): the zero-value case.
  for (const double res : {0.25, 0.1, 0.05}) {
    const Shape s{{part(PrimitiveKind::Sphere, Vec3(R, 0, 0))}};
    const TriMesh m = sinew::mesh_shape_surface(s, res);
    CAPTURE(res);
    REQUIRE(!m.triangles.empty());
    CHECK(sinew::count_open_edges(m) == 0);
    CHECK(consistently_oriented(m));
    CHECK(uses_every_vertex(m));
    // Grid values that are exactly 0 are nudged: no triangle collapses to zero area.
    double min_area = 1e300;
    for (const auto& t : m.triangles)
      min_area = std::min(min_area, (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm());
    CHECK(min_area > 0);
    // Vertices: R^2 - 3 res^2 / 4 <= |v|^2 <= R^2 (slack for the 1e-12 res zero nudge).
    double rmin = 1e300, rmax = 0;
    for (const Vec3& v : m.vertices) rmin = std::min(rmin, v.norm()), rmax = std::max(rmax, v.norm());
    CHECK(rmax <= R + 1e-9 * res);
    CHECK(rmin >= std::sqrt(R * R - 0.75 * res * res) - 1e-9 * res);
    // Volume between the balls of radius sqrt(R^2 - D^2) and R.
    const double D = std::sqrt(3.0) * res;
    const double v = signed_volume(m);
    MESSAGE("sphere res " << res << ": " << m.triangles.size() << " triangles, volume " << v << " vs "
                          << sphere_volume(R));
    CHECK(v > 0);
    CHECK(v <= sphere_volume(R) * (1 + 1e-9));
    CHECK(v >= sphere_volume(std::sqrt(R * R - D * D)));
  }
}

TEST_CASE("surface_mesher: union of crossing capsules and a sphere") {
  // A plus sign of two capsules (r = 0.3, half length 0.5 along y and along x) crossing at
  // their centres, and a separate sphere. The capsules meet inside their cylinder parts,
  // in a Steinmetz bicylinder of volume 16 r^3 / 3.
  const double r = 0.3, h = 0.5, rs = 0.25;
  const Mat3 y_to_x = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 c(0.2, -0.1, 0.4), cs(0.2, 1.4, 0.4);
  const Shape s{{part(PrimitiveKind::Capsule, Vec3(r, h, 0), c), part(PrimitiveKind::Capsule, Vec3(r, h, 0), c, y_to_x),
                 part(PrimitiveKind::Sphere, Vec3(rs, 0, 0), cs)}};
  auto union_volume = [&](double rc, double rsphere) {
    return 2 * capsule_volume(rc, h) - 16.0 / 3.0 * rc * rc * rc + sphere_volume(rsphere);
  };
  const double res = 0.02, D = std::sqrt(3.0) * res;
  const TriMesh m = sinew::mesh_shape_surface(s, res);
  CHECK(sinew::count_open_edges(m) == 0);
  CHECK(consistently_oriented(m));
  double worst = 0;
  for (const Vec3& v : m.vertices) worst = std::max(worst, std::abs(s.sdf(v)));
  CHECK(worst <= D / 2 + 1e-12);
  // The sphere is 0.8 - 0.3 - 0.25 = 0.25 away from the capsules: the parts stay apart
  // even when grown by D, so their volumes add in both bounds.
  const double v = signed_volume(m);
  const double lo = union_volume(std::sqrt(r * r - D * D), std::sqrt(rs * rs - D * D));
  const double hi = union_volume(r + D, rs + D);
  MESSAGE("capsules + sphere: " << m.triangles.size() << " triangles, volume " << v << " (exact "
                                << union_volume(r, rs) << ", bounds " << lo << " .. " << hi << ")");
  CHECK(v >= lo);
  CHECK(v <= hi);
}

TEST_CASE("surface_mesher: rotated box keeps its sharp edges closed") {
  const Mat3 rot = (Eigen::AngleAxisd(0.3, Vec3::UnitX()) * Eigen::AngleAxisd(0.5, Vec3::UnitY())).toRotationMatrix();
  const Vec3 half(0.5, 0.3, 0.2);
  const Shape s{{part(PrimitiveKind::Box, half, Vec3(1, 2, 3), rot)}};
  const double res = 0.025, D = std::sqrt(3.0) * res;
  const TriMesh m = sinew::mesh_shape_surface(s, res);
  CHECK(sinew::count_open_edges(m) == 0);
  CHECK(consistently_oriented(m));
  for (const Vec3& v : m.vertices) CHECK(std::abs(s.sdf(v)) <= D / 2 + 1e-12);
  // Convex: inside the box, and holding the box shrunk by D (F <= f + D).
  const double v = signed_volume(m);
  const Vec3 shrunk = 2 * (half - Vec3::Constant(D));
  CHECK(v <= 8 * half.prod() * (1 + 1e-9));
  CHECK(v >= shrunk.prod());
}
