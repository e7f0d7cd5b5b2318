// Sleeping bodies (engine/sleep/, issue 7 section 3) through whole steps: three boxes
// dropped onto a plane fall asleep; asleep they cost almost no work (counted by StepWork,
// never timed); a kinematic obstacle, a caller's velocity or an awake body hitting a sleeper
// wakes it and it responds; results stay independent of the thread count.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include "tests/engine/step/contact_scenes.hpp"

using namespace sinew;
using namespace sinew::test;

namespace {

constexpr double kBoxX[] = {-0.8, 0.0, 0.8};

// Three 0.34 m boxes (64 cells each) 5 mm above the plane y = 0, 0.46 m apart, with extra
// obstacles and solver settings as JSON fragments.
SceneDesc three_boxes(const std::string& extra_obstacles = "", const std::string& solver = "{}") {
  std::string bodies;
  for (int i = 0; i < 3; ++i) {
    char body[512];
    std::snprintf(body, sizeof body, R"(%s{"name": "box%d", "shape": [{"type": "box", "half_extents": [0.17, 0.17, 0.17]}],
      "transform": {"translate": [%.17g, 0.5, 0.007]}, "cell_size": 0.1, "surface_resolution": 0.085,
      "material": {"E": 1e6, "nu": 0.3, "rho": 500}})",
                  i ? ", " : "", i, kBoxX[i]);
    bodies += body;
  }
  const std::string text = R"({"h": 0.0166666666666667, "solver": )" + solver + R"(, "bodies": [)" + bodies +
                           R"(], "obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "friction": 0.5})" +
                           extra_obstacles + "]}";
  SceneDesc scene = parse_scene_text(text, "three_boxes", ".");
  const Model probe = build_model(scene, [](const std::string&) {});
  double lowest = 1e300;
  for (const Vec3& p : probe.bodies[0].rest_surface.vertices) lowest = std::min(lowest, p.y());
  for (BodyDesc& body : scene.bodies) body.translate.y() += 0.005 - lowest;
  return scene;
}

int sleeping(const World& w) {
  const auto& it = w.profile().iterations;
  return it.count("sleeping_bodies") ? it.at("sleeping_bodies") : 0;
}

// Steps until every body sleeps (or `limit` steps); returns the steps taken.
int settle(World& w, int limit) {
  int steps = 0;
  while (steps < limit && !w.state().sleep.all()) {
    REQUIRE(w.step());
    ++steps;
  }
  return steps;
}

// Work summed over `steps` further steps.
StepWork work_over(World& w, int steps) {
  StepWork sum;
  for (int i = 0; i < steps; ++i) {
    REQUIRE(w.step());
    const StepWork& p = w.profile().work;
    sum.elements += p.elements, sum.rows += p.rows, sum.factorizations += p.factorizations, sum.solves += p.solves;
  }
  return sum;
}

double largest_move(const World& w, const VecX& x_before, int body) {
  const Body& b = w.model().bodies[body];
  return (w.state().x - x_before).segment(3 * b.node_offset, 3 * b.num_nodes()).lpNorm<Eigen::Infinity>();
}

}  // namespace

TEST_CASE("sleep: boxes resting on a plane fall asleep and then cost at most 5 % of the work awake") {
  World asleep = make_world(three_boxes());
  World awake = make_world(three_boxes("", R"({"sleep_steps": 0})"));  // 0: sleeping off
  int steps = 0, first_asleep = -1;
  while (steps < 300 && !asleep.state().sleep.all()) {
    REQUIRE(asleep.step());
    REQUIRE(awake.step());
    ++steps;
    // Until a body falls asleep (and gets v = 0), sleeping changes nothing, bitwise.
    if (first_asleep < 0 && asleep.state().sleep.count() > 0) first_asleep = steps;
    if (first_asleep < 0) REQUIRE(asleep.state_hash() == awake.state_hash());
  }
  MESSAGE("first box asleep after " << first_asleep << " steps, all three after " << steps);
  REQUIRE(asleep.state().sleep.all());
  CHECK(first_asleep > asleep.model().solver.sleep_steps);
  CHECK(awake.state().sleep.count() == 0);
  CHECK(awake.kinetic_energy() < 1e-6);  // the awake copy is at rest too: same scene, same state

  const VecX x = asleep.state().x;
  const StepWork slept = work_over(asleep, 20), woke = work_over(awake, 20);
  CHECK(awake.state().sleep.count() == 0);
  MESSAGE("work over 20 steps at rest, asleep vs awake: elements " << slept.elements << " / " << woke.elements
          << ", rows " << slept.rows << " / " << woke.rows << ", factorisations " << slept.factorizations << " / "
          << woke.factorizations << ", solves " << slept.solves << " / " << woke.solves);
  CHECK(woke.total() > 0);
  CHECK(slept.total() <= 0.05 * woke.total());
  CHECK(slept.elements <= 0.05 * woke.elements);
  CHECK(slept.solves <= 0.05 * woke.solves);
  // Asleep: positions kept bitwise, no velocity, every stage skipped with the reason.
  CHECK(asleep.state().x == x);
  CHECK(asleep.state().v.isZero(0));
  CHECK(sleeping(asleep) == 3);
  for (int s = 0; s < kStageCount; ++s) CHECK(asleep.profile().skipped[s] == "all bodies asleep");
  CHECK(asleep.state().t == doctest::Approx(awake.state().t));
}

