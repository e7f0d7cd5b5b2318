// sinew_bench_hyperelastic: paper 003, section 5 of issue 6. Stable Neo-Hookean drops of the
// shared TetGen meshes bunny_5 (5,266 tets) and cube_20 (13,200 tets) onto a ground plane,
// h = 1/60 s, E = 5e5 Pa, nu = 0.45, rho = 1000 kg/m^3, mass damping 1/s, CHOLMOD, the
// default solver.delassus_reuse and refactor_interval unless --delassus-reuse and
// --refactor-interval say otherwise. Per mesh:
// time per step with one Newton iteration (newton_max_iterations 1) and with Newton
// converged to a relative residual of 1e-6 (cap 50), on 1 and 2 threads
// (tbb::global_control); Newton and linear iterations per step. Each run starts the drop
// afresh, skips `--warmup` steps and times `--steps` (the body falls, lands and settles:
// contact rows and the SQP stage are included). Medians; JSON out. Skips a mesh cleanly when
// its files are absent.
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/stats_summary.hpp"
#include "engine/world.hpp"
#include "tools/cli_options.hpp"
#include "tools/hyperelastic_drop.hpp"

using namespace sinew;
using sinew::bench::drop_scene;
using sinew::bench::kMeshes;
using sinew::bench::MeshCase;

namespace {

struct Samples {
  std::vector<double> step_ms, newton, linear, assemble, factorize, solve, constraints, preconditioned, fallbacks,
      factorizations, hessians_formed;
  // 1 where the step's Newton ended above its tolerance (at its cap): with one iteration
  // nearly every step, in the converged mode the steps that did not converge.
  std::vector<double> above_tolerance;
  bool finite = true;

  // Another run's samples after these (a repeat pools every run's steps).
  void append(const Samples& o) {
    for (auto [to, from] : {std::pair{&step_ms, &o.step_ms}, {&newton, &o.newton}, {&linear, &o.linear},
                            {&assemble, &o.assemble}, {&factorize, &o.factorize}, {&solve, &o.solve},
                            {&constraints, &o.constraints}, {&preconditioned, &o.preconditioned},
                            {&fallbacks, &o.fallbacks}, {&factorizations, &o.factorizations},
                            {&hessians_formed, &o.hessians_formed}, {&above_tolerance, &o.above_tolerance}})
      to->insert(to->end(), from->begin(), from->end());
    finite = finite && o.finite;
  }
};

Samples run(const SceneDesc& scene, int warmup, int steps) {
  World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
  Samples s;
  for (int k = 0; k < warmup + steps && s.finite; ++k) {
    s.finite = world.step();
    if (k < warmup) continue;
    const StepProfile& p = world.profile();
    auto count = [&](const char* key) { return p.iterations.count(key) ? p.iterations.at(key) : 0; };
    auto ms = [&](Stage stage) { return p.ms[static_cast<int>(stage)]; };
    s.step_ms.push_back(p.step_ms);
    s.newton.push_back(count("newton"));
    // CHOLMOD: one direct solve per Newton iteration; PCG: its iterations.
    s.linear.push_back(scene.solver.linear == "pcg" ? count("pcg") : count("newton"));
    // refactor_interval > 1: CG iterations preconditioned with an older factorisation.
    s.preconditioned.push_back(count("newton_pcg"));
    // Those CG solves stopped at their cap (12 iterations, not in newton_pcg) or at a direction
    // without positive curvature, each replaced by a factorisation.
    s.fallbacks.push_back(count("newton_pcg_fallbacks"));
    s.factorizations.push_back(static_cast<double>(p.work.factorizations));
    // Tets whose projected Hessian was formed afresh (the others kept one: hessian_reuse_tolerance).
    s.hessians_formed.push_back(count("newton_hessians_formed"));
    const auto residual = p.violation.find("newton_residual");
    s.above_tolerance.push_back(residual != p.violation.end() && residual->second > scene.solver.newton_tolerance);
    s.assemble.push_back(ms(Stage::Assemble));
    s.factorize.push_back(ms(Stage::Factorize));
    s.solve.push_back(ms(Stage::Solve));
    s.constraints.push_back(p.constraint_ms());
  }
  return s;
}

double median(std::vector<double> v) { return v.empty() ? 0.0 : quantile(v, 0.5); }
double mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

}  // namespace

