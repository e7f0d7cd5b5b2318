// The scale sweep's report (tools/scale_sweep/report.cpp): which steps count as a stage's
// work, and the working medians and speedups built on that.
#include <doctest/doctest.h>

#include "tools/scale_sweep/report.hpp"

using namespace sinew;

namespace {

// A timed step with the given stage times, skipped stages and iteration counts.
FrameStats step_with(std::vector<std::pair<std::string, double>> stages,
                     std::vector<std::pair<std::string, std::string>> skipped, std::map<std::string, int> iterations) {
  FrameStats f;
  f.stages = std::move(stages);
  f.skipped = std::move(skipped);
  f.iterations = std::move(iterations);
  return f;
}

}  // namespace

TEST_CASE("scale_sweep report: a step that ran no QP did no solve or merit work") {
  sweep::ThreadRun run;
  // Rows built but all met at v*: PGS skipped, the SQP timers ran empty (sqp 0).
  const FrameStats met = step_with({{"rows", 0.3}, {"sqp_solve", 0.001}, {"sqp_merit", 0.001}},
                                   {{"pgs", "no row violated"}}, {{"sqp", 0}, {"pgs", 0}});
  // Two QPs.
  const FrameStats solved = step_with({{"rows", 0.5}, {"sqp_solve", 2.0}, {"sqp_merit", 0.4}, {"pgs", 0.2}}, {},
                                      {{"sqp", 2}, {"pgs", 12}});
  run.samples = {met, solved, solved};
  for (const std::string stage : {"sqp_solve", "sqp_merit"}) {
    CAPTURE(stage);
    CHECK(sweep::worked(run, stage) == std::vector<bool>{false, true, true});
  }
  CHECK(sweep::worked(run, "rows") == std::vector<bool>{true, true, true});
  CHECK(sweep::worked(run, "pgs") == std::vector<bool>{false, true, true});
  // A stats map without the "sqp" count at all (the stage never ran a QP) is no work either.
  run.samples = {step_with({{"sqp_solve", 0.001}}, {}, {})};
  CHECK(sweep::worked(run, "sqp_solve") == std::vector<bool>{false});
}

TEST_CASE("scale_sweep report: working medians need work in more than half the steps") {
  sweep::ThreadRun run;
  const FrameStats idle = step_with({{"sqp_solve", 0.001}}, {}, {{"sqp", 0}});
  const FrameStats busy = step_with({{"sqp_solve", 3.0}}, {}, {{"sqp", 3}});
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
