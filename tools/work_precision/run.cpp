#include "tools/work_precision/run.hpp"

#include <chrono>
#include <ctime>
#include <cmath>
#include <limits>

#include "tools/work_precision/measures.hpp"

namespace sinew::wp {

namespace {

World make_world(const SceneDesc& scene) {
  return World(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
}

void sample(const World& world, RunResult& r) {
  Trajectory& t = r.samples;
  t.times.push_back(world.state().t);
  std::vector<Vec3> all;
  for (const std::vector<Vec3>& body : world.state().surface) all.insert(all.end(), body.begin(), body.end());
  t.surface.push_back(std::move(all));
  t.energy.push_back(total_energy(world));
  r.axis_strain_excess = std::max(r.axis_strain_excess, axis_strain_excess(world));
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

// Wall and CPU time of one step added to `times`; false if it failed.
bool timed_step(World& world, RunTimes& times) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu = process_cpu_seconds();
  const bool ok = world.step();
  times.cpu += process_cpu_seconds() - cpu;
  times.wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return ok;
}

}  // namespace

RunResult run_scene(const SceneDesc& scene, int steps, int sample_every) {
  World world = make_world(scene);
  RunResult r;
  sample(world, r);
  RunTimes times;
  for (int s = 1; s <= steps; ++s) {
    const bool ok = timed_step(world, times);
    r.step_seconds = times.wall;
    r.step_cpu_seconds = times.cpu;
    if (!ok) {
      r.finite = false;
      break;
    }
    r.steps = s;
    const StepProfile& p = world.profile();
    for (const auto& [kind, value] : p.violation) r.worst_violation[kind] = std::max(r.worst_violation[kind], value);
    for (const auto& [solver, count] : p.iterations) r.iterations[solver] += count;
    if (p.ended_at_sqp_cap(scene.solver.sqp_max_iterations)) ++r.steps_at_sqp_cap;
    if (s % sample_every == 0) sample(world, r);
  }
  const VolumeChange volume = volume_change(world);
  r.worst_volume_change = volume.worst;
  r.total_volume_change = volume.total;
  return r;
}

RunTimes time_scene(const SceneDesc& scene, int steps) {
  World world = make_world(scene);
  RunTimes times;
  for (int s = 0; s < steps; ++s)
    if (!timed_step(world, times)) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      return {nan, nan};
    }
  return times;
}

}  // namespace sinew::wp
