// Paper 001, fig. 2: a soft cantilever (E 5 kPa) with anisotropic strain limits (free along
// its axis, 0.96-1.04 across) stretches along its axis far more than with isotropic limits
// 0.96-1.04, and both keep their limits (up to the SQP tolerance) at every step.
#include "paper001_support.hpp"

using namespace sinew;
using namespace sinew::paper001;

namespace {

struct BeamRun {
  StretchRange axial, across_y, across_z;
  double worst_transient = -1;  // max over the steps of the worst constraint violation
  double final_violation = -1;
  double tip_sag = 0;
  double tolerance = 0;  // the scene's solver.strain_tolerance
};

BeamRun run(const std::string& name, int frames) {
  World world = load_world(name);
  BeamRun r;
  r.tolerance = world.model().solver.strain_tolerance;
  for (int f = 0; f < frames; ++f) {
    REQUIRE(world.step());
    r.worst_transient = std::max(r.worst_transient, worst_strain_limit_violation(world.model(), world.state().x));
  }
  r.final_violation = worst_strain_limit_violation(world.model(), world.state().x);
  r.axial = stretch_along(world, Vec3::UnitX());
  r.across_y = stretch_along(world, Vec3::UnitY());
  r.across_z = stretch_along(world, Vec3::UnitZ());
  const Model& m = world.model();
  for (int n = 0; n < m.num_nodes; ++n) r.tip_sag = std::max(r.tip_sag, m.rest_x[3 * n + 1] - world.state().x[3 * n + 1]);
  return r;
}

}  // namespace

TEST_CASE("paper 001 fig. 2: anisotropic limits let the beam stretch along its axis, isotropic ones do not") {
  const int frames = 60;  // 1 s: the soft beam has swung down and is settling
  const BeamRun aniso = run("paper001_beam_5kPa_anisotropic", frames);
  const BeamRun iso = run("paper001_beam_5kPa_isotropic", frames);
  const BeamRun stiff = run("paper001_beam_200kPa", frames);
  MESSAGE("largest axial stretch: anisotropic " << aniso.axial.hi << ", isotropic " << iso.axial.hi
                                                << ", 200 kPa unconstrained " << stiff.axial.hi);
  MESSAGE("tip sag (m): anisotropic " << aniso.tip_sag << ", isotropic " << iso.tip_sag << ", 200 kPa " << stiff.tip_sag);
  MESSAGE("worst violation (stretch): anisotropic transient " << aniso.worst_transient << " final "
                                                                << aniso.final_violation << "; isotropic transient "
                                                                << iso.worst_transient << " final " << iso.final_violation);
  // Isotropic: every stretch, axial included, within 1.04 + tolerance.
  const double tol = iso.tolerance;
  REQUIRE(aniso.tolerance == tol);
  CHECK(iso.axial.hi <= 1.04 + tol);
  CHECK(iso.final_violation <= tol);
  // Anisotropic: within the tolerance at every step too. (Before the rows' curvature held
  // their dependence on the principal directions and SQP damped its swings, it reached its
  // cap at 1-7 % past the limits in two thirds of these steps.)
  CHECK(aniso.final_violation <= tol);
  CHECK(aniso.worst_transient <= tol);
  // Anisotropic: the free axis carries the bending: its stretch exceeds the isotropic
  // bound by far (several times the 4 % the isotropic beam may use).
  CHECK(aniso.axial.hi - 1 > 3 * (iso.axial.hi - 1));
  CHECK(aniso.tip_sag > iso.tip_sag);
}

TEST_CASE("paper 001 fig. 2: the anisotropic beam runs its whole scene within its limits") {
  // The scene's 240 frames (4 s: the beam swings and settles). With PGS's subspace steps
  // (the solver's default) its step at t = 2.03 s failed, even when retried (SVD of 7a5cb71),
  // or one frame reached 1.7e-3 (since 74883f9): SQP ends many steps at its cap, and the
  // outcome depends on round-off (docs/ARCHITECTURE.md, "Open: ..."). The scene runs plain
  // PGS (pgs_subspace_interval 0) until that is understood.
  const BeamRun aniso = run("paper001_beam_5kPa_anisotropic", 240);
  CHECK(aniso.worst_transient <= aniso.tolerance);
}
