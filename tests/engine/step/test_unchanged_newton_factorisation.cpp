// A factorisation due in a Newton step is kept when the step's Hessian is the very matrix
// the solver last factorised (LinearSolver::holds_factor_of, bit for bit): a body at rest
// keeps every tet Hessian (solver.hessian_reuse_tolerance) and its A0 is the mass diagonal,
// so its H repeats step after step. Only then: a step that formed any tet Hessian afresh
// since the last factorisation changed H and factorises.
#include <doctest/doctest.h>

#include <string>

#include "tests/engine/step/snh_landing_box.hpp"

using namespace sinew;

namespace {

const std::string kUnchanged = "Newton's Hessian unchanged since the last factorisation";

}  // namespace

TEST_CASE("Newton keeps a due factorisation of an unchanged Hessian, and only then") {
  World world = test::snh_landing_box("\"newton_max_iterations\": 1, \"sleep_steps\": 0, \"refactor_interval\": 4");
  const int factorize = static_cast<int>(Stage::Factorize);
  int kept = 0, factorised = 0;
  bool formed_since_factorisation = false;
  for (int step = 0; step < 150; ++step) {
    CAPTURE(step);
    REQUIRE(world.step());
    const StepProfile& p = world.profile();
    const State& s = world.state();
    const bool formed = test::iteration_count(p, "newton_hessians_formed") > 0;
    const std::string& skipped = p.skipped[factorize];
    if (skipped == kUnchanged) {
      ++kept;
      // No tet formed its Hessian afresh since the factorisation kept, this step included.
      CHECK_FALSE(formed_since_factorisation);
      CHECK_FALSE(formed);
      CHECK(s.factor_exact);
      CHECK(s.factor_age == 0);
      CHECK(test::iteration_count(p, "newton_pcg") == 0);  // the step solved with its own factor
    } else if (skipped.empty()) {
      ++factorised;  // of this step's one assembly: its fresh Hessians are in the factor
      formed_since_factorisation = false;
    } else {
      formed_since_factorisation = formed_since_factorisation || formed;
    }
  }
  MESSAGE("factorisations kept " << kept << ", made " << factorised << " in 150 steps");
  CHECK(kept > 10);  // the box rests from about step 40: a factorisation is due every 4 steps
  CHECK(factorised > 0);
}
