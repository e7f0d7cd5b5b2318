// Paper 000, sec. 6.2: exact energy-limit Jacobians (eqs. 15-18) against warped elastic
// forces, on the fig. 3 beam (E 150 kPa) for Umax 0.5, 0.1, 0.05, 0.01 J. For each: SQP and
// PGS iterations, steps that hit the SQP cap, worst violation, constraint-stage time.
// Writes JSON and a Markdown table.
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "engine/io/atomic_file.hpp"
#include "engine/io/stats_summary.hpp"
#include "engine/simulate_frame.hpp"
#include "tools/cli_options.hpp"

using namespace sinew;

namespace {

struct Outcome {
  long sqp = 0, pgs = 0;
  int capped = 0, steps = 0;
  double worst = 0, constraint_ms_total = 0, constraint_ms_median = 0;
};

Outcome run(double Umax, const std::string& jacobian, int frames) {
  SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_beam_150kPa.json");
  scene.bodies[0].energy_limit.enabled = true;
  scene.bodies[0].energy_limit.Umax = Umax;
  scene.bodies[0].energy_limit.jacobian = jacobian;
  // Every step simulated: a beam that falls asleep once its limit holds it (at small Umax,
  // within a second) would make later steps free and hide the solver's work.
  scene.solver.sleep_steps = 0;
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  Outcome o;
  std::vector<double> ms;
  for (int f = 0; f < frames; ++f) {
    for (int s = 0; s < scene.steps_per_frame(); ++s) {
      world.step();
      const StepProfile& p = world.profile();
      const int sqp = p.iterations.count("sqp") ? p.iterations.at("sqp") : 0;
      o.sqp += sqp;
      o.pgs += p.iterations.count("pgs") ? p.iterations.at("pgs") : 0;
      o.capped += p.ended_at_sqp_cap(scene.solver.sqp_max_iterations);
      o.worst = std::max(o.worst, p.violation.count("energy") ? p.violation.at("energy") : 0.0);
      const double c = p.constraint_ms();
      o.constraint_ms_total += c;
      ms.push_back(c);
      ++o.steps;
    }
  }
  o.constraint_ms_median = quantile(ms, 0.5);
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  cli::Options options("sinew_bench_jacobian [FRAMES] [OUT]",
                       "Paper 000's exact vs warped energy-limit Jacobians on the fig. 3 beam (E 150 kPa) for\n"
                       "Umax 0.5, 0.1, 0.05, 0.01 J, bodies never sleeping: SQP and PGS iterations, steps at the\n"
                       "SQP cap, worst violation, constraint-stage time. Prints a Markdown table, writes JSON.\n"
                       "FRAMES: frames to simulate per run (default 120); OUT: JSON results (default\n"
                       "bench_jacobian.json).",
                       {}, 0, 2);
  int frames = 120;
  std::string out = "bench_jacobian.json";
  try {
    if (!options.parse(argc - 1, argv + 1)) return 0;
    const std::vector<std::string>& args = options.positional();
    if (!args.empty()) frames = cli::parse_int(args[0], "FRAMES", 1);
    if (args.size() > 1) out = args[1];
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "sinew_bench_jacobian: %s\n", e.what());
    return 2;
  }
  nlohmann::json results = nlohmann::json::array();
  std::ostringstream table;
  table << "| Umax (J) | Jacobian | SQP iterations | PGS iterations | steps at SQP cap | worst Ue/Umax-1 | constraint stage total (ms) | median per step (ms) |\n"
        << "|---|---|---|---|---|---|---|---|\n";
  for (double Umax : {0.5, 0.1, 0.05, 0.01}) {
    for (const char* mode : {"exact", "warped"}) {
      const Outcome o = run(Umax, mode, frames);
      char line[512];
      std::snprintf(line, sizeof line, "| %g | %s | %ld | %ld | %d / %d | %.2e | %.1f | %.3f |\n", Umax, mode, o.sqp,
                    o.pgs, o.capped, o.steps, o.worst, o.constraint_ms_total, o.constraint_ms_median);
      table << line;
      std::fputs(line, stdout);
      std::fflush(stdout);
      results.push_back({{"Umax", Umax}, {"jacobian", mode}, {"sqp_iterations", o.sqp}, {"pgs_iterations", o.pgs},
                         {"steps_at_cap", o.capped}, {"steps", o.steps}, {"worst_violation", o.worst},
                         {"constraint_ms_total", o.constraint_ms_total}, {"constraint_ms_median", o.constraint_ms_median}});
    }
  }
  write_file_atomically(out, [&](std::ostream& s) { s << nlohmann::json{{"frames", frames}, {"runs", results}}.dump(2) << "\n"; });
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
