// Paper 003, fig. 3: a Stable Neo-Hookean cube (nu 0.49) whose vertices are scattered at
// random within twice its volume returns to its rest shape (up to a rigid motion): the energy
// is defined and smooth for inverted and degenerate elements. Classic Neo-Hookean (log J) is
// undefined for J <= 0, which a scramble produces in most elements: its run is reported.
//
// The claim holds here for a hex8 cube whose volume term sees the element's mean dilatation
// (material "volume_term": "mean_dilatation", engine/assembly/mean_dilatation_element.hpp).
// With the volume term at every Gauss point, or on the cube split into 6 tets per cell, the
// mesh locks at nu 0.49 (more volume constraints than DOFs) and most scrambles settle into a
// tangled equilibrium: every element positively oriented with J near 1, the shape ~1 m off.
// Measured (40 steps, 8 seeds; harness): tets 0/8 at nu 0.49, 6/8 at 0.45, 8/8 at 0.3; hex8 with the
// volume term per point 5/8 at 0.49, 8/8 at 0.45. Those two are reported below, not asserted.
// Mean dilatation is not a proof of recovery either: seeds 1-200 all recover, but of seeds
// 201-700 (sinew_stress scrambled_cubes) 5 settle tangled (441, 446, 555, 616, 698; the same
// after 60 steps): element volumes right (Jbar 0.95-1.01) while 2-7 Gauss points are
// inverted, which the volume term, seeing only the mean, does not resist, and Ic cannot
// tell from upright. A round-off change can move a seed across that line, so the test asks
// for the measured rate, not for these 200 seeds: with 5 in 500 failing (p ~ 0.01), more
// than 8 failures in 200 has probability ~0.1 %. All 200 recover today (the message says).
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

// A 1 m cube, 4 x 4 x 4 cells of 0.25 m (5 x 5 x 5 nodes), nu 0.49, no gravity, nothing fixed.
//
// Time step and damping: the test asks for the rest shape, not for the dynamics, so a
// large step makes backward Euler strongly dissipative. With E 1e5 Pa, rho 1000 kg/m^3 the
// slowest shear mode has omega ~ pi c_s / L = pi sqrt(mu / rho) ~ 18 rad/s; with h = 0.5 s
// (omega h ~ 9) each step keeps ~1 / (omega h)^2 ~ 1 % of that mode's energy, and mass
// damping 2/s takes more. Newton: up to 30 iterations per step, to 1e-8. 10 steps (5 s):
// the untangling takes the first 3-5 steps, the rest bring the shape to ~1e-7 m of rest
// (8 seeds measured: 3 of 8 within 1e-3 m after 5 steps, 8 of 8 after 10).
constexpr int kSteps = 10;
constexpr double kSize = 1.0;  // m, the cube's edge
constexpr unsigned kSeeds = 200;
constexpr unsigned kReportedSeeds = 10;  // for the locking variants, reported only

Model scrambled_cube_model(const char* material, const char* elements, const char* volume_term) {
  char text[1024];
  std::snprintf(text, sizeof text, R"({"h": 0.5, "gravity": [0, 0, 0],
    "solver": {"newton_tolerance": 1e-8, "newton_max_iterations": 30},
    "bodies": [{"name": "cube", "shape": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}],
      "cell_size": 0.25, "elements": "%s", "damping": {"mass": 2},
      "material": {"model": "%s", "E": 1e5, "nu": 0.49, "rho": 1000, "volume_term": "%s"}}]})",
                elements, material, volume_term);
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
  bool recovered() const { return finite && error <= 1e-3 * kSize; }
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

struct Summary {
  unsigned recovered = 0, non_finite = 0, failed_runs = 0;
  double worst_error = 0;
  int worst_newton = 0;
};

// check_each: finite and every step solved, for every seed (recovery is counted).
Summary run_seeds(const Model& model, unsigned seeds, bool check_each) {
  Summary s;
  for (unsigned seed = 1; seed <= seeds; ++seed) {
    const Outcome out = run_scrambled(model, seed);
    if (check_each) {
      CAPTURE(seed);
      CHECK(out.finite);
      CHECK(out.failed_steps == 0);
    }
    s.recovered += out.recovered();
    s.non_finite += !out.finite;
    s.failed_runs += out.failed_steps > 0;
    s.worst_error = std::max(s.worst_error, out.error);
    s.worst_newton = std::max(s.worst_newton, out.newton);
  }
  return s;
}

}  // namespace

TEST_CASE("paper 003 fig. 3: a scrambled Stable Neo-Hookean cube returns to rest for 200 seeds") {
  const Model model = scrambled_cube_model("stable_neo_hookean", "hex", "mean_dilatation");
  REQUIRE(model.num_nodes >= 125);
  const auto start = std::chrono::steady_clock::now();
  const Summary s = run_seeds(model, kSeeds, true);
  CHECK(s.recovered >= kSeeds - 8);
  MESSAGE("stable_neo_hookean, hex8 mean dilatation, " << kSeeds << " scrambles: " << s.recovered
          << " back to rest within 1e-3 m (worst rigid-fit error " << s.worst_error << " m); most Newton "
          << "iterations in a run " << s.worst_newton << "; "
          << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s");
}

TEST_CASE("paper 003 fig. 3: the locking discretisations stay finite (recovery reported)") {
  const struct {
    const char* name;
    const char* elements;
    const char* volume_term;
  } variants[] = {{"hex8, volume term per point", "hex", "per_point"}, {"6 tets per cell", "tet", "per_point"}};
  for (const auto& v : variants) {
    const std::string name = v.name;
    CAPTURE(name);
    const Summary s = run_seeds(scrambled_cube_model("stable_neo_hookean", v.elements, v.volume_term),
                                kReportedSeeds, false);
    CHECK(s.non_finite == 0);
    CHECK(s.failed_runs == 0);
    MESSAGE("stable_neo_hookean, " << name << ": " << s.recovered << " of " << kReportedSeeds
            << " scrambles back to rest (locking at nu 0.49; worst rigid-fit error " << s.worst_error << " m)");
  }
}

TEST_CASE("paper 003 fig. 3: the same scrambles with classic Neo-Hookean (reported)") {
  // log J is undefined for J <= 0: a scramble inverts many elements, so the incremental
  // potential is undefined at the start and the step fails (World rolls it back); the
  // cube stays scrambled. Reported, not asserted: the paper's point is that it fails.
  const Summary s = run_seeds(scrambled_cube_model("neo_hookean", "hex", "mean_dilatation"), kSeeds, false);
  MESSAGE("classic Neo-Hookean, " << kSeeds << " scrambles: " << s.recovered << " returned to rest, " << s.failed_runs
          << " had steps refused (undefined energy), " << s.non_finite << " went non-finite");
  CHECK(s.non_finite == 0);  // never NaN: undefined energies are reported, not propagated
}
