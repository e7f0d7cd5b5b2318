#pragma once
// What every case of sinew_stress shares: its result, checked stepping (a refused step must
// leave the state exactly as it was), scene loading, and a few measures of a state.
// Included once, by tools/stress.cpp (header-only so that the program stays one target).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "engine/analysis/element_fields.hpp"
#include "engine/world.hpp"

namespace sinew::stress {

struct Options {
  bool quick = false;  // the reduced CI run
};

// One case's outcome: PASS/FAIL, the text of its verdict line after that word, and the
// figures behind it (written to --out).
struct CaseResult {
  bool pass = true;
  std::string summary;
  nlohmann::json details = nlohmann::json::object();
};

inline std::string format(const char* fmt, auto... args) {
  std::string out(std::snprintf(nullptr, 0, fmt, args...), '\0');
  std::snprintf(out.data(), out.size() + 1, fmt, args...);
  return out;
}

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Positions, velocities and the embedded surfaces: everything a caller would write out.
inline bool state_finite(const World& world) {
  if (!world.state().x.allFinite() || !world.state().v.allFinite()) return false;
  for (const auto& surface : world.state().surface)
    for (const Vec3& p : surface)
      if (!p.allFinite()) return false;
  return true;
}

// How a run of steps ended. A refused step (World::step() false) stops the run, as `sinew
// run` stops: stepping again would repeat it.
struct RunOutcome {
  int steps = 0;            // steps completed
  int refused_at = -1;      // index of the refused step, -1 if none
  bool finite = true;       // no NaN/Inf in x, v or the surfaces after any step
  bool clean_rollback = true;  // a refused step left x and v bit-identical
  double max_speed = 0;     // fastest node over the run, m/s
  std::map<std::string, double> worst_violation;  // by kind, over the steps (profile.violation)
  bool completed() const { return refused_at < 0 && finite; }
};

// One checked step, recorded in `out`; false when the run must stop (refused or non-finite).
inline bool step_checked(World& world, RunOutcome& out) {
  const uint64_t before = world.state_hash();
  const bool ok = world.step();
  out.finite = state_finite(world);
  if (!out.finite) return false;
  if (!ok) {
    out.refused_at = out.steps;
    out.clean_rollback = world.state_hash() == before;
    return false;
  }
  ++out.steps;
  out.max_speed = std::max(out.max_speed, world.state().v.lpNorm<Eigen::Infinity>());
  for (const auto& [kind, value] : world.profile().violation)
    out.worst_violation[kind] = std::max(out.worst_violation[kind], value);
  return true;
}

// Steps `world` up to `steps` times; `after_step(k)` runs after each good step.
template <class AfterStep>
RunOutcome run_steps(World& world, int steps, AfterStep&& after_step) {
  RunOutcome out;
  for (int k = 0; k < steps && step_checked(world, out); ++k) after_step(k);
  return out;
}
inline RunOutcome run_steps(World& world, int steps) {
  return run_steps(world, steps, [](int) {});
}

inline nlohmann::json to_json(const RunOutcome& r) {
  return {{"steps", r.steps}, {"refused_at", r.refused_at}, {"finite", r.finite},
          {"clean_rollback", r.clean_rollback}, {"max_speed", r.max_speed},
          {"worst_violation", r.worst_violation}};
}

// "ran 240 steps" / "refused step 37 (rolled back)" / "NaN/Inf after step 12".
inline std::string describe(const RunOutcome& r) {
  if (!r.finite) return format("NaN/Inf in the state after step %d", r.steps + 1);
  if (r.refused_at >= 0)
    return format("refused step %d (%s)", r.refused_at + 1,
                  r.clean_rollback ? "rolled back" : "ROLLBACK CHANGED THE STATE");
  return format("ran %d steps", r.steps);
}

// Whether the scene has the constraint kind a profile.violation entry is about (the profile
// reports "energy" even where no element has a limit).
inline bool has_constraint_kind(const Model& m, const std::string& kind) {
  if (kind == "energy")
    return std::any_of(m.element_Umax.begin(), m.element_Umax.end(), [](double u) { return u > 0; });
  if (kind == "strain") return m.has_strain_limits;
  if (kind == "penetration") return !m.obstacles.empty() || m.bodies.size() > 1;
  return false;
}

inline void ignore_warning(const std::string&) {}

inline SceneDesc shipped_scene(const std::string& name) {
  return load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/" + name + ".json");
}

inline World make_world(const SceneDesc& scene) {
  return World(build_model(scene, ignore_warning), initial_velocities(scene));
}

inline World world_from_text(const std::string& text, const std::string& name) {
  return make_world(parse_scene_text(text, name, "."));
}

// Smallest and largest det F over the elements (element centres).
inline std::pair<double, double> volume_ratio_range(const World& world) {
  const auto fields = compute_element_fields(world.model(), world.state());
  const std::vector<double>& J = fields.at("volume_ratio");
  const auto [lo, hi] = std::minmax_element(J.begin(), J.end());
  return {*lo, *hi};
}

// Highest and lowest point of body b's embedded surface along y.
inline std::pair<double, double> surface_y_range(const World& world, int b) {
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : world.state().surface[b]) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
  return {lo, hi};
}

}  // namespace sinew::stress
