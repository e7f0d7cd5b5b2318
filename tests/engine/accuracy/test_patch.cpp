// Patch tests (issue 10, section 1: analytic references): the boundary nodes of a block are
// held at an affine map x = F X + c of their rest positions and the free nodes must settle
// exactly there, i.e. the discretisation reproduces a uniform deformation. Under a uniform
// F every element has the same stress (and the same rotation), so the element forces at
// every free node cancel: the affine state is an exact discrete equilibrium for any element
// that can represent a linear field (hex8, tet4) and any material; a solver that reaches
// equilibrium must find it. Hex and tet lattices, an irregular tet mesh (free node off
// centre), the linear corotational element and Stable Neo-Hookean.
//
// Tolerance: round-off. The static solve is a sparse direct solve of a system whose
// condition number is ~1e4 for these lattices (stiffness over the mass term of a 1 s step),
// so positions of 0.5 m are exact to ~1e-16 * 1e4 * 0.5 m ~ 1e-12 m; the Newton path stops
// at 1e-12 of its residual scale, ~1e-13 m. 1e-10 m is asked, 1e-9 of F.
#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/assembly/element_kernels.hpp"
#include "tests/engine/accuracy/static_equilibrium.hpp"

using namespace sinew;

namespace {

const Mat3 kF = (Mat3() << 1.08, 0.03, -0.02, 0.01, 0.95, 0.04, -0.03, 0.02, 1.05).finished();
const Vec3 kOffset(0.01, -0.02, 0.03);

// Six half-spaces just inside the faces of the box [-a, a]^3: they select its boundary nodes.
std::string boundary_regions(double a) {
  std::string out;
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1}) {
      Vec3 point = Vec3::Zero(), normal = Vec3::Zero();
      point[axis] = side * (a - 1e-6);
      normal[axis] = -side;  // selects (x - point) . normal <= 0: the side beyond the point
      char region[200];
      std::snprintf(region, sizeof region, R"(%s{"half_space": {"point": [%.9g, %.9g, %.9g], "normal": [%g, %g, %g]}})",
                    out.empty() ? "" : ", ", point.x(), point.y(), point.z(), normal.x(), normal.y(), normal.z());
      out += region;
    }
  return out;
}

std::string scene_json(const std::string& geometry, const std::string& model, double a) {
  return R"({"h": 1, "gravity": [0, 0, 0],
    "solver": {"newton_tolerance": 1e-12, "newton_max_iterations": 50},
    "bodies": [{)" + geometry + R"(,
      "material": {"model": ")" + model + R"(", "E": 1e6, "nu": 0.3, "rho": 1000},
      "fixed": [)" + boundary_regions(a) + "]}]}";
}

// Worst distance of a free node from the affine map, and worst |F_e - F| over elements,
// after the boundary was placed on the map and the free nodes settled from rest.
struct PatchResult {
  int free_nodes = 0;
  double node_error = 0, gradient_error = 0;
};

PatchResult run_patch(const std::string& json) {
  World world = accuracy::make_world(accuracy::static_scene(json));
  const Model& m = world.model();
  VecX& x = world.mutable_state().x;
  PatchResult r;
  for (int n = 0; n < m.num_nodes; ++n) {
    if (m.free_index[n] < 0)
      x.segment<3>(3 * n) = kF * m.rest_x.segment<3>(3 * n) + kOffset;
    else
      ++r.free_nodes;
  }
  REQUIRE(r.free_nodes > 0);
  // Newton stops at a residual of 1e-12 of the element forces (~1e5 N here), which leaves
  // a creep of ~1e-14 m per step against stiffnesses ~1e6 N/m: settled below 1e-12 m a step.
  accuracy::settle(world, 1e-12, 100);
  for (int n = 0; n < m.num_nodes; ++n)
    r.node_error = std::max(r.node_error, (world.state().x.segment<3>(3 * n) - kF * m.rest_x.segment<3>(3 * n) - kOffset).norm());
  for (int e = 0; e < m.num_elements; ++e) {
    const Mat3 F = element_center_deformation_gradient(m, e, gather_element_nodes(m, world.state().x, e));
    r.gradient_error = std::max(r.gradient_error, (F - kF).cwiseAbs().maxCoeff());
  }
  return r;
}

// A unit cube of 12 tets: each face split into two triangles, each coned to one interior
// node placed off centre, so that no two tets are congruent. TetGen files in a temp folder.
std::string write_irregular_cube() {
  const auto dir = std::filesystem::temp_directory_path() / "sinew_test_patch";
  std::filesystem::create_directories(dir);
  const std::string base = (dir / "cube12").string();
  std::ofstream node(base + ".node");
  node << "9 3 0 0\n";
  for (int i = 0; i < 8; ++i)
    node << i << " " << ((i & 4) ? 0.5 : -0.5) << " " << ((i & 2) ? 0.5 : -0.5) << " " << ((i & 1) ? 0.5 : -0.5) << "\n";
  node << "8 0.08 -0.06 0.05\n";
  // Faces as corner quads (i, j, k, l) in cyclic order; each splits along (i, k).
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  std::ofstream ele(base + ".ele");
  ele << "12 4 0\n";
  int t = 0;
  for (const auto& f : faces) {
    ele << t++ << " " << f[0] << " " << f[1] << " " << f[2] << " 8\n";
    ele << t++ << " " << f[0] << " " << f[2] << " " << f[3] << " 8\n";
  }
  return base;
}

}  // namespace

TEST_CASE("accuracy: patch test, an affine boundary motion gives the affine state exactly") {
  const std::string hex = R"("shape": [{"type": "box", "half_extents": [0.15, 0.15, 0.15]}], "cell_size": 0.1)";
  const std::string tet = hex + R"(, "elements": "tet")";
  const std::string mesh = R"("tet_mesh": ")" + write_irregular_cube() + R"(")";
  struct Case {
    std::string name;
    std::string geometry;
    double a;
  };
  const Case cases[] = {{"hex lattice 3x3x3", hex, 0.15}, {"tet lattice 3x3x3", tet, 0.15}, {"irregular tet cube", mesh, 0.5}};
  for (const Case& c : cases)
    for (const std::string model : {"corotational", "stable_neo_hookean"}) {
      CAPTURE(c.name);
      CAPTURE(model);
      const PatchResult r = run_patch(scene_json(c.geometry, model, c.a));
      MESSAGE(c.name << ", " << model << ": " << r.free_nodes << " free nodes, worst node error " << r.node_error
                     << " m, worst |F_e - F| " << r.gradient_error);
      CHECK(r.node_error <= 1e-10);
      CHECK(r.gradient_error <= 1e-9);
    }
}
