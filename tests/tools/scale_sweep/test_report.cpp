// The scale sweep's report (tools/scale_sweep/report.cpp): which steps count as a stage's
// work, and the working medians and speedups built on that.
#include <doctest/doctest.h>

#include "engine/simulate_frame.hpp"
#include "tests/engine/step/contact_scenes.hpp"
#include "tools/scale_sweep/report.hpp"

using namespace sinew;

TEST_CASE("scale_sweep report: the SQP's stages work only in steps that solved a QP") {
  // A box dropped 5 cm onto a plane: steps in the air find no row near, the impact and the
  // resting steps solve QPs, and some resting steps meet every row at v* (no QP either).
  World world = test::make_world(test::box_scene(0.5, Vec3(0, -9.81, 0), 0.05));
  sweep::ThreadRun run;
  for (int i = 0; i < 40; ++i) run.samples.push_back(simulate_frame(world, 1));
  std::vector<bool> solved;
  for (const FrameStats& f : run.samples) {
    const auto sqp = f.iterations.find("sqp");
    solved.push_back(sqp != f.iterations.end() && sqp->second > 0);
  }
  const long with_qp = std::count(solved.begin(), solved.end(), true);
  REQUIRE(with_qp > 0);
  REQUIRE(with_qp < static_cast<long>(solved.size()));
  for (const std::string stage : {"pgs", "sqp_solve", "sqp_merit"}) {
    CAPTURE(stage);
    CHECK(sweep::worked(run, stage) == solved);
  }
  // The rows are looked for on every step of a scene with an obstacle.
  const std::vector<bool> rows = sweep::worked(run, "rows");
  CHECK(std::count(rows.begin(), rows.end(), true) == static_cast<long>(rows.size()));
}

TEST_CASE("scale_sweep report: working medians need work in more than half the steps") {
  FrameStats idle, busy;
  idle.stages = {{"sqp_solve", 0.001}};
  idle.skipped = {{"sqp_solve", "no row violated"}};
  busy.stages = {{"sqp_solve", 3.0}};
  sweep::ThreadRun run;
  run.samples = {idle, idle, busy};
  CHECK_FALSE(sweep::working_median_ms(run, "sqp_solve").has_value());
  run.samples = {idle, busy, busy};
  REQUIRE(sweep::working_median_ms(run, "sqp_solve").has_value());
  // The median of every timed step (0.001, 3, 3), once the stage works in most of them.
  CHECK(*sweep::working_median_ms(run, "sqp_solve") == 3.0);
  sweep::ThreadRun faster = run;
  for (FrameStats& f : faster.samples) f.stages[0].second /= 2;
  REQUIRE(sweep::speedup(run, faster, "sqp_solve").has_value());
  CHECK(*sweep::speedup(run, faster, "sqp_solve") == doctest::Approx(2.0).epsilon(1e-12));
}
