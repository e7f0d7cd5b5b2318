// A free bar pulled (or pushed) at both ends by a "loads" force, for every material model,
// against the closed-form uniaxial stretch of its energy (issue 10, section 1: analytic
// references; closed forms in uniaxial_closed_form.hpp).
//
// The bar is 3 x 1 x 1 cells, hex or tet (Kuhn split), with no fixed node and no gravity.
// Each end node carries its consistent share of the total force T A (A the rest section):
// a quarter per node of a hex face, a third of each triangle's area per node of a tet face.
// Then the uniform state F = diag(s, t, t) with the closed-form s, t is an exact discrete
// equilibrium (every element has the same stress, the end forces are that stress
// integrated over the faces): the FEM must reproduce it whatever the lattice size, and the
// only errors left are the solvers'. Net force and torque are zero, so no rigid motion is
// excited.
//
// Tension only: a free body under compressive dead loads is unstable to rotation (turned by
// dtheta, its end loads no longer pass through each other and turn it further), so no
// solver should be expected to hold it.
//
// Time step. Hyperelastic models: h = 1 s, a quasi-static Newton solve (its Hessian holds
// the stress's restoring torque). The linear corotational step evaluates the rotation at
// the start of the step, so that torque is explicit: symplectic-Euler stability asks
// h omega < 2, omega^2 = 12 T / (rho L^2) the stretched bar's rotation frequency
// (183 rad/s at T = E/4): h = 5 ms, and more steps to settle. That torque is then undamped
// (symplectic), and a tet lattice (the Kuhn split is not mirror-symmetric) sets the bar
// rocking on its way to equilibrium: mass damping (alpha = 50/s, a drag on velocities,
// nothing on the static state) stops it.
//
// Tolerance: Newton stops at a residual of 1e-12 of the element forces (~T A = 2500 N),
// ~3e-9 N against a bar stiffness E A / L ~ 3e4 N/m: ~1e-13 m; the closed form is exact to
// ~1e-12 (uniaxial_closed_form.hpp). 1e-9 in stretch leaves three orders for conditioning.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/assembly/element_kernels.hpp"
#include "tests/engine/accuracy/static_equilibrium.hpp"
#include "tests/engine/accuracy/uniaxial_closed_form.hpp"

using namespace sinew;

