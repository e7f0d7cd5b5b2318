// sinew_bench_assembly: the hyperelastic pass of Newton's steps alone
// (engine/step/hyperelastic_derivatives.hpp) on paper 003's drop (tools/hyperelastic_drop.hpp)
// after --settle steps, when the body has landed and is deformed: with projected Hessians
// scattered into the system matrix (each Newton iteration's assembly) and without (the line
// search's trials), on 1 and 2 threads. The two passes alternate call by call so that the
// machine's drift touches both alike; medians and minima (the least disturbed call) in ms and
// ns a tet. A whole step's figures are sinew_bench_hyperelastic's; this one isolates the pass
// that most of them spend on. A mesh whose files are absent is skipped.
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"
#include "engine/io/stats_summary.hpp"
#include "engine/step/hyperelastic_derivatives.hpp"
#include "engine/world.hpp"
#include "tools/cli_options.hpp"
#include "tools/hyperelastic_drop.hpp"

using namespace sinew;

namespace {

struct PassTimes {
  std::vector<double> hessian_ms, gradient_ms;
};

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// `repeats` calls of each pass at the positions x, alternating.
PassTimes time_passes(const Model& model, const VecX& x, const SparseMatrix& pattern, int repeats) {
  std::vector<double> energy, force2;
  std::vector<Vec3> node_gradients;
  VecX gradient;
  SparseMatrix matrix = pattern;
  const std::vector<double> start(pattern.valuePtr(), pattern.valuePtr() + pattern.nonZeros());
  PassTimes times;
  for (int k = 0; k < repeats + 1; ++k) {  // the first call of each warms the buffers, untimed
    std::copy(start.begin(), start.end(), matrix.valuePtr());
    auto begin = std::chrono::steady_clock::now();
    hyperelastic_derivatives(model, x, false, energy, force2, gradient, matrix.valuePtr(), node_gradients);
    if (k > 0) times.hessian_ms.push_back(elapsed_ms(begin));
    begin = std::chrono::steady_clock::now();
    hyperelastic_derivatives(model, x, false, energy, force2, gradient, nullptr, node_gradients);
    if (k > 0) times.gradient_ms.push_back(elapsed_ms(begin));
  }
  return times;
}

// The least sample (quantile's nearest rank at 0).
double minimum(const std::vector<double>& v) { return quantile(v, 0.0); }

}  // namespace

int main(int argc, char** argv) {
  cli::Options options(
      "sinew_bench_assembly [OPTION...]",
      "The hyperelastic pass of a Newton iteration alone (energies, gradient and projected Hessians\n"
      "scattered into the system matrix; and energies and gradient only, as the line search's\n"
      "trials) on the landed Stable Neo-Hookean drops of bunny_5 and cube_20\n"
      "(../shared/meshes/tet/), on 1 and 2 threads, the two passes alternating call by call.\n"
      "Prints medians and minima in ms and ns a tet; JSON out. A mesh whose files are absent is\n"
      "skipped.",
      {{"--repeats", "N", "timed calls of each pass per mesh and thread count (default 100)"},
       {"--settle", "N", "steps of the drop before timing (default 20: landed and deformed)"},
       {"--mesh", "NAME", "bunny_5 or cube_20: that mesh only (default: both)"},
       {"--threads", "T", "1 or 2: that thread count only (default: both)"},
       {"--out", "FILE", "JSON results (default bench_assembly.json)"}},
      0);
  int repeats = 100, settle = 20, only_threads = 0;
  std::string out = "bench_assembly.json", only_mesh;
  try {
    if (!options.parse(argc - 1, argv + 1)) return 0;
    repeats = options.get_int("--repeats", repeats, 1);
    settle = options.get_int("--settle", settle, 0);
    out = options.get("--out", out);
    only_mesh = options.get_one_of("--mesh", bench::mesh_names());
    const std::string threads = options.get_one_of("--threads", {"1", "2"});
    if (!threads.empty()) only_threads = threads == "1" ? 1 : 2;
  } catch (const cli::UsageError& e) {
    std::fprintf(stderr, "sinew_bench_assembly: %s\n", e.what());
    return 2;
  }
  nlohmann::json results = {{"repeats", repeats}, {"settle_steps", settle}, {"runs", nlohmann::json::array()}};
  for (const bench::MeshCase& mesh : bench::kMeshes) {
    if (!only_mesh.empty() && mesh.name != only_mesh) continue;
    if (!bench::mesh_present(mesh)) {
      std::printf("%s: skipped (no %s.node/.ele)\n", mesh.name.c_str(), bench::mesh_base(mesh).c_str());
      continue;
    }
    try {
      // One Newton iteration a step, refactorised every 8 steps: the benchmark's real-time mode.
      World world(build_model(bench::drop_scene(bench::mesh_base(mesh) + ".node", mesh, 1, 1e-6, 64, 8),
                              [](const std::string&) {}),
                  {});
      for (int k = 0; k < settle; ++k)
        if (!world.step()) {
          std::fprintf(stderr, "sinew_bench_assembly: %s: the drop stopped at step %d\n", mesh.name.c_str(), k);
          return 1;
        }
      const Model& model = world.model();
      for (int threads : {1, 2}) {
        if (only_threads && threads != only_threads) continue;
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        const PassTimes t = time_passes(model, world.state().x, world.state().system, repeats);
        const double per_tet = 1e6 / model.num_elements;  // ms -> ns a tet
        std::printf("%-8s threads %d: Hessian pass median %.3f ms (min %.3f; %.0f ns a tet), gradient pass median "
                    "%.3f ms (min %.3f; %.0f ns a tet)\n",
                    mesh.name.c_str(), threads, quantile(t.hessian_ms, 0.5), minimum(t.hessian_ms),
                    quantile(t.hessian_ms, 0.5) * per_tet, quantile(t.gradient_ms, 0.5), minimum(t.gradient_ms),
                    quantile(t.gradient_ms, 0.5) * per_tet);
        std::fflush(stdout);
        results["runs"].push_back({{"mesh", mesh.name}, {"threads", threads}, {"tets", model.num_elements},
                                   {"hessian_ms_median", quantile(t.hessian_ms, 0.5)},
                                   {"hessian_ms_min", minimum(t.hessian_ms)},
                                   {"gradient_ms_median", quantile(t.gradient_ms, 0.5)},
                                   {"gradient_ms_min", minimum(t.gradient_ms)}});
      }
    } catch (const InputError& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 2;
    } catch (const std::exception& e) {  // no JSON then: a partial result would read as whole
      std::fprintf(stderr, "sinew_bench_assembly: %s: %s\n", mesh.name.c_str(), e.what());
      return 1;
    }
  }
  write_file_atomically(out, [&](std::ostream& o) { o << results.dump(2) << "\n"; });
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
