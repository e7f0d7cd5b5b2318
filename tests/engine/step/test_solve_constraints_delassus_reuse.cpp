// solver.delassus_reuse: H^-1 on the touched nodes kept across steps' factorisations, the
// LCP corrected by the exact W lambda of its warm start (solve_constraints.cpp). A tet-mesh
// block (surface vertices are nodes: one node per contact row, so W comes from the touched
// inverse) dropped on a plane, with Stable Neo-Hookean and one Newton iteration per step as
// in sinew_bench_hyperelastic: the same tolerances met at every step, far fewer columns.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "tests/engine/step/contact_scenes.hpp"

using namespace sinew;
using namespace sinew::test;

namespace {

// A 0.2 x 0.1 x 0.2 m block of 4 x 2 x 4 cells, 6 tets each, as TetGen files.
std::string write_block() {
  const auto dir = std::filesystem::temp_directory_path() / "sinew_test_delassus_reuse";
  std::filesystem::create_directories(dir);
  const std::string base = (dir / "block").string();
  const int nx = 4, ny = 2, nz = 4;
  const double cell = 0.05;
  auto node = [&](int i, int j, int k) { return (i * (ny + 1) + j) * (nz + 1) + k; };
  std::ofstream nodes(base + ".node");
  nodes << (nx + 1) * (ny + 1) * (nz + 1) << " 3 0 0\n";
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j)
      for (int k = 0; k <= nz; ++k) nodes << node(i, j, k) << " " << i * cell << " " << j * cell << " " << k * cell << "\n";
  // Each cube split into 6 tets around its diagonal from corner (0,0,0) to (1,1,1).
  std::ofstream ele(base + ".ele");
  ele << 6 * nx * ny * nz << " 4 0\n";
  int t = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        auto c = [&](int di, int dj, int dk) { return node(i + di, j + dj, k + dk); };
        const int a = c(0, 0, 0), b = c(1, 1, 1);
        const int ring[6] = {c(1, 0, 0), c(1, 1, 0), c(0, 1, 0), c(0, 1, 1), c(0, 0, 1), c(1, 0, 1)};
        for (int r = 0; r < 6; ++r) ele << t++ << " " << a << " " << ring[r] << " " << ring[(r + 1) % 6] << " " << b << "\n";
      }
  return base + ".node";
}

SceneDesc drop(const std::string& mesh, int reuse, double E, double gap, int refactor_interval = 1) {
  const std::string text = R"({"h": 0.0166666666666667,
    "solver": {"newton_max_iterations": 1, "sleep_steps": 0, "delassus_reuse": )" + std::to_string(reuse) +
                           R"(, "refactor_interval": )" + std::to_string(refactor_interval) + R"(},
    "bodies": [{"name": "block", "tet_mesh": ")" + mesh + R"(", "transform": {"translate": [0, )" + std::to_string(gap) + R"(, 0]},
      "material": {"model": "stable_neo_hookean", "E": )" + std::to_string(E) + R"(, "nu": 0.45, "rho": 1000}, "damping": {"mass": 1}}],
    "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5}]})";
  return parse_scene_text(text, "delassus_reuse", ".");
}

struct Run {
  long columns = 0, refreshes = 0, sqp = 0, preconditioned_cg = 0;
  double worst_penetration = 0;
  bool every_step_converged = true;
  VecX x;
};

Run run(const SceneDesc& scene, int steps) {
  World world = make_world(scene);
  Run r;
  for (int i = 0; i < steps; ++i) {
    REQUIRE(world.step());
    const auto& it = world.profile().iterations;
    auto count = [&](const char* key) { return it.count(key) ? it.at(key) : 0L; };
    r.columns += count("solved_columns");
    r.refreshes += count("delassus_refreshes");
    r.sqp += count("sqp");
    r.preconditioned_cg += count("newton_pcg");
    // SQP stops at its cap only when it did not converge.
    if (count("sqp") >= scene.solver.sqp_max_iterations) r.every_step_converged = false;
    if (world.profile().violation.count("penetration"))
      r.worst_penetration = std::max(r.worst_penetration, world.profile().violation.at("penetration"));
  }
  r.x = world.state().x;
  return r;
}

}  // namespace

TEST_CASE("delassus_reuse: H^-1 kept across steps meets the same tolerances with far fewer solves") {
  const std::string mesh = write_block();
  const int steps = 60;  // falls, lands at step ~12, bounces and settles
  // Soft (E 20 kPa) and dropped from 20 cm: H changes much over the 30 steps one H^-1
  // serves, so the LCP's correction matters (without it the runs end 4 mm apart and the
  // reused one penetrates 12x deeper).
  const double E = 2e4, gap = 0.2;
  const Run fresh = run(drop(mesh, 1, E, gap), steps), reused = run(drop(mesh, 30, E, gap), steps);
  // And with Newton's directions preconditioned by a factorisation of up to 8 steps ago
  // (refactor_interval): the constraint solve then also refines with that older factor.
  const Run preconditioned = run(drop(mesh, 30, E, gap, 8), steps);
  const SolverDesc solver = drop(mesh, 1, E, gap).solver;
  const double tolerance = solver.contact_tolerance;
  MESSAGE("columns solved: " << fresh.columns << " (reuse 1) vs " << reused.columns << " (reuse 30); SQP iterations "
                             << fresh.sqp << " vs " << reused.sqp << "; refreshes " << reused.refreshes
                             << "; deepest penetration " << fresh.worst_penetration << " vs "
                             << reused.worst_penetration);
  REQUIRE(fresh.columns > 0);
  CHECK(fresh.every_step_converged);
  CHECK(reused.every_step_converged);
  CHECK(preconditioned.every_step_converged);
  CHECK(preconditioned.preconditioned_cg > 0);  // the older factorisation served as preconditioner
  CHECK(preconditioned.worst_penetration <= tolerance);
  CHECK(fresh.worst_penetration <= tolerance);
  CHECK(reused.worst_penetration <= tolerance);
  // One factorisation's H^-1 serves up to 30 steps, less when SQP stalls on it.
  CHECK(reused.columns < fresh.columns / 3);
  // Both rest on the plane; they may differ by what each run's tolerances accept: the
  // penetration (contact_tolerance) and, per step, the last SQP move (up to the stall
  // tolerance when a stall within tolerance ends the step).
  const double sqp_move = std::max(solver.sqp_position_tolerance, solver.sqp_stall_tolerance);
  double farthest = 0;
  for (Eigen::Index n = 0; n < fresh.x.size() / 3; ++n)
    farthest = std::max(farthest, (fresh.x.segment<3>(3 * n) - reused.x.segment<3>(3 * n)).norm());
  MESSAGE("farthest node apart after " << steps << " steps: " << farthest << " m");
  CHECK(farthest <= tolerance + sqp_move);
  double farthest_preconditioned = 0;
  for (Eigen::Index n = 0; n < fresh.x.size() / 3; ++n)
    farthest_preconditioned =
        std::max(farthest_preconditioned, (fresh.x.segment<3>(3 * n) - preconditioned.x.segment<3>(3 * n)).norm());
  MESSAGE("with refactor_interval 8: " << preconditioned.sqp << " SQP iterations, " << farthest_preconditioned
                                       << " m from reuse 1");
  CHECK(farthest_preconditioned <= tolerance + sqp_move);
}