TEST_CASE("sleep: a moving obstacle wakes the box it hits, which moves; the others sleep on") {
  // A sphere held away until t = 1 s (the boxes sleep from ~0.7 s), then pushed 0.6 m/s
  // into the right box, which it shoves ~0.3 m, short of the middle box.
  const std::string sphere = R"(, {"type": "sphere", "radius": 0.15, "friction": 0.3, "motion": {"keyframes": [
      {"t": 1.0, "position": [1.4, 0.17, 0.0]}, {"t": 2.0, "position": [0.8, 0.17, 0.0]}]}})";
  World w = make_world(three_boxes(sphere));
  settle(w, 59);
  REQUIRE(w.state().sleep.all());
  const VecX x = w.state().x;
  const int elements_per_box = w.model().bodies[2].num_elements();
  int woke_at = -1, partial_steps = 0;
  long partial_elements = 0;
  while (w.state().t < 2.2) {
    REQUIRE(w.step());
    if (woke_at < 0 && !w.state().sleep.asleep[2]) woke_at = static_cast<int>(w.state().step_count);
    if (sleeping(w) == 2) ++partial_steps, partial_elements += w.profile().work.elements;
  }
  MESSAGE("right box woke at step " << woke_at << " (t = " << woke_at / 60.0 << " s), moved " << largest_move(w, x, 2)
                                    << " m");
  CHECK(woke_at > 60);
  CHECK(largest_move(w, x, 2) > 0.1);  // pushed by the sphere
  CHECK(largest_move(w, x, 0) == 0);   // never disturbed: kept bitwise
  CHECK(largest_move(w, x, 1) == 0);
  // While two of three boxes sleep, only the awake box's elements are assembled.
  REQUIRE(partial_steps > 0);
  CHECK(partial_elements == static_cast<long>(partial_steps) * elements_per_box);
}

