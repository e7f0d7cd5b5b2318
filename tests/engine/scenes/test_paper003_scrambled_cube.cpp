// Paper 003, fig. 3: a Stable Neo-Hookean cube whose vertices are scattered at random
// returns to its rest shape (up to a rigid motion), whatever the scramble: the energy is
// defined and smooth for inverted and degenerate elements, so Newton on backward Euler
// always has a descent direction back to rest. Classic Neo-Hookean (log J) is undefined
// for J <= 0, which a scramble produces in most elements: its run is reported, not asserted.
#include <doctest/doctest.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "engine/world.hpp"

using namespace sinew;

namespace {

// A 1 m cube, 4 x 4 x 4 cells of 0.25 m split into 6 tets each (125 nodes, 384 tets),
// nu 0.49, no gravity, nothing fixed.
//
// Time step and damping: the test asks for the rest shape, not for the dynamics, so a
// large step makes backward Euler strongly dissipative. With E 1e5 Pa, rho 1000 kg/m^3 the
// slowest shear mode has omega ~ pi c_s / L = pi sqrt(mu / rho) ~ 18 rad/s; with h = 0.5 s
// (omega h ~ 9) each step keeps ~1 / (omega h)^2 ~ 1 % of that mode's energy, and mass
// damping 2/s takes more. Newton: up to 30 iterations per step, to 1e-8 (with 15, the
// truncated solves sent some runs flying off at ~100 m/s). What matters is where the
// untangling ends, decided in the first steps: 2 steps (1 s); 200 seeds take ~47 s on the
// 2-core machine (over the 30 s aimed at; 10 steps took 130 s). Longer runs (40 steps
// of 0.5 s, 150 of 1/30 s, 300 of 1/60 s, E 1e4..1e5) ended in the same tangled states.
constexpr int kSteps = 2;
constexpr double kSize = 1.0;  // m, the cube's edge
constexpr unsigned kSeeds = 200;

Model scrambled_cube_model(const char* material) {
  char text[1024];
  std::snprintf(text, sizeof text, R"({"h": 0.5, "gravity": [0, 0, 0],
    "solver": {"newton_tolerance": 1e-8, "newton_max_iterations": 30},
    "bodies": [{"name": "cube", "shape": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}],
      "cell_size": 0.25, "elements": "tet", "damping": {"mass": 2},
      "material": {"model": "%s", "E": 1e5, "nu": 0.49, "rho": 1000}}]})",
                material);
  return build_model(parse_scene_text(text, "scrambled_cube", "."), [](const std::string&) {});
}

// Every node at a uniform random point of the cube of twice the body's volume (edge
// 2^(1/3) L) around its centre.
void scramble(World& world, unsigned seed) {
  std::mt19937_64 rng(seed);
  const double half = 0.5 * std::cbrt(2.0) * kSize;
  std::uniform_real_distribution<double> coordinate(-half, half);
  VecX& x = world.mutable_state().x;
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = coordinate(rng);
}

// Largest distance of a node from the rest shape moved by the best-fit rotation and
// translation (Kabsch: R from the SVD of the cross-covariance, det R = +1).
double rigid_fit_error(const Model& model, const VecX& x) {
  const int n = model.num_nodes;
  Vec3 rest_mean = Vec3::Zero(), mean = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    rest_mean += model.rest_x.segment<3>(3 * i) / n;
    mean += x.segment<3>(3 * i) / n;
  }
  Mat3 covariance = Mat3::Zero();
  for (int i = 0; i < n; ++i)
    covariance += (x.segment<3>(3 * i) - mean) * (model.rest_x.segment<3>(3 * i) - rest_mean).transpose();
  Eigen::JacobiSVD<Mat3> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
  const Mat3 R = svd.matrixU() * D * svd.matrixV().transpose();
  double worst = 0;
  for (int i = 0; i < n; ++i)
    worst = std::max(worst, (mean + R * (model.rest_x.segment<3>(3 * i) - rest_mean) - x.segment<3>(3 * i)).norm());
  return worst;
}

struct Outcome {
  bool finite = true;       // no NaN/Inf in the state at any step
  int failed_steps = 0;     // steps World::step() refused (state rolled back)
  double error = 0;         // rigid_fit_error at the end, m
  int newton = 0;           // Newton iterations over the run
};

