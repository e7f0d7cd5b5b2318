// refactor_interval > 1 on the Newton path: a factorisation that preconditions a step's
// Hessian only in kNewtonPcgStruggling CG iterations or more, or not within kNewtonPcgCap
// (the CG stops and H is factorised), is spent: the next step factorises without trying it.
// A Stable Neo-Hookean box landing on a plane changes its Hessian fast enough, step to step,
// to run into both.
#include <doctest/doctest.h>

#include "engine/step/stages.hpp"
#include "engine/world.hpp"

using namespace sinew;

namespace {

World landing_box() {
  const char* text = R"({"h": 0.0166666666666667,
    "solver": {"newton_max_iterations": 1, "refactor_interval": 8, "delassus_reuse": 8},
    "bodies": [{"name": "box", "shape": [{"type": "box", "half_extents": [0.15, 0.1, 0.1]}],
      "transform": {"translate": [0, 0.15, 0], "rotation_deg": [0, 0, 8]}, "cell_size": 0.05,
      "elements": "tet", "material": {"model": "stable_neo_hookean", "E": 200000.0, "nu": 0.45, "rho": 1000},
      "damping": {"mass": 1}}],
    "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5}]})";
  return World(build_model(parse_scene_text(text, "landing_box", "."), [](const std::string&) {}));
}

int iterations(const StepProfile& profile, const char* name) {
  const auto it = profile.iterations.find(name);
  return it == profile.iterations.end() ? 0 : it->second;
}

}  // namespace

TEST_CASE("Newton: after a preconditioned CG that struggled, the next step factorises outright") {
  World world = landing_box();
  int struggles = 0, fallbacks = 0, preconditioned_steps = 0;
  bool last_struggled = false;
  for (int step = 0; step < 30; ++step) {
    REQUIRE(world.step());
    const StepProfile& p = world.profile();
    const int pcg = iterations(p, "newton_pcg"), fallback = iterations(p, "newton_pcg_fallbacks");
    const bool factorised = p.work.factorizations > 0;
    if (last_struggled) {
      // No CG tried: none ran (newton_pcg counts the converged ones' iterations, fallbacks
      // the stopped ones), and H was factorised.
      CHECK(pcg == 0);
      CHECK(fallback == 0);
      CHECK(factorised);
    }
    if (pcg > 0) ++preconditioned_steps;
    CHECK(pcg < kNewtonPcgCap + 1);  // one CG a step (one Newton iteration), stopped past the cap
    fallbacks += fallback;
    last_struggled = fallback > 0 || pcg >= kNewtonPcgStruggling;
    struggles += last_struggled ? 1 : 0;
    // A stopped CG factorised this very step.
    if (fallback > 0) CHECK(factorised);
  }
  MESSAGE("steps whose CG struggled " << struggles << " (stopped at the cap " << fallbacks
                                      << "), steps preconditioned " << preconditioned_steps);
  // The rule was exercised, and the older factorisations still served most steps.
  REQUIRE(struggles > 0);
  CHECK(preconditioned_steps > 15);
}
