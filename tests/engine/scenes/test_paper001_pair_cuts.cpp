// The pair cuts (engine/constraints/strain_limit.hpp) on the finger of paper 001, fig. 3,
// pressed flat: where two principal stretches meet at the 1.02 limit of e3, the paper's
// rows alone let each QP step turn the largest stretch past its limit unseen, and the SQP
// needs more iterations to end within its tolerance (docs/ARCHITECTURE.md, "Why the pressed
// finger never settles"). With the cuts, fewer; both within the tolerance at every step.
#include "paper001_support.hpp"

using namespace sinew;
using namespace sinew::paper001;

namespace {

FlatFingerRun run_with_pair_cuts(const std::string& pair_cuts) {
  MESSAGE("pair cuts " << pair_cuts << ":");
  return run_flat_finger(
      [&](SceneDesc& scene) {
        for (BodyDesc& body : scene.bodies) body.strain_limit.pair_cuts = pair_cuts;
      },
      120);
}

}  // namespace

TEST_CASE("paper 001 fig. 3: pressed flat, the finger's SQP needs fewer iterations with the pair cuts") {
  const FlatFingerRun off = run_with_pair_cuts("off"), on = run_with_pair_cuts("on");
  CHECK(off.worst_violation <= off.tolerance);
  CHECK(on.worst_violation <= on.tolerance);
  CHECK(on.capped_steps == 0);
  // 276 -> 243 here (2026-12-07, AMD EPYC, with the SQP's KKT stop; 321 -> 262 before it);
  // the runs are chaotic in round-off: with the load scaled by 1 + k 1e-14, k = 0..3, the
  // ratio was 0.83-0.88 (`sinew run`, 120 frames, sleep off). So only the direction is
  // asserted, with a margin of a tenth.
  CHECK(on.sqp_iterations < 0.9 * off.sqp_iterations);
}

TEST_CASE("paper 001 fig. 3: pressed on its side and settled, the finger has no pair cut") {
  // The cuts are gated by the strain change a step makes at its start velocities
  // (strain_limit_rows.hpp): once the finger rests, none is a row (ungated, ~8 stayed, and
  // the degenerate LCP they made kept PGS at 3-17 sweeps a step).
  SceneDesc scene =
      load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper001_finger_side_anisotropic.json");
  scene.solver.sleep_steps = 0;
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  int cuts_while_moving = 0, cuts_at_rest = 0;
  double kinetic_energy = 0;
  for (int f = 0; f < 110; ++f) {
    REQUIRE(world.step());
    int cuts = 0;
    const RowTable& rows = world.state().rows;
    for (int i = 0; i < rows.size(); ++i)
      if (rows.kind[i] == RowKind::Strain && row_key_second(rows.key[i]) >= kStrainCutFirst) ++cuts;
    (f < 40 ? cuts_while_moving : cuts_at_rest) += cuts;
    if (f >= 80) kinetic_energy = std::max(kinetic_energy, world.kinetic_energy());
  }
  MESSAGE("cut rows in frames 0-39: " << cuts_while_moving << ", in frames 40-109: " << cuts_at_rest
                                      << "; largest kinetic energy over frames 80-109: " << kinetic_energy << " J");
  CHECK(cuts_while_moving > 0);
  CHECK(cuts_at_rest == 0);
}
