// Newton hands its quadratic model on to the constraint stage as the residual r = rhs - H v
// at its result (State::model_residual, solve_newton.cpp), formed without a product with H:
// -grad Phi(v), or 0 where Newton left more than a tenth of the step's scale, less the
// predicted force. Checked against an independent evaluation of grad Phi at the result,
// through the landing of the Stable Neo-Hookean box, with one Newton iteration a step and
// with Newton converged.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "engine/step/hyperelastic_derivatives.hpp"
#include "tests/engine/step/snh_landing_box.hpp"

using namespace sinew;

namespace {

// grad Phi at v: A0 v - b0 + h dPsi/dx(x0 + h v) (b0 with the predicted force; no driven
// nodes in the box), and the step's scale as solve_newton takes it at its first iterate.
struct Evaluation {
  VecX gradient;
  double scale = 0;
};

Evaluation evaluate(const Model& model, const State& s, const VecX& v) {
  VecX x = s.scratch.newton_x0;
  for (int n = 0; n < model.num_nodes; ++n)
    if (const int f = model.free_index[n]; f >= 0) x.segment<3>(3 * n) += model.h * v.segment<3>(3 * f);
  std::vector<double> energy, force2;
  std::vector<Vec3> node_gradients;
  VecX dPsi;
  hyperelastic_derivatives(model, x, false, energy, force2, dPsi, nullptr, node_gradients);
  Evaluation out;
  // A0 is its diagonal alone (the box is all hyperelastic; its other values are stale).
  REQUIRE(s.scratch.newton_A0_diagonal.size() == v.size());
  out.gradient = s.scratch.newton_A0_diagonal.cwiseProduct(v) - s.scratch.newton_b0 + model.h * dPsi;
  double forces = 0;
  for (double f2 : force2) forces += f2;
  out.scale = std::max({out.gradient.norm(), s.scratch.newton_b0.norm(), model.h * std::sqrt(forces)});
  return out;
}

}  // namespace

TEST_CASE("Newton hands on its model as the residual at its result: -grad Phi there, less the predicted force") {
  for (const int iterations : {1, 30}) {
    CAPTURE(iterations);
    World world = test::snh_landing_box("\"newton_max_iterations\": " + std::to_string(iterations) +
                                        ", \"sleep_steps\": 0, \"refactor_interval\": 8");
    const Model& model = world.model();
    int kept = 0, dropped = 0, predicted_steps = 0;
    for (int step = 0; step < 60; ++step) {
      REQUIRE(world.step());
      const State& s = world.state();
      // World::step ran the whole step; Newton's inputs and result (newton_v) are still in its
      // scratch, and v_start is where it started.
      REQUIRE(s.model_residual_known);
      const double scale = evaluate(model, s, s.v_start).scale;  // Newton's first iterate
      const VecX gradient = evaluate(model, s, s.scratch.newton_v).gradient;
      VecX remaining = -s.model_residual;
      double predicted = 0;
      if (test::iteration_count(world.profile(), "newton_predicted") > 0) {
        remaining -= s.scratch.newton_predicted_impulse;
        predicted = s.scratch.newton_predicted_impulse.norm();
        ++predicted_steps;
      }
      // The gradient here takes Newton's operations in Newton's order (positions, diagonal
      // product, the same pass), so it is Newton's to the bit; what separates r from it is
      // (g + p) - p, within eps |g + p| entry by entry: 2 eps (|g| + |p|) in norm.
      const double round_off = 2 * std::numeric_limits<double>::epsilon() * (gradient.norm() + predicted);
      if (gradient.norm() <= 0.1 * scale) {
        ++kept;
        CHECK((remaining - gradient).norm() <= round_off);
      } else {
        ++dropped;
        CHECK(remaining.norm() <= round_off);
      }
    }
    MESSAGE(iterations << " Newton iterations a step: gradient kept in " << kept << " steps, dropped in " << dropped
                       << "; " << predicted_steps << " with the predictor");
    CHECK(kept > 40);
    CHECK(predicted_steps > 20);
  }
}