int main(int argc, char** argv) {
  const SolverDesc defaults;
  cli::Options options(
      "sinew_bench_hyperelastic [OPTION...]",
      "Paper 003's Stable Neo-Hookean drops of bunny_5 and cube_20 (../shared/meshes/tet/) onto a\n"
      "ground plane: time per step with one Newton iteration and with Newton converged to 1e-6,\n"
      "on 1 and 2 threads; Newton and linear iterations per step. Each run starts the drop afresh;\n"
      "medians; JSON out. A mesh whose files are absent is skipped.",
      {{"--steps", "N", "timed steps per run (default 60)"},
       {"--warmup", "N", "untimed steps first, from the start of the drop (default 5)"},
       {"--delassus-reuse", "N", "solver.delassus_reuse (default " + std::to_string(defaults.delassus_reuse) + ")"},
       {"--refactor-interval", "N",
        "solver.refactor_interval (default " + std::to_string(defaults.refactor_interval) + ")"},
       {"--stale-factor-precision", "P",
        "single or double: solver.stale_factor_precision (default " + defaults.stale_factor_precision + ")"},
       {"--hessian-reuse-tolerance", "T",
        "solver.hessian_reuse_tolerance: tets keep their projected Hessian while F\n"
        "                          moves by at most T, entrywise (default: the scene default; 0: formed\n"
        "                          at every assembly)"},
       {"--mesh", "NAME", "bunny_5 or cube_20: that mesh only (default: both)"},
       {"--mode", "MODE", "one_newton_iteration or newton_converged_1e-6: that mode only\n"
                          "                          (default: both)"},
       {"--threads", "T", "1 or 2: that thread count only (default: both)"},
       {"--repeat", "N", "run each case N times from the start (default 1): the figures pool every\n"
                         "                          run's timed steps, and each run's median step and the median of\n"
                         "                          those are reported too (the VM's noise drifts over minutes)"},
       {"--out", "FILE", "JSON results (default bench_hyperelastic.json)"}},
      0);
  int warmup = 5, steps = 60, repeat = 1, delassus_reuse = defaults.delassus_reuse, refactor_interval = defaults.refactor_interval;
  std::string out = "bench_hyperelastic.json", precision = defaults.stale_factor_precision;
  double reuse_tolerance = defaults.hessian_reuse_tolerance;
  std::string only_mesh, only_mode;  // empty: all
  int only_threads = 0;              // 0: 1 and 2
  try {
    if (!options.parse(argc - 1, argv + 1)) return 0;
    steps = options.get_int("--steps", steps, 1);
    warmup = options.get_int("--warmup", warmup, 0);
    repeat = options.get_int("--repeat", repeat, 1);
    delassus_reuse = options.get_int("--delassus-reuse", delassus_reuse, 1);
    refactor_interval = options.get_int("--refactor-interval", refactor_interval, 1);
    out = options.get("--out", out);
    reuse_tolerance = options.get_nonnegative("--hessian-reuse-tolerance", reuse_tolerance);
    if (const std::string p = options.get_one_of("--stale-factor-precision", {"single", "double"}); !p.empty()) precision = p;
    // A case name that matches nothing would run nothing and write an empty result.
    only_mesh = options.get_one_of("--mesh", sinew::bench::mesh_names());
    only_mode = options.get_one_of("--mode", {"one_newton_iteration", "newton_converged_1e-6"});
    const std::string threads = options.get_one_of("--threads", {"1", "2"});
    if (!threads.empty()) only_threads = cli::parse_int(threads, "option --threads", 1);
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "sinew_bench_hyperelastic: %s\n", e.what());
    return 2;
  }
  nlohmann::json results = {{"E", 5e5}, {"nu", 0.45}, {"rho", 1000}, {"h", 1.0 / 60}, {"warmup", warmup},
                            {"steps", steps}, {"delassus_reuse", delassus_reuse}, {"refactor_interval", refactor_interval},
                            {"stale_factor_precision", precision}, {"hessian_reuse_tolerance", reuse_tolerance}, {"repeat", repeat},
                            {"runs", nlohmann::json::array()}};
  for (const MeshCase& mesh : kMeshes) {
    if (!only_mesh.empty() && mesh.name != only_mesh) continue;
    const std::string base = sinew::bench::mesh_base(mesh);
    if (!sinew::bench::mesh_present(mesh)) {
      std::printf("%s: skipped (no %s.node/.ele)\n", mesh.name.c_str(), base.c_str());
      continue;
    }
    for (const auto& [mode, iterations, tolerance] :
         {std::tuple{"one_newton_iteration", 1, 1e-6}, std::tuple{"newton_converged_1e-6", 50, 1e-6}}) {
      if (!only_mode.empty() && only_mode != mode) continue;
      for (int threads : {1, 2}) {
        if (only_threads && threads != only_threads) continue;
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        try {
          SceneDesc scene = drop_scene(base + ".node", mesh, iterations, tolerance, delassus_reuse, refactor_interval);
          scene.solver.stale_factor_precision = precision;
          scene.solver.hessian_reuse_tolerance = reuse_tolerance;
          Samples s;
          std::vector<double> run_medians;
          for (int r = 0; r < repeat && s.finite; ++r) {
            const Samples one = run(scene, warmup, steps);
            run_medians.push_back(median(one.step_ms));
            s.append(one);
          }
          const double total_newton = [&] { double t = 0; for (double n : s.newton) t += n; return t; }();
          std::printf("%-8s %-22s threads %d: step median %8.2f ms (mean %.2f, p95 %.2f, max %.2f; assemble %.2f, factorize %.2f, solve+line search "
                      "%.2f, contact %.2f); Newton iterations median %.0f max %.0f; linear %.0f per step; factorisations "
                      "%.2f, preconditioned CG iterations %.2f (converged solves), CG fallbacks %.2f and tet Hessians formed "
                      "%.0f per step (means); %.0f of %zu steps ended above the Newton tolerance%s\n",
                      mesh.name.c_str(), mode, threads, median(s.step_ms), mean(s.step_ms), s.step_ms.empty() ? 0.0 : quantile(s.step_ms, 0.95),
                      s.step_ms.empty() ? 0.0 : *std::max_element(s.step_ms.begin(), s.step_ms.end()),
                      median(s.assemble), median(s.factorize),
                      median(s.solve), median(s.constraints), median(s.newton),
                      s.newton.empty() ? 0.0 : *std::max_element(s.newton.begin(), s.newton.end()), median(s.linear),
                      mean(s.factorizations), mean(s.preconditioned), mean(s.fallbacks), mean(s.hessians_formed),
                      mean(s.above_tolerance) * static_cast<double>(s.above_tolerance.size()), s.above_tolerance.size(),
                      s.finite ? "" : "  (stopped: non-finite)");
          if (repeat > 1) {
            std::printf("  median step of each of %d runs:", repeat);
            for (double m : run_medians) std::printf(" %.2f", m);
            std::printf(" ms; their median %.2f ms\n", median(run_medians));
          }
          std::fflush(stdout);
          results["runs"].push_back({{"mesh", mesh.name}, {"mode", mode}, {"threads", threads},
                                     {"finite", s.finite}, {"step_ms_median", median(s.step_ms)},
                                     {"step_ms_mean", mean(s.step_ms)},
                                     {"step_ms_p95", s.step_ms.empty() ? 0.0 : quantile(s.step_ms, 0.95)},
                                     {"step_ms_max", s.step_ms.empty() ? 0.0 : *std::max_element(s.step_ms.begin(), s.step_ms.end())},
                                     {"assemble_ms_median", median(s.assemble)},
                                     {"factorize_ms_median", median(s.factorize)},
                                     {"solve_ms_median", median(s.solve)},
                                     {"constraints_ms_median", median(s.constraints)},
                                     {"newton_median", median(s.newton)}, {"newton_total", total_newton},
                                     {"linear_median", median(s.linear)}, {"factorizations_mean", mean(s.factorizations)},
                                     {"preconditioned_cg_mean", mean(s.preconditioned)},
                                     {"preconditioned_cg_fallbacks_mean", mean(s.fallbacks)},
                                     {"hessians_formed_mean", mean(s.hessians_formed)},
                                     {"steps_above_newton_tolerance",
                                      mean(s.above_tolerance) * static_cast<double>(s.above_tolerance.size())},
                                     {"timed_steps", s.step_ms.size()}, {"repeats", repeat},
                                     {"step_ms_median_per_run", run_medians},
                                     {"step_ms_median_of_runs", median(run_medians)}});
        } catch (const InputError& e) {
          std::fprintf(stderr, "%s\n", e.what());
          return 2;
        }
      }
    }
  }
  write_file_atomically(out, [&](std::ostream& o) { o << results.dump(2) << "\n"; });
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
