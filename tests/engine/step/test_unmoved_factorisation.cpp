// solve_velocity keeps the factorisation it holds when no element rotated since it was
// made: A depends on the positions only through the rotations, so a body that only
// translates (a fall) needs one factorisation, and one that turns needs one a step.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <string>

#include "tests/engine/step/contact_scenes.hpp"

using namespace sinew;
using namespace sinew::test;

namespace {

const std::string kUnmoved = "no rotation moved since the last factorisation";

const std::string& factorize_skip(const World& w) {
  return w.profile().skipped[static_cast<int>(Stage::Factorize)];
}

}  // namespace

TEST_CASE("unmoved rotations: a falling cube factorises once, then lands and factorises again") {
  // Dropped from 0.5 m: about 19 steps of free fall before it reaches the plane.
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 0.5, "", 1e6, R"({"sleep_steps": 0})"));
  REQUIRE(w.model().solver.refactor_interval == 1);
  REQUIRE(w.step());
  CHECK(factorize_skip(w).empty());  // the first step has nothing to keep
  const double h = w.model().h;
  for (int k = 2; k <= 15; ++k) {
    REQUIRE(w.step());
    CHECK(factorize_skip(w) == kUnmoved);
    CHECK(w.state().factor_exact);
    // Backward Euler's free fall, v_k = -k h g on every node (K annihilates translations
    // whatever factor the step used; this checks that keeping it broke nothing).
    CHECK(mean_node_velocity(w).y() == doctest::Approx(-k * h * kGravity).epsilon(1e-12));
  }
  // Landing bends the cube's elements: their rotations move and each step factorises.
  int factorised_after_contact = 0, contact_steps = 0;
  for (int k = 16; k <= 60; ++k) {
    REQUIRE(w.step());
    if (w.state().rows.size() > 0) ++contact_steps;
    if (contact_steps > 0 && factorize_skip(w).empty()) ++factorised_after_contact;
  }
  REQUIRE(contact_steps > 10);
  CHECK(factorised_after_contact > 10);
}

TEST_CASE("unmoved rotations: a spinning cube factorises at every step") {
  // No gravity, far above the plane: only the spin moves the rotations.
  World w = make_world(box_scene(0.5, Vec3::Zero(), 5.0, "", 1e6, R"({"sleep_steps": 0})"));
  State& s = w.mutable_state();
  const Vec3 centre = mean_node_position(w), omega(0, 0.5, 0);  // rad/s: 0.008 rad a step
  for (int n = 0; n < w.model().num_nodes; ++n)
    s.v.segment<3>(3 * n) = omega.cross(Vec3(s.x.segment<3>(3 * n) - centre));
  for (int k = 0; k < 10; ++k) {
    REQUIRE(w.step());
    CHECK(factorize_skip(w).empty());
  }
}

TEST_CASE("unmoved rotations: a factorisation that must not be reused is not, rotations or not") {
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 0.5, "", 1e6, R"({"sleep_steps": 0})"));
  REQUIRE(w.step());
  REQUIRE(w.step());
  REQUIRE(factorize_skip(w) == kUnmoved);
  // What a retried step or a change of the sleeping set does (world.cpp): the next step factorises.
  w.mutable_state().factor_age = w.model().solver.refactor_interval;
  w.mutable_state().factor_rotations.clear();
  REQUIRE(w.step());
  CHECK(factorize_skip(w).empty());
  REQUIRE(w.step());
  CHECK(factorize_skip(w) == kUnmoved);
}

TEST_CASE("unmoved rotations: keeping the factorisation changes a fall and landing by round-off only") {
  // The same cube dropped twice: `kept` runs as shipped, `fresh` forgets its factorisation's
  // rotations before every step (refactor_interval 1: it factorises at every step). A kept
  // factor is the matrix a fresh one would be, up to the 1e-12 allowed on the rotations,
  // so every iteration count must agree and the positions differ by round-off amplified
  // through the solves (a factor of another A would move them by the solver tolerances,
  // 1e-5 m and more).
  const SceneDesc scene = box_scene(0.5, Vec3(0, -kGravity, 0), 0.3, "", 1e6, R"({"sleep_steps": 0})");
  World kept = make_world(scene), fresh = make_world(scene);
  int kept_steps = 0;
  double worst = 0;
  for (int k = 0; k < 60; ++k) {
    fresh.mutable_state().factor_rotations.clear();
    REQUIRE(kept.step());
    REQUIRE(fresh.step());
    kept_steps += factorize_skip(kept) == kUnmoved;
    CHECK(factorize_skip(fresh).empty());
    for (const char* name : {"sqp", "pgs"}) {
      const auto& a = kept.profile().iterations;
      const auto& b = fresh.profile().iterations;
      CHECK((a.count(name) ? a.at(name) : 0) == (b.count(name) ? b.at(name) : 0));
    }
    worst = std::max(worst, (kept.state().x - fresh.state().x).lpNorm<Eigen::Infinity>());
  }
  REQUIRE(kept_steps >= 10);  // the fall before the landing
  CHECK(kept.state().rows.size() > 0);  // and the landing
  MESSAGE("factorisations kept: " << kept_steps << " of 60 steps; largest position difference " << worst << " m");
  CHECK(worst <= 1e-9);
}

