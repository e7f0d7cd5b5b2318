// refactor_interval > 1 on the Newton path: a factorisation with which a step's
// preconditioned CG fails (unconverged after kNewtonPcgCap iterations; H is then factorised)
// is spent: the next step factorises at its first Newton iteration without trying it, and
// preconditions its later iterations with that factorisation. A Stable Neo-Hookean box
// landing on a plane changes its Hessian fast enough, step to step, to run into it.
#include <doctest/doctest.h>

#include <string>

#include "engine/step/stages.hpp"
#include "engine/world.hpp"
#include "tests/engine/step/snh_landing_box.hpp"

using namespace sinew;

namespace {

World landing_box(int newton_iterations) {
  return test::snh_landing_box("\"newton_max_iterations\": " + std::to_string(newton_iterations) +
                               ", \"refactor_interval\": 8, \"delassus_reuse\": 8");
}

int iterations(const StepProfile& profile, const char* name) { return test::iteration_count(profile, name); }

}  // namespace

TEST_CASE("Newton: after a preconditioned CG that failed, the next step factorises outright") {
  World world = landing_box(1);
  int fallbacks = 0, preconditioned_steps = 0;
  bool last_failed = false;
  for (int step = 0; step < 30; ++step) {
    REQUIRE(world.step());
    const StepProfile& p = world.profile();
    const int pcg = iterations(p, "newton_pcg"), fallback = iterations(p, "newton_pcg_fallbacks");
    const bool factorised = p.work.factorizations > 0;
    if (last_failed) {
      // No CG tried: none ran (newton_pcg counts the converged ones' iterations, fallbacks
      // the stopped ones), and H was factorised.
      CHECK(pcg == 0);
      CHECK(fallback == 0);
      CHECK(factorised);
    }
    if (pcg > 0) ++preconditioned_steps;
    CHECK(pcg < kNewtonPcgCap + 1);  // one CG a step (one Newton iteration), stopped past the cap
    fallbacks += fallback;
    last_failed = fallback > 0;
    // A stopped CG factorised this very step.
    if (fallback > 0) CHECK(factorised);
  }
  MESSAGE("steps whose CG failed " << fallbacks << ", steps preconditioned " << preconditioned_steps);
  // The rule was exercised, and the older factorisations still served most steps.
  REQUIRE(fallbacks > 0);
  CHECK(preconditioned_steps > 15);
}

TEST_CASE("Newton: the factorisation that replaces a spent one serves the step's later iterations") {
  World world = landing_box(4);
  int after_failure = 0, preconditioned_after = 0;
  for (int step = 0; step < 30; ++step) {
    // Whether the last step's CG failed.
    const bool spent = world.state().newton_factor_spent;
    REQUIRE(world.step());
    const StepProfile& p = world.profile();
    if (!spent) continue;
    // One factorisation at the first Newton iteration, more only for a CG of its own that
    // stopped (not one per Newton iteration, as a step whose factorisation is due takes).
    CHECK(p.work.factorizations == 1 + iterations(p, "newton_pcg_fallbacks"));
    ++after_failure;
    if (iterations(p, "newton_pcg") > 0) ++preconditioned_after;
  }
  MESSAGE("steps after a failed CG " << after_failure << ", of which preconditioned after their factorisation "
                                    << preconditioned_after);
  REQUIRE(after_failure > 0);
  CHECK(preconditioned_after > 0);
}
