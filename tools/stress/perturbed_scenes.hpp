#pragma once
// Case perturbed_scenes: every shipped paper scene, run a few steps, then hit: every free node
// moved by 20-50 % of its body's cell size in a random direction and given a random extra
// velocity of up to 3 m/s per axis (up to 5.2 m/s), then run on. A run that reaches its end
// finite, or stops on a cleanly refused step (World::step() false, state rolled back bit for
// bit), passes; NaN/Inf in the state, or a rollback that changed it, fails. One line per
// scene on stdout as it ends (the progress of this case).
#include <filesystem>

#include "tools/stress/stress_case.hpp"

namespace sinew::stress {

namespace perturbed {

constexpr int kStepsBefore = 5;   // steps before the hit: contacts and loads are under way
constexpr double kKick = 3.0;     // m/s, per axis

// Fixed and driven nodes keep their prescribed motion.
inline void hit(World& world, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> fraction(0.2, 0.5), kick(-kKick, kKick);
  const Model& m = world.model();
  State& s = world.mutable_state();
  for (int n = 0; n < m.num_nodes; ++n) {
    if (m.free_index[n] < 0) continue;
    const Vec3 direction = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    s.x.segment<3>(3 * n) += fraction(rng) * m.bodies[m.node_body[n]].lattice.cell_size * direction;
    s.v.segment<3>(3 * n) += Vec3(kick(rng), kick(rng), kick(rng));
  }
}

inline std::vector<std::string> paper_scenes() {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(SINEW_SOURCE_DIR) + "/assets/scenes")) {
    const std::string stem = entry.path().stem().string();
    if (entry.path().extension() == ".json" && stem.rfind("paper", 0) == 0) names.push_back(stem);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// Quick run: one scene of each figure; where a figure has several, one with constraints.
inline const std::vector<std::string> kQuickScenes = {
    "paper000_beam_150kPa_U0.5", "paper000_collapse_50kPa_U50", "paper000_creature_500kPa_U100",
    "paper000_sphere_150kPa_U500", "paper001_beam_5kPa_isotropic", "paper001_finger_tip_isotropic",
    "paper001_vertical_hyperbolic", "paper003_elbow_snh"};
constexpr int kQuickStepsAfter = 25;

}  // namespace perturbed

inline CaseResult run_perturbed_scenes(const Options& options) {
  using namespace perturbed;
  const std::vector<std::string> names = options.quick ? kQuickScenes : paper_scenes();
  int completed = 0, refused = 0, failed = 0;
  double fastest = 0;
  CaseResult r;
  r.details["scenes"] = nlohmann::json::array();
  for (size_t i = 0; i < names.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    const SceneDesc scene = shipped_scene(names[i]);
    World world = make_world(scene);
    const int total = options.quick ? kStepsBefore + kQuickStepsAfter : scene.frames * scene.steps_per_frame();
    RunOutcome run;
    bool going = true;
    for (int k = 0; k < total && going; ++k) {
      if (k == kStepsBefore) hit(world, 1000 + i), run.max_speed = 0;  // report speeds after the hit
      going = step_checked(world, run);
    }
    const bool ok = run.finite && run.clean_rollback;
    completed += run.completed();
    refused += ok && run.refused_at >= 0;
    failed += !ok;
    fastest = std::max(fastest, run.max_speed);
    const double seconds = seconds_since(start);
    std::printf("  %-34s %s%s, fastest node after the hit %.3g m/s (%.1f s)\n", names[i].c_str(),
                ok ? "" : "FAIL: ", describe(run).c_str(), run.max_speed, seconds);
    std::fflush(stdout);
    nlohmann::json entry = to_json(run);
    entry["scene"] = names[i];
    entry["planned_steps"] = total;
    entry["seconds"] = seconds;
    r.details["scenes"].push_back(entry);
  }
  r.pass = failed == 0;
  r.summary = format("%d/%zu scenes ok: %d ran to the end finite, %d stopped on a cleanly refused step, %d NaN "
                     "or bad rollback; fastest node after a hit %.3g m/s",
                     int(names.size()) - failed, names.size(), completed, refused, failed, fastest);
  return r;
}

}  // namespace sinew::stress