TEST_CASE("unmoved rotations: the step after the sleeping set changes factorises") {
  // A box at rest and another far off falling from 3 m: the first falls asleep while the
  // second still falls, unrotated. The stages then run on a model without the sleeper's
  // unknowns, whose matrix the held factorisation is not.
  char text[2048];
  std::snprintf(text, sizeof text, R"({"h": %.17g, "solver": {"sleep_steps": 10},
    "bodies": [
      {"name": "resting", "shape": [{"type": "box", "half_extents": [0.17, 0.17, 0.17]}],
       "transform": {"translate": [0, 0.1701, 0]}, "cell_size": 0.1, "material": {"E": 1e6, "nu": 0.3, "rho": 500}},
      {"name": "falling", "shape": [{"type": "box", "half_extents": [0.17, 0.17, 0.17]}],
       "transform": {"translate": [3, 3, 0]}, "cell_size": 0.1, "material": {"E": 1e6, "nu": 0.3, "rho": 500}}],
    "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5}]})",
                1.0 / 60);
  World w = make_world(parse_scene_text(text, "sleep", "."));
  int asleep_before = 0, changes = 0;
  for (int k = 0; k < 40; ++k) {
    REQUIRE(w.step());
    const auto& it = w.profile().iterations;
    const int asleep = it.count("sleeping_bodies") ? it.at("sleeping_bodies") : 0;
    if (asleep != asleep_before) {
      ++changes;
      CHECK(factorize_skip(w).empty());
      CHECK(w.profile().work.factorizations == 1);
    }
    asleep_before = asleep;
  }
  REQUIRE(changes >= 1);  // the resting box fell asleep within the 40 steps
  CHECK(asleep_before == 1);  // while the other still fell (3 m take about 47 steps)
}

TEST_CASE("unmoved rotations: a kept factorisation drops a G kept from an earlier one once it is delassus_reuse old") {
  // The cube at rest keeps its factorisation step after step. H^-1 on touched nodes kept
  // across an earlier factorisation (stale, solver.delassus_reuse) is planted by hand: what
  // a factorisation at this step would do with it, the kept factorisation must do too.
  // Without the KKT stop: with it the resting box ends each step after one QP, whose rows
  // (built at v*) are the last step's bit for bit, and W comes from the per-row columns kept
  // from that step (row_column_cache.hpp) without touching G, the subject here.
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 1e-3, "", 1e6, R"({"sleep_steps": 0, "sqp_kkt_stop": "off"})"));
  int k = 0;
  for (; k < 300 && factorize_skip(w) != kUnmoved; ++k) REQUIRE(w.step());
  REQUIRE(factorize_skip(w) == kUnmoved);  // at rest: the factorisation is kept
  // G on `nodes` free nodes (0, 1, ...), first filled `age` steps ago with `first_nodes` of them.
  const auto plant = [&](long age, int nodes = 2, int first_nodes = 2) {
    State& s = w.mutable_state();
    s.touched_inverse.reset(w.model().num_free);
    std::vector<int> planted(nodes);
    for (int n = 0; n < nodes; ++n) planted[n] = n;
    s.touched_inverse.require(planted, [](const auto&, auto& X, const std::vector<int>&, const ZeroedColumns::Pattern*) { X.setZero(); });
    s.touched_inverse.keep_stale();
    s.touched_inverse_step = s.step_count - age;
    s.touched_inverse_first_nodes = first_nodes;
  };
  const int reuse = w.model().solver.delassus_reuse;
  // What each step did with G: it used G (the rows' H^-1 came from touched nodes), and no
  // stalled SQP recomputed it (which would drop it whatever its age).
  const auto used_g_without_refresh = [&] {
    CHECK(w.state().touched_inverse.size() > 0);
    CHECK(w.profile().iterations.count("delassus_refreshes") == 0);
  };
  plant(reuse);  // as old as it may get: dropped
  REQUIRE(w.step());
  REQUIRE(factorize_skip(w) == kUnmoved);
  used_g_without_refresh();
  // Dropped: what the step solved since is the current factorisation's, not stale.
  CHECK_FALSE(w.state().touched_inverse.stale());
  CHECK(w.state().touched_inverse_step == w.state().step_count - 1);
  plant(reuse - 1);  // younger: kept, still marked stale, its planted nodes first
  REQUIRE(w.step());
  REQUIRE(factorize_skip(w) == kUnmoved);
  used_g_without_refresh();
  CHECK(w.state().touched_inverse.stale());
  CHECK(w.state().touched_inverse.local(0) == 0);
  // Young, but grown past twice the nodes of its first fill (contacts that moved onto new
  // nodes): dropped like an old one.
  plant(reuse - 1, 5, 2);
  REQUIRE(w.step());
  REQUIRE(factorize_skip(w) == kUnmoved);
  used_g_without_refresh();
  CHECK_FALSE(w.state().touched_inverse.stale());
  CHECK(w.state().touched_inverse_step == w.state().step_count - 1);
  plant(reuse - 1, 4, 2);  // twice its first fill: kept
  REQUIRE(w.step());
  REQUIRE(factorize_skip(w) == kUnmoved);
  CHECK(w.state().touched_inverse.stale());
}

