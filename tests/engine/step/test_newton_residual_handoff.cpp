// Newton hands its quadratic model on to the constraint stage as the residual r = rhs - H v
// at its result (State::model_residual, solve_newton.cpp), formed without a product with H:
// -grad Phi(v), or 0 where Newton left more than a tenth of the step's scale, less the
// predicted force. Checked against an independent evaluation of grad Phi at the result,
// through the landing of the Stable Neo-Hookean box, with one Newton iteration a step and
// with Newton converged; and, where the last step was a CG direction taken whole without a
// line-search trial (stats: newton_model_gradient), against the quadratic model's gradient
// g + H d, formed again from the step's start.
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

struct HandoffCounts {
  int kept = 0, dropped = 0, predicted = 0, model = 0;
  double worst_left_out = 0;  // |grad Phi| at the result of the model's steps, of the scale, most
};

// Runs `steps` steps of world, checking each step's handed-on residual.
HandoffCounts check_handoff(World& world, int steps, int iterations) {
  const Model& model = world.model();
  HandoffCounts count;
  for (int step = 0; step < steps; ++step) {
    CAPTURE(step);
    REQUIRE(world.step());
    const State& s = world.state();
    // World::step ran the whole step; Newton's inputs and result (newton_v) are still in its
    // scratch, and v_start is where it started.
    REQUIRE(s.model_residual_known);
    const Evaluation start = evaluate(model, s, s.v_start);  // Newton's first iterate
    const double scale = start.scale;
    const VecX gradient = evaluate(model, s, s.scratch.newton_v).gradient;
    VecX remaining = -s.model_residual;
    double predicted = 0;
    if (test::iteration_count(world.profile(), "newton_predicted") > 0) {
      remaining -= s.scratch.newton_predicted_impulse;
      predicted = s.scratch.newton_predicted_impulse.norm();
      ++count.predicted;
    }
    // The gradient here takes Newton's operations in Newton's order (positions, diagonal
    // product, the same pass), so it is Newton's to the bit; what separates r from it is
    // (g + p) - p, within eps |g + p| entry by entry: 2 eps (|g| + |p|) in norm.
    const double eps = std::numeric_limits<double>::epsilon();
    if (test::iteration_count(world.profile(), "newton_model_gradient") > 0) {
      // The last step was a CG direction d taken whole with no line-search trial, at the
      // cap: Newton handed on the model's gradient g + H d, CG's residual negated,
      // -(b - alpha q) with q = H p and d = alpha p. Formed again here from the step's start
      // (one iteration: v_start + d) and H, the matrix it was solved with (state.system:
      // the one QP of these steps keeps it): the two differ by the round-offs of a product
      // with H, within gamma_(k+2) (|g| + |H| |d|) entrywise with k the most entries in a
      // column (Higham, 3.5), of alpha p, and of the final subtraction and the predictor.
      ++count.model;
      // The step's start is the last iterate's only with one iteration; with more, the
      // bound on what the model leaves out (below) is still checked.
      if (iterations == 1) {
        REQUIRE(test::iteration_count(world.profile(), "sqp_refactorisations") == 0);
        const VecX& d = s.scratch.direction;
        const SparseMatrix& H = s.system;
        const VecX model_gradient = start.gradient + H * d;
        const VecX magnitude = start.gradient.cwiseAbs() + H.cwiseAbs() * d.cwiseAbs();
        int k = 0;
        for (int c = 0; c < H.outerSize(); ++c)
          k = std::max(k, static_cast<int>(H.outerIndexPtr()[c + 1] - H.outerIndexPtr()[c]));
        const double gamma = (k + 4) * (eps / 2) / (1 - (k + 4) * (eps / 2));
        const double round_off = 2 * gamma * magnitude.norm() + 2 * eps * (model_gradient.norm() + predicted);
        if (model_gradient.norm() <= 0.1 * scale) CHECK((remaining - model_gradient).norm() <= round_off);
        else CHECK(remaining.norm() <= round_off);
      }
      // What the model leaves out, Phi's own gradient at the result ((H_exact - H) d, H's
      // Hessians projected and kept from nearby F), is within Newton's own tolerance of
      // the step's scale: Newton run to convergence would stop there too, so the constraint
      // stage loses nothing a converged Newton would have given it.
      const double left_out = gradient.norm() / scale;
      CHECK(left_out <= world.model().solver.newton_tolerance);
      count.worst_left_out = std::max(count.worst_left_out, left_out);
      continue;
    }
    const double round_off = 2 * eps * (gradient.norm() + predicted);
    if (gradient.norm() <= 0.1 * scale) {
      ++count.kept;
      CHECK((remaining - gradient).norm() <= round_off);
    } else {
      ++count.dropped;
      CHECK(remaining.norm() <= round_off);
    }
  }
  MESSAGE(iterations << " Newton iterations a step: gradient kept in " << count.kept << " steps, dropped in "
                     << count.dropped << ", the model's in " << count.model << " (grad Phi there at most "
                     << count.worst_left_out << " of the scale); " << count.predicted << " with the predictor");
  return count;
}

}  // namespace

TEST_CASE("Newton hands on its model as the residual at its result: -grad Phi there, less the predicted force") {
  for (const int iterations : {1, 30}) {
    CAPTURE(iterations);
    World world = test::snh_landing_box("\"newton_max_iterations\": " + std::to_string(iterations) +
                                        ", \"sleep_steps\": 0, \"refactor_interval\": 8");
    const HandoffCounts count = check_handoff(world, 60, iterations);
    CHECK(count.kept > 40);
    CHECK(count.predicted > 20);
  }
}

// A bar hanging from one end, heavily damped, with one Newton iteration a step: once it
// settles, its CG directions predict decreases within the energies' round-off, are taken
// without a line-search trial, and Newton hands on the model's gradient at the result.
TEST_CASE("Newton hands on the quadratic model's gradient after a step the line search left unchecked") {
  const auto hanging_bar = [](const std::string& reuse_tolerance) {
    const std::string text = R"({"h": 0.0166666666666667,
      "solver": {"newton_max_iterations": 1, "sleep_steps": 0, "refactor_interval": 8,
                 "hessian_reuse_tolerance": )" + reuse_tolerance + R"(},
      "bodies": [{"name": "bar", "shape": [{"type": "box", "half_extents": [0.2, 0.05, 0.05]}], "cell_size": 0.05,
        "elements": "tet", "material": {"model": "stable_neo_hookean", "E": 200000.0, "nu": 0.45, "rho": 1000},
        "damping": {"mass": 20}, "fixed": [{"half_space": {"point": [-0.19, 0, 0], "normal": [1, 0, 0]}}]}]})";
    return World(build_model(parse_scene_text(text, "hanging_bar", "."), [](const std::string&) {}));
  };
  World world = hanging_bar("1e-3");  // the default
  CHECK(check_handoff(world, 120, 1).model > 10);
  // Older kept Hessians leave more out of the model (solve_newton.cpp,
  // kModelGradientReuseLimit): Phi's gradient is evaluated there.
  World older = hanging_bar("1e-2");
  CHECK(check_handoff(older, 120, 1).model == 0);
}
