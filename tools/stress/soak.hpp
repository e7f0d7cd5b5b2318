#pragma once
// Case soak: 10,000 steps (quick: 1,000) of two small scenes stepped side by side, so that
// both step paths are soaked: linear (corotational hex with an energy limit and tet with
// strain limits) and Newton (two Stable Neo-Hookean tet cubes), each pair on a shaken table
// (kinematic obstacle, contact, friction, body-body contact). Resident memory of the process
// (/proc/self/statm) must not grow after warm-up by more than kMaxGrowth.
//
// Why 1 MiB: after warm-up every buffer has met the largest row count of the shaking cycle,
// so a step allocates and frees the same sizes again; what moves the resident size then is
// the allocator (glibc keeps up to 128 KiB of freed memory at the top of each of its arenas
// before trimming, one arena per worker thread) and 4 KiB page granularity: a few hundred KiB
// on the 2-core machine. A leak of the smallest heap block (32 B) per step of each scene over
// the 9,000 steps after warm-up is 576 KiB, a leak of one state vector (~1 KiB here) 18 MiB;
// the bound is above the allocator noise and catches any leak of more than ~60 B per step of
// each scene in the full run (~600 B in the quick one).
#include <unistd.h>

#include <fstream>

#include "engine/core/progress.hpp"
#include "engine/io/stats_summary.hpp"
#include "tools/stress/stress_case.hpp"

namespace sinew::stress {

namespace soak {

constexpr double kMaxGrowth = 1 << 20;  // bytes
constexpr double kPeriod = 1.0;         // s, one shaking cycle

// Resident set size in bytes (second field of /proc/self/statm, in pages); 0 if unreadable.
inline double resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  if (!(statm >> pages >> resident)) return 0;
  return double(resident) * double(sysconf(_SC_PAGESIZE));
}

// A table (plane) shaken along a diamond in x-y once a period: 0.08 m up and 0.05 m to one
// side and back, then to the other. Its velocity flips at each keyframe, so the bodies hop,
// land and slide again and again.
inline std::string table(double duration) {
  const double x[4] = {0, 0.05, 0, -0.05}, y[4] = {0, 0.08, 0, 0.08};
  std::string keyframes;
  for (int k = 0; k <= int(4 * duration / kPeriod) + 1; ++k)
    keyframes += format(R"(%s{"t": %g, "position": [%g, %g, 0]})", k ? ", " : "", 0.25 * kPeriod * k, x[k % 4],
                        y[k % 4]);
  return R"({"type": "plane", "friction": 0.5, "motion": {"keyframes": [)" + keyframes + "]}}";
}

// Two 0.2 m cubes 2 cm apart on the table: within the contact margin (a quarter of the 0.1 m
// cell), so body-body contact rows are built every step. Linear: a corotational hex cube with
// an energy limit (binding on landings) and a corotational tet cube with strain limits 0.98-1.02.
// Hyperelastic (Newton): two Stable Neo-Hookean tet cubes. Surface resolution 0.09 m keeps
// the contact rows few (a step costs milliseconds) and off the mesher's grid (a box face on
// its sample grid comes out with zero-area triangles that break body-body contact: see
// the stress results' notes).
inline std::string scene_text(bool hyperelastic, double duration) {
  const char* cube = R"({"name": "%s", "shape": [{"type": "box", "half_extents": [0.1, 0.1, 0.1]}], "cell_size": 0.1,
      "surface_resolution": 0.09, "transform": {"translate": [%g, 0.1001, 0]}, %s})";
  const std::string a =
      hyperelastic
          ? format(cube, "a", -0.11, R"("elements": "tet", "material": {"model": "stable_neo_hookean", "E": 1e5,
                   "nu": 0.3, "rho": 1000}, "damping": {"mass": 2})")
          : format(cube, "a", -0.11, R"("material": {"model": "corotational", "E": 1e5, "nu": 0.3, "rho": 1000},
                   "damping": {"stiffness": 0.01}, "energy_limit": {"Umax": 2e-3})");
  const std::string b =
      hyperelastic
          ? format(cube, "b", 0.11, R"("elements": "tet", "material": {"model": "stable_neo_hookean", "E": 1e5,
                   "nu": 0.3, "rho": 1000}, "damping": {"mass": 2})")
          : format(cube, "b", 0.11, R"("elements": "tet", "material": {"model": "corotational", "E": 1e5, "nu": 0.3,
                   "rho": 1000}, "damping": {"stiffness": 0.01}, "strain_limit": {"smin": 0.98, "smax": 1.02})");
  return R"({"bodies": [)" + a + ", " + b + R"(], "obstacles": [)" + table(duration) + "]}";
}

}  // namespace soak

inline CaseResult run_soak(const Options& options) {
  using namespace soak;
  const int steps = options.quick ? 1000 : 10000;
  const int warmup = std::max(steps / 10, 180);  // at least 3 shaking cycles at h = 1/60 s
  const double duration = steps / 60.0 + 1;
  World worlds[2] = {world_from_text(scene_text(false, duration), "soak_linear"),
                     world_from_text(scene_text(true, duration), "soak_hyperelastic")};
  RunOutcome runs[2];
  double at_warmup = 0, peak = 0;
  std::vector<double> step_ms;  // both scenes' steps together
  Progress progress("soak", steps);
  for (int k = 0; k < steps; ++k) {
    if (!step_checked(worlds[0], runs[0]) || !step_checked(worlds[1], runs[1])) break;
    step_ms.push_back(worlds[0].profile().step_ms + worlds[1].profile().step_ms);
    if (k + 1 == warmup) at_warmup = peak = resident_bytes();
    if (k + 1 > warmup && ((k + 1) % 50 == 0 || k + 1 == steps)) peak = std::max(peak, resident_bytes());
    progress.update(k + 1);
  }
  progress.finish();
  const double growth = peak - at_warmup;
  const std::ptrdiff_t n = std::ssize(step_ms);
  const std::ptrdiff_t tenth = std::min<std::ptrdiff_t>(n, std::max<std::ptrdiff_t>(1, n / 10));
  const double early = quantile(std::vector<double>(step_ms.begin(), step_ms.begin() + tenth), 0.5);
  const double late = quantile(std::vector<double>(step_ms.end() - tenth, step_ms.end()), 0.5);
  CaseResult r;
  const bool completed = runs[0].completed() && runs[1].completed() && runs[0].steps == steps;
  r.pass = completed && at_warmup > 0 && growth <= kMaxGrowth;
  r.summary = format("linear scene %s, Newton scene %s, of %d, finite; resident memory %.1f MiB after %d warm-up "
                     "steps, grew %.0f KiB after (bound %.0f KiB); median step of both %.2f ms in the first tenth, "
                     "%.2f ms in the last",
                     describe(runs[0]).c_str(), describe(runs[1]).c_str(), steps, at_warmup / (1 << 20), warmup,
                     growth / 1024, kMaxGrowth / 1024, early, late);
  r.details["linear"] = to_json(runs[0]);
  r.details["hyperelastic"] = to_json(runs[1]);
  r.details["warmup_steps"] = warmup;
  r.details["resident_bytes_at_warmup"] = at_warmup;
  r.details["resident_bytes_peak_after"] = peak;
  r.details["growth_bytes"] = growth;
  r.details["bound_bytes"] = kMaxGrowth;
  r.details["median_step_ms_first_tenth"] = early;
  r.details["median_step_ms_last_tenth"] = late;
  return r;
}

}  // namespace sinew::stress
