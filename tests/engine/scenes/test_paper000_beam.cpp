// Paper 000, fig. 3 ("the maximum deformation of the beam"): a compliant beam with energy
// limits sags less the lower the limit,
// and every element ends at or below its limit (up to the SQP tolerance).
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "engine/analysis/element_fields.hpp"
#include "engine/simulate_frame.hpp"

using namespace sinew;

namespace {

struct BeamResult {
  double tip_sag = 0;         // m, largest downward displacement of the free end (averaged over its nodes)
  double worst_violation = 0; // max over every step of the worst Ue/Umax - 1
  double min_active_ratio = 1, max_active_ratio = 0;  // spread of Ue/Umax over active elements
  int active = 0;
  double sqp_tolerance = 0;
};

BeamResult run_beam(const std::string& variant, int frames) {
  const SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_beam_" + variant + ".json");
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  BeamResult r;
  r.sqp_tolerance = scene.solver.sqp_tolerance;
  const Model& m = world.model();
  double tip_x = -1e300;
  for (int n = 0; n < m.num_nodes; ++n) tip_x = std::max(tip_x, m.rest_x[3 * n]);
  std::vector<int> tip;
  for (int n = 0; n < m.num_nodes; ++n)
    if (m.rest_x[3 * n] > tip_x - 1e-9) tip.push_back(n);
  for (int f = 0; f < frames; ++f) {
    const FrameStats stats = simulate_frame(world, scene.steps_per_frame());
    REQUIRE(stats.finite);
    if (stats.violation.count("energy")) r.worst_violation = std::max(r.worst_violation, stats.violation.at("energy"));
    double sag = 0;
    for (int n : tip) sag += (m.rest_x[3 * n + 1] - world.state().x[3 * n + 1]) / tip.size();
    r.tip_sag = std::max(r.tip_sag, sag);
  }
  const auto fields = compute_element_fields(m, world.state());
  for (double ratio : fields.at("energy_ratio"))
    if (ratio > 0.9) {
      ++r.active;
      r.min_active_ratio = std::min(r.min_active_ratio, ratio);
      r.max_active_ratio = std::max(r.max_active_ratio, ratio);
    }
  return r;
}

}  // namespace

TEST_CASE("paper 000 fig. 3: lower energy limits sag less, and limits hold within the SQP tolerance") {
  const int frames = 120;  // 2 s: past the first and largest swing of every variant
  const BeamResult free_beam = run_beam("150kPa", frames);
  const BeamResult stiff = run_beam("2MPa", frames);
  const BeamResult u1 = run_beam("150kPa_U1.0", frames);
  const BeamResult u05 = run_beam("150kPa_U0.5", frames);
  const BeamResult u01 = run_beam("150kPa_U0.1", frames);
  MESSAGE("tip sag: 150 kPa " << free_beam.tip_sag << " m, Umax 1.0 J " << u1.tip_sag << ", 0.5 J " << u05.tip_sag
                              << ", 0.1 J " << u01.tip_sag << ", 2 MPa " << stiff.tip_sag);
  CHECK(free_beam.tip_sag > u1.tip_sag);
  CHECK(u1.tip_sag > u05.tip_sag);
  CHECK(u05.tip_sag > u01.tip_sag);
  CHECK(u01.tip_sag > stiff.tip_sag);
  for (const BeamResult* r : {&u1, &u05, &u01}) {
    MESSAGE("worst Ue/Umax - 1 over the run: " << r->worst_violation << "; at rest " << r->active
                                                << " elements within 10 % of the limit, Ue/Umax from "
                                                << r->min_active_ratio << " to " << r->max_active_ratio);
    CHECK(r->worst_violation <= r->sqp_tolerance);
    CHECK(r->max_active_ratio <= 1 + r->sqp_tolerance);
    CHECK(r->active > 0);
  }
}