TEST_CASE("sleep: a box lowered onto a sleeping box wakes it; then both sleep again, together") {
  // A wide slab resting on two rails (box obstacles beside the lower box, not touching it)
  // 6 cm above the lower box. From t = 0.6 s the rails sink 0.3 m in 1 s: they wake the slab,
  // which lands on the sleeping box and wakes it through their contact rows.
  const SceneDesc scene = parse_scene_text(R"({"h": 0.0166666666666667, "solver": {"sleep_steps": 10},
    "bodies": [{"name": "box", "shape": [{"type": "box", "half_extents": [0.17, 0.17, 0.17]}],
                "transform": {"translate": [0, 0.175, 0]}, "cell_size": 0.1, "surface_resolution": 0.085,
                "material": {"E": 1e6, "nu": 0.3, "rho": 500}},
               {"name": "slab", "shape": [{"type": "box", "half_extents": [0.32, 0.08, 0.2]}],
                "transform": {"translate": [0, 0.495, 0]}, "cell_size": 0.08, "surface_resolution": 0.08,
                "material": {"E": 1e6, "nu": 0.3, "rho": 500}}],
    "obstacles": [{"type": "plane", "friction": 0.5},
      {"type": "box", "half_extents": [0.06, 0.02, 0.3], "friction": 0.5, "motion": {"keyframes": [
        {"t": 0.6, "position": [-0.3, 0.39, 0]}, {"t": 1.6, "position": [-0.3, 0.09, 0]}]}},
      {"type": "box", "half_extents": [0.06, 0.02, 0.3], "friction": 0.5, "motion": {"keyframes": [
        {"t": 0.6, "position": [0.3, 0.39, 0]}, {"t": 1.6, "position": [0.3, 0.09, 0]}]}}]})",
                                           "lowered", ".");
  World w = make_world(scene);
  settle(w, 35);
  REQUIRE(w.state().sleep.all());
  const VecX x = w.state().x;
  double slab_alone = 0;  // how far the slab moved while the box still slept
  int box_woke_at = -1, asleep_again_at = -1;
  while (w.state().t < 3.0 && asleep_again_at < 0) {
    REQUIRE(w.step());
    const auto& asleep = w.state().sleep.asleep;
    if (box_woke_at < 0 && !asleep[1]) CHECK(w.state().t > 0.6);  // the slab wakes with the rails
    if (box_woke_at < 0 && asleep[0]) slab_alone = largest_move(w, x, 1);
    if (box_woke_at < 0 && !asleep[0]) box_woke_at = static_cast<int>(w.state().step_count);
    if (box_woke_at >= 0 && w.state().sleep.all()) asleep_again_at = static_cast<int>(w.state().step_count);
  }
  MESSAGE("slab moved " << slab_alone << " m before the box woke at t = " << box_woke_at / 60.0
                        << " s; both asleep again at t = " << asleep_again_at / 60.0 << " s; box moved "
                        << largest_move(w, x, 0) << " m");
  CHECK(slab_alone > 0.02);         // lowered onto the box by the rails while the box slept
  CHECK(box_woke_at > 0);
  CHECK(largest_move(w, x, 0) > 1e-4);  // the box responds: pressed by the slab
  CHECK(asleep_again_at > box_woke_at);
  CHECK(w.state().sleep.island[0] == w.state().sleep.island[1]);  // one island: they touch
  CHECK(deepest_between_bodies(w) <= 2 * w.model().solver.contact_tolerance);
}

TEST_CASE("sleep: a caller's velocity or external force wakes a sleeper") {
  World w = make_world(three_boxes());
  settle(w, 300);
  REQUIRE(w.state().sleep.all());
  const VecX x = w.state().x;
  const Body& left = w.model().bodies[0];
  for (int n = left.node_offset; n < left.node_offset + left.num_nodes(); ++n)
    w.mutable_state().v.segment<3>(3 * n) = Vec3(0, 0.5, 0);  // tossed up
  const Body& middle = w.model().bodies[1];
  for (int n = middle.node_offset; n < middle.node_offset + middle.num_nodes(); ++n)
    w.mutable_state().external_force[3 * n + 1] = 20.0;  // 20 N up per node: more than its weight
  double hop = 0;  // the tossed box lands again after ~10 steps
  for (int i = 0; i < 10; ++i) {
    REQUIRE(w.step());
    hop = std::max(hop, largest_move(w, x, 0));
  }
  CHECK(hop > 0.008);  // v^2 / 2g = 1.3 cm
  CHECK(largest_move(w, x, 1) > 0.01);
  CHECK(largest_move(w, x, 2) == 0);
}

TEST_CASE("sleep: falling asleep and waking give the same state hash for 1 and 2 threads") {
  // The sphere of the moving-obstacle case, sooner: it reaches the right box at ~1.1 s.
  const std::string sphere = R"(, {"type": "sphere", "radius": 0.15, "motion": {"keyframes": [
      {"t": 0.9, "position": [1.3, 0.17, 0.0]}, {"t": 1.9, "position": [0.7, 0.17, 0.0]}]}})";
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    World w = make_world(three_boxes(sphere));
    int slept = 0, partial = 0;
    for (int i = 0; i < 85; ++i) {
      REQUIRE(w.step());
      slept += sleeping(w);
      partial += sleeping(w) == 2;
    }
    return std::make_tuple(w.state_hash(), slept, partial);
  };
  const auto one = run(1), two = run(2);
  CHECK(std::get<2>(one) > 0);  // fell asleep, then the right box woke
  CHECK(std::get<1>(one) == std::get<1>(two));
  CHECK(std::get<0>(one) == std::get<0>(two));
}
