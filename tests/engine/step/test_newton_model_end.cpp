// Newton's last iteration ends on its quadratic model (solve_newton.cpp): the gradient at its
// result is not evaluated, and the model handed to the constraint stage is the one around the
// iteration's start v_m, whose gradient g_m the iteration did evaluate. Checked against an
// independent evaluation of g_m, through the landing of the Stable Neo-Hookean box, with
// directions from a factorisation of this H and from CG preconditioned with an older one.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/solve/linear_solver.hpp"
#include "engine/step/hyperelastic_derivatives.hpp"
#include "engine/step/stages.hpp"
#include "tests/engine/step/snh_landing_box.hpp"

using namespace sinew;

namespace {

// grad Phi at v: A0 v - b0 + h dPsi/dx(x0 + h v) (no driven nodes in the box), and the
// step's scale as solve_newton takes it at its first iterate.
struct Evaluation {
  VecX gradient;
  double scale = 0;
};

Evaluation evaluate(const Model& model, const State& s, const VecX& v) {
  VecX x = s.scratch.newton_x0;
  for (int n = 0; n < model.num_nodes; ++n)
    if (const int f = model.free_index[n]; f >= 0) x.segment<3>(3 * n) += model.h * v.segment<3>(3 * f);
  std::vector<double> energy, force2;
  std::vector<Vec24> element_gradients;
  VecX dPsi;
  hyperelastic_derivatives(model, x, false, energy, force2, dPsi, nullptr, element_gradients);
  Evaluation out;
  out.gradient = s.scratch.newton_A0 * v - s.scratch.newton_b0 + model.h * dPsi;
  double forces = 0;
  for (double f2 : force2) forces += f2;
  out.scale = std::max({out.gradient.norm(), s.scratch.newton_b0.norm(), model.h * std::sqrt(forces)});
  return out;
}

}  // namespace

TEST_CASE("Newton's last iteration: the constraint stage gets the quadratic model around the iteration's start") {
  for (int refactor_interval : {1, 8}) {
    CAPTURE(refactor_interval);
    World world = test::snh_landing_box(R"("newton_max_iterations": 1, "sleep_steps": 0, "refactor_interval": )" +
                                        std::to_string(refactor_interval));
    const Model& model = world.model();
    LinearSolver solver(model.solver);
    int full_steps = 0, shortened_steps = 0, preconditioned = 0;
    for (int step = 0; step < 50; ++step) {
      REQUIRE(world.step());
      // Newton on a copy of this state, with this test's solver: every fourth copy factorises
      // (factor_age at the interval's end), the others precondition with that factorisation.
      State s = world.state();
      s.profile.clear();
      s.newton_factor_spent = false;
      s.factor_age = step % 4 == 0 ? refactor_interval - 1 : 0;
      if (step == 0) s.factor_age = refactor_interval - 1;
      assemble_system(model, s);
      REQUIRE(solve_newton(model, solver, s));
      if (s.profile.iterations.at("newton") == 0) continue;  // converged at its start: no model end
      preconditioned += test::iteration_count(s.profile, "newton_pcg") > 0;
      const VecX& v = s.v_free;
      const VecX& v_m = s.scratch.newton_model_v;
      const SparseMatrix& H = s.system;
      // The iteration's g_m is grad Phi at v_m, evaluated afresh here.
      const Evaluation at_start = evaluate(model, s, v_m);
      const VecX& g_m = s.scratch.gradient;
      CHECK((g_m - at_start.gradient).norm() <= 1e-12 * at_start.scale);
      // The model's gradient at v: g_m + H (v - v_m) (round-off of the products and of CG's
      // residual recurrence, far below 1e-9 of the terms).
      const VecX step_product = H * (v - v_m);
      const VecX& model_gradient = s.scratch.newton_model_gradient;
      CHECK((model_gradient - (g_m + step_product)).norm() <= 1e-9 * (g_m.norm() + step_product.norm()));
      CHECK(s.profile.violation.at("newton_residual") ==
            doctest::Approx(model_gradient.norm() / at_start.scale).epsilon(1e-12));
      // rhs: H v - rhs (less the predictor's force) is the model's gradient after a full step
      // (at most a tenth of g_m, the forcing term), zero after a shortened one (v taken as the
      // model's minimiser).
      VecX remaining = H * v - s.rhs;
      if (s.impulse_predicted) remaining -= s.scratch.newton_predicted_impulse;
      const double round_off = 1e-12 * ((H * v).norm() + s.rhs.norm());
      if ((remaining - model_gradient).norm() <= round_off + 1e-9 * model_gradient.norm()) {
        ++full_steps;
        CHECK(model_gradient.norm() <= 0.1 * g_m.norm() * (1 + 1e-9));
      } else {
        ++shortened_steps;
        CHECK(remaining.norm() <= round_off);
      }
    }
    MESSAGE("refactor_interval " << refactor_interval << ": " << full_steps << " full steps, " << shortened_steps
                                 << " shortened, " << preconditioned << " with preconditioned CG");
    CHECK(full_steps > 30);
    if (refactor_interval > 1) CHECK(preconditioned > 10);
  }
}
