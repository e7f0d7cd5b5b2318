// Paper 001, fig. 3: a finger (E 2 MPa) pressed onto a table. With anisotropic limits
// (0.95-1.05 along its length e1, 0.75-1.25 along e2 from pad to nail, 0.98-1.02 across e3)
// it flattens under a press along e2 but hardly gives when pressed on its side (e3). The
// test asserts that and that the anisotropy is the limits' doing: the side-to-flat ratio of
// the anisotropic finger is far below the isotropic one's. (The paper's "isotropic deforms
// about as much either way" is not what this finger shows: its isotropic side press
// compresses more than the flat one; the figures are printed.)
//
// Deviation: the press is a 200 N load ramped over 0.5 s on the half of the finger away from
// the table, not a plate driven by a prescribed displacement: a prescribed squeeze of the
// side beyond the 2 % the limits allow has no solution, a prescribed force always has one.
#include "paper001_support.hpp"

using namespace sinew;
using namespace sinew::paper001;

namespace {

// Largest compression 1 - min |F d| along the press direction d after the press; checks
// that every step ends within the strain tolerance (the issue's "worst violation after SQP
// at most 1e-3" in every strain-limited scene).
double compression(const std::string& press, const std::string& limits, const Vec3& d, int frames) {
  World world = load_world("paper001_finger_" + press + "_" + limits);
  double worst = -1;
  for (int f = 0; f < frames; ++f) {
    REQUIRE(world.step());
    worst = std::max(worst, worst_strain_limit_violation(world.model(), world.state().x));
  }
  MESSAGE(press << ", " << limits << ": worst strain-limit violation over the steps " << worst);
  CHECK(worst <= world.model().solver.strain_tolerance);
  return 1 - stretch_along(world, d).lo;
}

}  // namespace

TEST_CASE("paper 001 fig. 3: the anisotropic finger resists a side press far more than a flat one") {
  // The load is fully on after 30 frames; the isotropic finger pressed flat then gives way
  // and settles by frame 50 (at frame 40 it is mid-way, its compression a snapshot).
  const int frames = 60;
  const double aniso_flat = compression("flat", "anisotropic", Vec3::UnitY(), frames);
  const double aniso_side = compression("side", "anisotropic", Vec3::UnitZ(), frames);
  const double iso_flat = compression("flat", "isotropic", Vec3::UnitY(), frames);
  const double iso_side = compression("side", "isotropic", Vec3::UnitZ(), frames);
  MESSAGE("largest compression along the press: anisotropic flat " << aniso_flat << ", side " << aniso_side
                                                                   << "; isotropic flat " << iso_flat << ", side " << iso_side);
  // Side: e3 may compress by 2 % (plus the SQP tolerance, 1e-3); flat: e2 allows 25 %, so
  // the load compresses it as the elasticity dictates, several times more.
  CHECK(aniso_side <= 0.02 + 1e-3);
  CHECK(aniso_side < 0.3 * aniso_flat);
  CHECK(aniso_side / aniso_flat < 0.25 * (iso_side / iso_flat));
}

TEST_CASE("paper 001 fig. 3: pressed on its tip, the anisotropic finger shortens far less than the isotropic one") {
  // Along its length e1 the anisotropic limits hold 0.95-1.05, the isotropic ones 0.75-1.25;
  // both runs must end every step within the SQP tolerance (compression() checks). The
  // hyperbolic limits bound |F e1| only through the principal stretches (with two axes at
  // 45 degrees to e1 a 5.9 % shortening meets them all), so no exact bound on the
  // shortening follows; the claim checked is the paper's ordering, with the figures printed.
  const int frames = 60;
  const double aniso_tip = compression("tip", "anisotropic", Vec3::UnitX(), frames);
  const double iso_tip = compression("tip", "isotropic", Vec3::UnitX(), frames);
  MESSAGE("largest compression along the press: anisotropic tip " << aniso_tip << ", isotropic tip " << iso_tip);
  CHECK(aniso_tip > 0);
  CHECK(aniso_tip < 0.5 * iso_tip);
}
