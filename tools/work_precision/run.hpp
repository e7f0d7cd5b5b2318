#pragma once
// One simulation of the work-precision study: the scene stepped for a fixed simulated time,
// its surfaces and energy sampled at fixed times, its steps timed.
#include <map>
#include <string>
#include <vector>

#include "engine/world.hpp"

namespace sinew::wp {

// The state at the sample times: what errors are measured on.
struct Trajectory {
  std::vector<double> times;                  // s
  std::vector<std::vector<Vec3>> surface;     // per sample: every body's surface vertices, in body order
  std::vector<double> energy;                 // per sample: kinetic + elastic + gravity potential, J
};

struct RunResult {
  bool finite = true;        // false: a step failed (NaN/Inf, singular, too fast) and the run stopped
  int steps = 0;             // steps taken (= asked when finite)
  double step_seconds = 0;   // wall time inside World::step(), summed
  double step_cpu_seconds = 0;  // the process's CPU time over the same calls (robust to other
                                // processes sharing the cores; equals wall time on an idle
                                // machine with one thread)
  Trajectory samples;
  std::map<std::string, double> worst_violation;  // StepProfile::violation by kind, max over steps
  std::map<std::string, long> iterations;         // StepProfile::iterations by solver, summed
  int steps_at_sqp_cap = 0;
  // Beyond the solver's own measure (which depends on the projection mode): the worst
  // stretch |F m_j| of any element past a strain limit of its material axis m_j, over the
  // samples (0 without strain limits). Compares the projections of paper 001 on one scale.
  double axis_strain_excess = 0;
  // At the end: max over elements of |J - 1| (J = det F at the element centre) and the
  // total volume change sum J V / sum V - 1 (paper 003's volume preservation).
  double worst_volume_change = 0, total_volume_change = 0;
};

// Runs `steps` steps of `scene`, sampling every `sample_every` steps (and at the start).
RunResult run_scene(const SceneDesc& scene, int steps, int sample_every);

// Only the times of the same run (for repeats of cheap points); NaN if it fails.
struct RunTimes {
  double wall = 0, cpu = 0;  // s
};
RunTimes time_scene(const SceneDesc& scene, int steps);

}  // namespace sinew::wp
