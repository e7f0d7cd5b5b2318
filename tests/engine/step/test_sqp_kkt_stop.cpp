// The SQP's KKT stop (engine/step/sqp_kkt_stop.hpp): the last QP's multipliers tested against
// the rows at the new iterate, and, in a simulation, the step it ends against the step a
// confirming QP ends.
#include <doctest/doctest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "engine/step/sqp_kkt_stop.hpp"
#include "tests/engine/step/contact_scenes.hpp"
#include "tests/engine/step/lockstep.hpp"

using namespace sinew;
using namespace sinew::test;

namespace {

constexpr double kH = 1.0 / 60;

// A contact on a plane with its two friction rows (mu 0.5), on nodes 3 and 7, as
// contact_rows.cpp makes them, with value C (m) and slips (m/s) s1, s2.
void add_plane_contact(RowTable& rows, uint32_t vertex, double C, double s1, double s2) {
  const int normal = rows.add_row(RowKind::Contact, C, 0.0, 1e300, row_key(RowKind::Contact, vertex, 0));
  rows.add_entry(3, Vec3(0, 0.25, 0));
  rows.add_entry(7, Vec3(0, 0.75, 0));
  const double slips[2] = {s1, s2};
  for (int t = 0; t < 2; ++t) {
    rows.add_row(RowKind::Friction, kH * slips[t], -1e300, 1e300, row_key(RowKind::Friction, vertex, t));
    rows.add_entry(3, 0.25 * Vec3::Unit(t == 0 ? 0 : 2));
    rows.add_entry(7, 0.75 * Vec3::Unit(t == 0 ? 0 : 2));
    rows.normal_row.back() = normal;
    rows.mu.back() = 0.5;
  }
}

struct Tables {
  RowTable last_qp, rows;
};

// One sticking contact carrying 2 N s (friction 0.3 and -0.1 N s, inside +-1), met exactly at
// the new iterate; a second contact without force, 1 mm clear.
Tables resting_contact() {
  Tables t;
  for (RowTable* table : {&t.last_qp, &t.rows}) {
    add_plane_contact(*table, 10, 0.0, 0.0, 0.0);
    add_plane_contact(*table, 11, 1e-3, 0.2, 0.0);
  }
  t.last_qp.lambda = {2.0, 0.3, -0.1, 0.0, 0.0, 0.0};
  return t;
}

// A cube dropped tilted onto a plane (friction 0.5) from 0.3 m, never sleeping.
SceneDesc tilted_cube(const std::string& solver) {
  SceneDesc scene = box_scene(0.5, Vec3(0, -kGravity, 0), 0.3, "", 1e6, solver);
  scene.bodies[0].rotate = (Eigen::AngleAxisd(0.17, Vec3::UnitX()) * Eigen::AngleAxisd(0.09, Vec3::UnitZ())).toRotationMatrix();
  return scene;
}

bool solves(const Tables& t, const SolverDesc& cfg = SolverDesc()) {
  std::vector<std::pair<uint64_t, int>> last_rows;
  std::vector<double> lambda;
  return last_multipliers_solve(t.last_qp, t.rows, kH, cfg, last_rows, lambda);
}

}  // namespace

TEST_CASE("KKT stop: the last QP's multipliers meet the rows at the new iterate") {
  const SolverDesc cfg;
  // Within PGS's tolerance: a sticking contact's values within pgs_tolerance x contact_tolerance
  // of exact (its gap and slip), a clear one anywhere above.
  const double limit = cfg.pgs_tolerance * cfg.contact_tolerance;
  Tables t = resting_contact();
  CHECK(solves(t));
  t.rows.value[0] = 0.99 * limit;  // the contact carrying force 0.99 of the tolerance open
  t.rows.value[1] = -0.99 * limit;  // and slipping as far (h x slip is the row's value)
  CHECK(solves(t));
  t.rows.value[0] = 1.01 * limit;  // a row with force must be closed: open past the tolerance
  CHECK_FALSE(solves(t));
  t = resting_contact();
  t.rows.value[2] = -1.01 * limit;  // sticking, yet slipping past the tolerance
  CHECK_FALSE(solves(t));
  t = resting_contact();
  t.rows.value[3] = -0.99 * limit;  // the row without force, closed within the tolerance
  CHECK(solves(t));
  t.rows.value[3] = -1.01 * limit;  // and past it: it would need force
  CHECK_FALSE(solves(t));
  t = resting_contact();
  t.rows.value[0] = std::nan("");
  CHECK_FALSE(solves(t));
  t = resting_contact();
  t.rows.value[3] = std::nan("");  // a row at its lower bound, where max(0, -w) would pass NaN
  CHECK_FALSE(solves(t));
  t = resting_contact();
  t.last_qp.lambda[0] = std::nan("");
  CHECK_FALSE(solves(t));
}

