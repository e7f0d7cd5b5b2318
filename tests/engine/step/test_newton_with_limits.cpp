// Stable Neo-Hookean bodies carrying paper 000's energy limits and paper 001's strain limits
// (solved after Newton, with its last Hessian as the QP's matrix).
// Energy limits: Newton still converges in a few iterations per step, and every limited
// element ends within the SQP tolerance. Regression (tools/stress): the previous step's
// constraint curvature entered Newton's matrix but not its gradient, and every step ran to
// the cap (20) with a residual near 1e-2.
#include <doctest/doctest.h>

#include <Eigen/SVD>

#include "engine/assembly/element_kernels.hpp"
#include "engine/constraints/energy_limit.hpp"
#include "engine/constraints/strain_limit_rows.hpp"
#include "engine/scene/scene.hpp"
#include "engine/world.hpp"

using namespace sinew;

TEST_CASE("solve_newton: converges with active energy-limit rows") {
  const std::string text = R"({"bodies": [{"name": "snh", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1]}],
      "cell_size": 0.1, "elements": "tet", "surface_resolution": 0.09, "transform": {"translate": [0.5, 0.1001, 0]},
      "material": {"model": "stable_neo_hookean", "E": 1e5, "nu": 0.3, "rho": 1000}, "damping": {"mass": 2},
      "energy_limit": {"Umax": 1e-4}}],
    "obstacles": [{"type": "plane", "friction": 0.5}]})";
  World world(build_model(parse_scene_text(text, "t", "."), [](const std::string&) {}));
  for (int s = 0; s < 10; ++s) {
    CAPTURE(s);
    REQUIRE(world.step());
    CHECK(world.profile().rows.count("energy"));  // the limits bind on every step
    CHECK(world.profile().iterations.at("newton") < world.model().solver.newton_max_iterations);
    CHECK(world.profile().violation.at("newton_residual") <= world.model().solver.newton_tolerance);
    // The limit holds: worst Ue / Umax - 1 within the SQP's tolerance.
    CHECK(worst_energy_violation(world.model(), world.state().x) <= world.model().solver.sqp_tolerance);
  }
}

namespace {

// Paper 001's fig. 2 cantilever (1 x 0.2 x 0.2 m, tets, E 5 kPa) in Stable Neo-Hookean, with
// isotropic strain limits 0.96-1.04 or none. Mass damping instead of the scene's stiffness
// damping (corotational only). The limits carry the beam's weight: before the QPs' matrix
// carried the last step's curvature (solve_newton.cpp, its end), 50 of these 60 steps ended
// at the SQP cap, 1.6e-3 past the limits (docs/ARCHITECTURE.md, "Strain limits on
// hyperelastic bodies").
World snh_cantilever(bool limited) {
  const std::string limits = limited ? R"(, "strain_limit": {"mode": "isotropic", "smin": 0.96, "smax": 1.04})" : "";
  const std::string text = R"({"solver": {"sqp_max_iterations": 20, "pgs_max_iterations": 50, "pgs_subspace_interval": 0},
    "bodies": [{"name": "beam", "shape": [{"type": "box", "half_extents": [0.5, 0.1, 0.1]}], "cell_size": 0.1,
      "elements": "tet", "material": {"model": "stable_neo_hookean", "E": 5000, "nu": 0.3, "rho": 1000},
      "damping": {"mass": 1}, "fixed": [{"half_space": {"point": [-0.49, 0, 0], "normal": [1, 0, 0]}}])" +
                           limits + "}]}";
  return World(build_model(parse_scene_text(text, "t", "."), [](const std::string&) {}));
}

// Largest principal stretch over the tets: the largest singular value of F.
double largest_stretch(const World& world) {
  const Model& m = world.model();
  double largest = 0;
  for (int e = 0; e < m.num_elements; ++e) {
    const Mat3 F = element_center_deformation_gradient(m, e, gather_element_nodes(m, world.state().x, e));
    largest = std::max(largest, Eigen::JacobiSVD<Mat3>(F).singularValues()(0));
  }
  return largest;
}

}  // namespace

TEST_CASE("solve_newton + strain limits: a Stable Neo-Hookean beam keeps its isotropic limits at every step") {
  World limited = snh_cantilever(true), free = snh_cantilever(false);
  const double tolerance = limited.model().solver.strain_tolerance;
  double worst = 0, free_stretch = 0;
  int capped = 0, curved = 0;
  for (int s = 0; s < 60; ++s) {  // 1 s: the beam swings down and starts to settle
    CAPTURE(s);
    REQUIRE(limited.step());
    REQUIRE(free.step());
    worst = std::max(worst, worst_strain_limit_violation(limited.model(), limited.state().x));
    free_stretch = std::max(free_stretch, largest_stretch(free));
    const auto& its = limited.profile().iterations;
    capped += its.count("sqp") && its.at("sqp") >= limited.model().solver.sqp_max_iterations;
    curved += its.count("newton_curved_factorisations") ? its.at("newton_curved_factorisations") : 0;
  }
  MESSAGE("worst strain-limit violation " << worst << " (tolerance " << tolerance << "); largest stretch: limited "
                                          << largest_stretch(limited) << ", free " << free_stretch << "; steps at the SQP cap "
                                          << capped << "; QPs started on H + curvature " << curved);
  CHECK(curved > 0);  // the path under test ran
  CHECK(worst <= tolerance);
  CHECK(largest_stretch(limited) <= 1.04 + tolerance);
  CHECK(free_stretch > 1.04 + tolerance);  // the limits bind: without them the beam stretches past them
}

// Paper 001's side-pressed finger (fig. 3: 200 N ramped in over 0.5 s against a table,
// anisotropic limits) in Stable Neo-Hookean. With the last step's J^T lambda as Newton's
// predictor, strain rows included, steps went to 12 Newton iterations, ~3,900 strain rows and
// the SQP cap: 0.02-0.24 past the limits, 1.5 mm into the table (solve_constraints.cpp, where
// the predictor is kept). Every step within the strain and contact tolerances now.
TEST_CASE("solve_newton + strain limits + contact: the side-pressed Stable Neo-Hookean finger keeps its limits") {
  SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_side_anisotropic.json");
  REQUIRE(scene.bodies.size() == 1);
  scene.bodies[0].material.model = "stable_neo_hookean";
  scene.bodies[0].damping_mass = 2;
  scene.bodies[0].damping_stiffness = 0;  // the corotational model's alone
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  REQUIRE(world.model().has_hyperelastic);
  const SolverDesc& solver = world.model().solver;
  double worst_strain = 0, worst_penetration = 0;
  int retried = 0;
  for (int s = 0; s < 60; ++s) {  // the press ramps in over 30 steps, then holds
    CAPTURE(s);
    REQUIRE(world.step());
    const StepProfile& p = world.profile();
    worst_strain = std::max(worst_strain, worst_strain_limit_violation(world.model(), world.state().x));
    if (p.violation.count("penetration")) worst_penetration = std::max(worst_penetration, p.violation.at("penetration"));
    retried += p.iterations.count("step_retries") ? p.iterations.at("step_retries") : 0;
  }
  MESSAGE("worst strain violation " << worst_strain << ", deepest penetration " << worst_penetration << " m, steps retried "
                                    << retried);
  CHECK(worst_strain <= solver.strain_tolerance);
  CHECK(worst_penetration <= solver.contact_tolerance);
  CHECK(retried == 0);  // no step failed and was redone (World::step's retries)
}