TEST_CASE("PCG never reuses a factorisation: refactor_interval changes nothing on solver.linear pcg") {
  // Its "factorisation" is the diagonal and the matrix its solves use; reused, the solves of a
  // later step ran on an older step's matrix (with the constraint curvature of its energy
  // rows): the creature with PCG then ended elsewhere at refactor_interval 4 than at 1.
  const auto run = [](int interval) {
    SceneDesc scene = load_scene(std::string(SINEW_SOURCE_DIR) + "/assets/scenes/paper000_creature_500kPa_U100.json");
    scene.solver.linear = "pcg";
    scene.solver.refactor_interval = interval;
    World world(build_model(scene, [](const std::string&) {}), initial_velocities(scene));
    for (int s = 0; s < 25; ++s) REQUIRE(world.step());
    return world.state_hash();
  };
  CHECK(run(4) == run(1));
}

TEST_CASE("unmoved rotations: a reused factorisation of a falling cube solves exactly") {
  // refactor_interval 4: steps 2-4 reuse the first factorisation as an earlier step's. Its
  // rotations have not moved, so it is this step's A and is solved exactly: a
  // single-precision solve (solver.stale_factor_precision) would strain the cube by its
  // round-off, turn its rotations by ~1e-8 and cost a factorisation at every 4th step.
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 0.5, "", 1e6,
                                 R"({"sleep_steps": 0, "refactor_interval": 4, "stale_factor_precision": "single"})"));
  const double h = w.model().h;
  long factorisations = 0;
  for (int k = 1; k <= 15; ++k) {
    REQUIRE(w.step());
    factorisations += w.profile().work.factorizations;
    CHECK(mean_node_velocity(w).y() == doctest::Approx(-k * h * kGravity).epsilon(1e-12));
  }
  CHECK(factorisations == 1);
}

TEST_CASE("unmoved rotations: a cube at rest on contacts keeps its factorisation with single-precision solves") {
  // refactor_interval 4 and the box resting on the plane (sleep off): once settled, no
  // rotation moves, so every due factorisation is skipped. The reused factorisation is this
  // step's A, and the SQP's solves read its own values: single-precision solves there would
  // move the box by their round-off (its lowest point by ~1e-10 m), its rotations by more
  // than 1e-12, and refactorise at every 4th step.
  World w = make_world(box_scene(0.5, Vec3(0, -kGravity, 0), 1e-3, "", 1e6,
                                 R"({"sleep_steps": 0, "refactor_interval": 4, "stale_factor_precision": "single"})"));
  for (int k = 0; k < 200; ++k) REQUIRE(w.step());
  long factorisations = 0;
  int contact_steps = 0;
  for (int k = 0; k < 100; ++k) {
    REQUIRE(w.step());
    factorisations += w.profile().work.factorizations;
    contact_steps += w.state().rows.size() > 0;
  }
  REQUIRE(contact_steps == 100);
  CHECK(factorisations == 0);
}