TEST_CASE("KKT stop: a friction row at its bound may slip, in its direction only") {
  // The contact's box is +-mu lambda_n = +-1. At the upper bound the force acts along +t1,
  // against a slip along -t1 (w < 0); a slip along +t1 would want less force.
  const SolverDesc cfg;
  const double limit = cfg.pgs_tolerance * cfg.contact_tolerance;
  Tables t = resting_contact();
  t.last_qp.lambda[1] = 1.0;
  t.rows.value[1] = -0.1;  // sliding along -t1: consistent
  CHECK(solves(t));
  t.rows.value[1] = 0.5 * limit;  // slipping the wrong way, within the tolerance
  CHECK(solves(t));
  t.rows.value[1] = 1.01 * limit;  // and past it
  CHECK_FALSE(solves(t));
  t.last_qp.lambda[1] = -1.0;  // at the lower bound, with the same slip along +t1: consistent
  CHECK(solves(t));
  t.rows.value[1] = -0.1;  // at the lower bound sliding along -t1: the force would turn
  CHECK_FALSE(solves(t));
  t = resting_contact();
  t.last_qp.lambda[1] = 1.2;  // outside its box
  CHECK_FALSE(solves(t));
}

TEST_CASE("KKT stop: only rows unchanged in stencil and Jacobian carry their multipliers") {
  Tables t = resting_contact();
  t.rows.jac[1].y() = std::nextafter(0.75, 1.0);  // one ulp: another linearisation
  CHECK_FALSE(solves(t));
  t = resting_contact();
  t.rows.nodes[0] = 4;
  CHECK_FALSE(solves(t));
  // A new row (not in the last QP) carries nothing and must be met as it is.
  t = resting_contact();
  add_plane_contact(t.rows, 12, 5e-4, 0.0, 0.0);
  CHECK(solves(t));
  t.rows.value[6] = -1e-3;  // new and penetrating: the last QP's multipliers do not solve it
  CHECK_FALSE(solves(t));
  // A row gone with its force: J^T lambda no longer balances the residual.
  t = resting_contact();
  RowTable fewer;
  add_plane_contact(fewer, 11, 1e-3, 0.2, 0.0);
  t.rows = fewer;
  CHECK_FALSE(solves(t));
  // Gone without force: nothing is lost.
  t = resting_contact();
  RowTable kept;
  add_plane_contact(kept, 10, 0.0, 0.0, 0.0);
  t.rows = kept;
  CHECK(solves(t));
}

TEST_CASE("KKT stop: not with PCG, whose solves leave the residual to a tolerance") {
  SceneDesc scene = box_scene(0.5, Vec3(0, -kGravity, 0), 0.05, "", 1e6, R"({"sleep_steps": 0, "linear": "pcg"})");
  World w = make_world(scene);
  long stops = 0, qps = 0;
  for (int i = 0; i < 40; ++i) {
    REQUIRE(w.step());
    stops += step_count_of(w, "sqp_kkt_stops");
    qps += step_count_of(w, "sqp");
  }
  CHECK(qps > 0);  // landed: QPs ran
  CHECK(stops == 0);
}

TEST_CASE("KKT stop: a contact's rows without force have no freedom to check") {
  // lambda_n = 0 collapses its friction box to [0, 0]: its slip is free.
  Tables t = resting_contact();
  t.rows.value[4] = 0.3;
  CHECK(solves(t));
}