Outcome run_scrambled(const Model& model, unsigned seed) {
  World world(model);
  scramble(world, seed);
  Outcome out;
  for (int s = 0; s < kSteps; ++s) {
    if (!world.step()) ++out.failed_steps;
    out.newton += world.profile().iterations.count("newton") ? world.profile().iterations.at("newton") : 0;
    out.finite = out.finite && world.state().x.allFinite() && world.state().v.allFinite();
  }
  out.error = rigid_fit_error(model, world.state().x);
  return out;
}

}  // namespace

// The Stable Neo-Hookean runs, made once for both test cases below.
const std::vector<Outcome>& stable_neo_hookean_outcomes() {
  static const std::vector<Outcome> outcomes = [] {
    const Model model = scrambled_cube_model("stable_neo_hookean");
    std::vector<Outcome> out;
    for (unsigned seed = 1; seed <= kSeeds; ++seed) out.push_back(run_scrambled(model, seed));
    return out;
  }();
  return outcomes;
}

TEST_CASE("paper 003 fig. 3: a scrambled Stable Neo-Hookean cube stays finite, every step solved") {
  REQUIRE(scrambled_cube_model("stable_neo_hookean").num_nodes >= 125);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Outcome>& outcomes = stable_neo_hookean_outcomes();
  int recovered = 0, worst_newton = 0;
  for (unsigned seed = 1; seed <= kSeeds; ++seed) {
    CAPTURE(seed);
    const Outcome& out = outcomes[seed - 1];
    CHECK(out.finite);
    CHECK(out.failed_steps == 0);
    recovered += out.error <= 1e-3 * kSize;
    worst_newton = std::max(worst_newton, out.newton);
  }
  MESSAGE("stable_neo_hookean, " << kSeeds << " scrambles: " << recovered << " returned to rest; most Newton "
          << "iterations in a run " << worst_newton << "; "
          << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s");
}

// The paper's claim, asserted but marked may_fail: it does NOT hold here. Every scramble
// tried settles into a tangled equilibrium (converged Newton, zero velocity, J > 0 in all
// or all but 1-3 tets, but some tets stretched 3-4x): a discrete local minimum of the
// energy reached from the scramble, with rigid-fit errors of ~1 m. The same happened with
// projected Newton only, and with small time steps (dynamic runs). The paper does not give
// its mesh, step or solver settings for fig. 3. Open in issue 6.
// Measured 2026-11-30 (/work/tmp harness, same cube, h 0.5 s, Newton to 1e-8, cap 100):
// the end states have all tets but 0-1 positively oriented, J in [0.5, 1.3], yet the
// shape is off by ~1 m (a tangled but orientation-consistent mesh); 150 steps of 1/30 s
// end the same way; on a 2 x 2 x 2-cell cube 1 of 4 seeds recovers. The same cube as 64
// hex8 elements (8 Gauss points) recovers in 15 of 20 seeds (bitwise to rest, 1e-15 m),
// and the others stop in one symmetric tangled state: the lattice split into 6 tets per
// cell is what traps most runs.
TEST_CASE("paper 003 fig. 3: a scrambled Stable Neo-Hookean cube returns to rest for 200 seeds" *
          doctest::may_fail()) {
  const std::vector<Outcome>& outcomes = stable_neo_hookean_outcomes();
  double worst = 0;
  unsigned recovered = 0;
  for (const Outcome& out : outcomes) {
    recovered += out.error <= 1e-3 * kSize;
    worst = std::max(worst, out.error);
  }
  MESSAGE("worst rigid-fit error " << worst << " m");
  CHECK(recovered == kSeeds);
}

TEST_CASE("paper 003 fig. 3: the same scrambles with classic Neo-Hookean (reported)") {
  // log J is undefined for J <= 0: a scramble inverts many elements, so the incremental
  // potential is undefined at the start and the step fails (World rolls it back); the
  // cube stays scrambled. Reported, not asserted: the paper's point is that it fails.
  const Model model = scrambled_cube_model("neo_hookean");
  int recovered = 0, failed_runs = 0, non_finite = 0;
  for (unsigned seed = 1; seed <= kSeeds; ++seed) {
    const Outcome out = run_scrambled(model, seed);
    recovered += out.finite && out.error <= 1e-3 * kSize;
    failed_runs += out.failed_steps > 0;
    non_finite += !out.finite;
  }
  MESSAGE("classic Neo-Hookean, 200 scrambles: " << recovered << " returned to rest, " << failed_runs
          << " had steps refused (undefined energy), " << non_finite << " went non-finite");
  CHECK(non_finite == 0);  // never NaN: undefined energies are reported, not propagated
}