namespace {

constexpr double kYoung = 1e6, kPoisson = 0.3, kHalfLength = 0.15, kSection = 0.1 * 0.1;

std::string bar_json(const std::string& model, const std::string& elements, const std::string& loads) {
  const std::string h = model == "corotational" ? "0.005" : "1";
  return R"({"h": )" + h + R"(, "gravity": [0, 0, 0],
    "solver": {"newton_tolerance": 1e-12, "newton_max_iterations": 100},
    "bodies": [{"shape": [{"type": "box", "half_extents": [0.15, 0.05, 0.05]}], "cell_size": 0.1,
      "elements": ")" + elements + R"(", "material": {"model": ")" + model + R"(", "E": 1e6, "nu": 0.3, "rho": 1000},
      "damping": {"mass": 50})" +
         (loads.empty() ? "" : R"(, "loads": [)" + loads + "]") + "}]}";
}

// Consistent nodal loads for nominal stress `traction` on both end faces (x = -+L/2,
// outward): per element face lying on an end plane, its area split over its nodes. One
// "loads" entry per node, a small box around it, so each node gets exactly its share.
std::string end_loads(const Model& m, double traction) {
  std::vector<double> area(m.num_nodes, 0);
  for (int e = 0; e < m.num_elements; ++e)
    for (double plane : {-kHalfLength, kHalfLength}) {
      std::vector<Vec3> face;
      std::vector<int> nodes;
      for (int n : m.element_nodes[e])
        if (n >= 0 && std::abs(m.rest_x[3 * n] - plane) < 1e-9) {
          nodes.push_back(n);
          face.push_back(m.rest_x.segment<3>(3 * n));
        }
      double face_area = 0;
      if (face.size() == 3) face_area = 0.5 * (face[1] - face[0]).cross(face[2] - face[0]).norm();
      if (face.size() == 4) face_area = m.bodies[0].lattice.cell_size * m.bodies[0].lattice.cell_size;
      for (int n : nodes) area[n] += face_area / nodes.size();
    }
  std::string out;
  double total = 0;
  for (int n = 0; n < m.num_nodes; ++n) {
    if (area[n] == 0) continue;
    const Vec3 p = m.rest_x.segment<3>(3 * n);
    const double fx = (p.x() > 0 ? 1 : -1) * traction * area[n];
    if (p.x() > 0) total += area[n];
    char load[256];
    std::snprintf(load, sizeof load, R"(%s{"box": {"min": [%.9g, %.9g, %.9g], "max": [%.9g, %.9g, %.9g]}, "force": [%.17g, 0, 0]})",
                  out.empty() ? "" : ", ", p.x() - 1e-4, p.y() - 1e-4, p.z() - 1e-4, p.x() + 1e-4, p.y() + 1e-4,
                  p.z() + 1e-4, fx);
    out += load;
  }
  REQUIRE(total == doctest::Approx(kSection).epsilon(1e-12));
  return out;
}

// Worst difference of each element's stretches sqrt(C_ii), C = F^T F, from (s, t, t), and
// the worst shear |C_ij| (zero under a principal stretch along the lattice axes).
struct BarResult {
  double stretch_error = 0, shear = 0, axial = 0, lateral = 0;
};

BarResult run_bar(const std::string& model, const std::string& elements, double traction,
                  const accuracy::UniaxialStretch& expected) {
  const Model unloaded = build_model(accuracy::static_scene(bar_json(model, elements, "")), [](const std::string&) {});
  World world = accuracy::make_world(accuracy::static_scene(bar_json(model, elements, end_loads(unloaded, traction))));
  // Settled: a move per step below what the solver resolves (Newton: ~1e-13 m, see above;
  // the linear step converges geometrically to round-off, so ask 1e-14 m of it).
  accuracy::settle(world, model == "corotational" ? 1e-14 : 1e-12, 1000);
  const Model& m = world.model();
  BarResult r;
  for (int e = 0; e < m.num_elements; ++e) {
    const Mat3 F = element_center_deformation_gradient(m, e, gather_element_nodes(m, world.state().x, e));
    const Mat3 C = F.transpose() * F;
    const Vec3 s = C.diagonal().cwiseSqrt();
    r.axial = s.x();
    r.lateral = s.y();
    r.stretch_error = std::max({r.stretch_error, std::abs(s.x() - expected.axial), std::abs(s.y() - expected.lateral),
                                std::abs(s.z() - expected.lateral)});
    r.shear = std::max({r.shear, std::abs(C(0, 1)), std::abs(C(0, 2)), std::abs(C(1, 2))});
  }
  return r;
}

}  // namespace

TEST_CASE("accuracy: a bar under uniaxial load stretches as the closed form of its material") {
  const std::string models[] = {"corotational", "stable_neo_hookean", "neo_hookean", "corotational_hyperelastic",
                                "stvk", "arap", "fung", "arruda_boyce"};
  // 5 % of E (near Hooke's range) and 25 % (far past it: the energies disagree by ~10 %).
  for (const std::string& model : models)
    for (double traction : {0.05 * kYoung, 0.25 * kYoung}) {
      const accuracy::UniaxialStretch expected =
          accuracy::solve_uniaxial(accuracy::stretch_energy(model, kYoung, kPoisson), traction);
      for (const std::string elements : {"hex", "tet"}) {
        CAPTURE(model);
        CAPTURE(traction);
        CAPTURE(elements);
        const BarResult r = run_bar(model, elements, traction, expected);
        MESSAGE(model << " " << elements << " T = " << traction / kYoung << " E: stretch " << r.axial << " (closed form "
                      << expected.axial << "), lateral " << r.lateral << " (" << expected.lateral << "), worst error "
                      << r.stretch_error);
        CHECK(r.stretch_error <= 1e-9);
        CHECK(r.shear <= 1e-9);
      }
    }
}
