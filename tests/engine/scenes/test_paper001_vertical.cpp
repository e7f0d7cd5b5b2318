// Paper 001, fig. 4: a soft column (E 10 kPa) fixed at its base sinks under gravity and
// bulges; only its x axis is limited to 0.95-1.05. It stands on a ground plane: too soft
// to carry its own weight, it buckles and folds onto the ground (without one, it folded
// down through its fixed base, its hinge tets inverted to det F = -2, and the hyperbolic
// rows of those tets could not be met in a step: the run diverged at frame ~96).
// The three ways of carrying the limit to the principal axes behave as the paper reports:
// - orthogonal projection gives every principal axis not along x the limits [1, 1]
//   (eqs. 19-20): its constraints are violated from the first frames and hold the column
//   nearly frozen;
// - linear interpolation under-constrains axes between x and the free ones: the stretch
//   along x passes 1.05 frames before its own constraints report a violation;
// - hyperbolic projection keeps its constraints (the x limits projected onto the principal
//   axes) within the solver tolerance at every frame, while the column sinks.
#include "paper001_support.hpp"

using namespace sinew;
using namespace sinew::paper001;

namespace {

struct ColumnRun {
  double sink = 0;                  // largest downward displacement of a node, m
  double max_x_stretch = 0;         // |F e_x| over every frame and element
  double worst_violation = -1;      // of the mode's own constraints, over every frame
  int first_violation = -1;         // first frame whose own constraints are violated past tol
  int first_x_past_limit = -1;      // first frame with |F e_x| > 1.05 + tol
};

ColumnRun run(const std::string& mode, int frames, double tol) {
  World world = load_world("paper001_vertical_" + mode);
  const Model& m = world.model();
  ColumnRun r;
  for (int f = 0; f < frames; ++f) {
    REQUIRE(world.step());
    const double violation = worst_strain_limit_violation(m, world.state().x);
    r.worst_violation = std::max(r.worst_violation, violation);
    if (r.first_violation < 0 && violation > tol) r.first_violation = f;
    const double x = stretch_along(world, Vec3::UnitX()).hi;
    r.max_x_stretch = std::max(r.max_x_stretch, x);
    if (r.first_x_past_limit < 0 && x > 1.05 + tol) r.first_x_past_limit = f;
    for (int n = 0; n < m.num_nodes; ++n) r.sink = std::max(r.sink, m.rest_x[3 * n + 1] - world.state().x[3 * n + 1]);
  }
  return r;
}

}  // namespace

TEST_CASE("paper 001 fig. 4: orthogonal projection freezes, linear interpolation passes the limit, hyperbolic holds") {
  const double tol = 1e-3;  // solver.strain_tolerance of the scenes
  const int frames = 120;  // the scenes' length
  const ColumnRun orthogonal = run("orthogonal", frames, tol);
  const ColumnRun linear = run("linear", frames, tol);
  const ColumnRun hyperbolic = run("hyperbolic", frames, tol);
  MESSAGE("sink (m): orthogonal " << orthogonal.sink << ", linear " << linear.sink << ", hyperbolic " << hyperbolic.sink);
  MESSAGE("orthogonal: first violated at frame " << orthogonal.first_violation << ", worst " << orthogonal.worst_violation);
  MESSAGE("linear: |F e_x| past 1.05 at frame " << linear.first_x_past_limit << " (max " << linear.max_x_stretch
                                              << "), own constraints first violated at frame " << linear.first_violation);
  MESSAGE("hyperbolic: worst violation " << hyperbolic.worst_violation << ", max |F e_x| " << hyperbolic.max_x_stretch);
  // The paper reports the violation in the first frame. Here the column starts at rest and
  // the first step's sag is within the tolerance of the [1, 1] limits; which early frame
  // first ends past the tolerance depends on SQP's path (frame index 1 or 3 measured with
  // two variants of its stall test), so the check is "within the first frames" (<= 5),
  // and the paper's point, a frozen column, is checked on the sink below.
  CHECK(orthogonal.first_violation >= 0);
  CHECK(orthogonal.first_violation <= 5);
  CHECK(orthogonal.sink < 0.1 * hyperbolic.sink);
  // Its limits cannot all be met, and SQP ends every step at its cap; a step returns its
  // least violated iterate, so the violation stays within the x axis's own band width
  // (0.05). Returning the last iterate instead, a perturbation of round-off made it run
  // away at frame 83 (2.1, then 57, then 2100: the column 52 m down).
  CHECK(orthogonal.worst_violation < 0.05);
  CHECK(linear.first_x_past_limit >= 0);
  CHECK((linear.first_violation < 0 || linear.first_x_past_limit < linear.first_violation));
  CHECK(hyperbolic.worst_violation <= tol);
  CHECK(hyperbolic.sink > 0.05);
}