TEST_CASE("KKT stop: in lockstep, the steps it ends are where a confirming QP ends them") {
  // A cube dropped tilted onto a plane (friction 0.5), refactor_interval 1: every QP is
  // solved with this step's A. World `off` takes `on`'s state before every step. Where the
  // KKT stop ended `on`'s step, `off` solved no fewer QPs (fewer in all), and the two ended
  // within twice `off`'s acceptance of its last move (sqp_position_tolerance, or
  // sqp_stall_tolerance where it accepted a stall), as the other lockstep tests bound two
  // stopped iterates: `on` stops at a KKT point to PGS's tolerance, `off` within that move of
  // one (their first QPs differ by `on`'s extra sweep, a change of the same order).
  SceneDesc scene = tilted_cube(R"({"sleep_steps": 0})");
  REQUIRE(scene.solver.refactor_interval == 1);
  scene.solver.sqp_kkt_stop = "on";
  World on = make_world(scene);
  scene.solver.sqp_kkt_stop = "off";
  World off = make_world(scene);
  int stopped = 0, qps_on = 0, qps_off = 0;
  double farthest = 0;
  for (int i = 0; i < 90; ++i) {
    off.mutable_state() = on.state();
    REQUIRE(on.step());
    REQUIRE(off.step());
    CHECK(step_count_of(off, "sqp_kkt_stops") == 0);
    if (step_count_of(on, "sqp_kkt_stops") == 0) continue;
    ++stopped;
    qps_on += step_count_of(on, "sqp");
    qps_off += step_count_of(off, "sqp");
    CHECK(step_count_of(off, "sqp") >= step_count_of(on, "sqp"));
    const double accepted = step_count_of(off, "sqp_stalls_accepted") > 0 ? scene.solver.sqp_stall_tolerance
                                                                           : scene.solver.sqp_position_tolerance;
    const double apart = farthest_node(on.state().x, off.state().x);
    CHECK(apart <= 2 * accepted);
    farthest = std::max(farthest, apart);
  }
  MESSAGE("KKT stops on " << stopped << " of 90 steps: " << qps_on << " QPs against " << qps_off
                          << " with a confirming QP; farthest node apart " << farthest << " m");
  CHECK(stopped > 30);  // landed within the first 20 steps, then resting
  CHECK(qps_off > qps_on);
}

TEST_CASE("KKT stop: not after a QP solved with an earlier step's factorisation") {
  // The identity the stop rests on, b - A v_k+1 = -J^T lambda_k, holds only for a QP solved
  // with this step's A. The tilted cube of the lockstep test above at refactor_interval 4:
  // three steps in four solve with an older factorisation (State::factor_exact false after
  // the step: it turns true only where the SQP refactorises). None of those may end by the
  // stop; the steps with their own factorisation show that the stop is active in this scene.
  // Without conjugate steps (sqp_acceleration "none"), whose first trial is rarely the whole
  // step and so would keep the stop out for a reason of its own.
  SceneDesc scene = tilted_cube(R"({"sleep_steps": 0, "refactor_interval": 4, "sqp_acceleration": "none"})");
  REQUIRE(scene.solver.sqp_kkt_stop == "on");
  World w = make_world(scene);
  int older_steps = 0, older_stops = 0, own_stops = 0;
  for (int i = 0; i < 90; ++i) {
    REQUIRE(w.step());
    const long stops = step_count_of(w, "sqp_kkt_stops");
    if (w.state().factor_exact) {
      own_stops += stops;
      continue;
    }
    if (step_count_of(w, "sqp") == 0) continue;  // no QP (in flight): nothing to stop
    ++older_steps;
    older_stops += stops;
  }
  MESSAGE("steps with QPs on an earlier factorisation: " << older_steps << ", KKT stops there " << older_stops
                                                         << "; stops on steps with their own: " << own_stops);
  CHECK(older_steps > 30);  // of the ~70 after landing (step 20), three in four: the test has steps to judge
  CHECK(own_stops > 0);
  CHECK(older_stops == 0);
}
