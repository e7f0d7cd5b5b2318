#pragma once
// The stages of a time step, named once, each timed into a StepProfile (Box2D-style).
#include <array>
#include <chrono>
#include <string>
#include <string_view>

#include "engine/profile_map.hpp"

namespace sinew {

// Disjoint: the stages' times add up to the step's (less the untimed sleep bookkeeping).
// Rows to SqpMerit make up the constraint solve (paper 000, section 5); SqpMerit is the
// line search's products with A and the iteration's bookkeeping.
enum class Stage {
  Assemble, Factorize, Solve, Rows, SqpFactorize, SqpSolve, Pgs, SqpMerit, Integrate, Surface, Count
};
constexpr int kStageCount = static_cast<int>(Stage::Count);

inline const char* stage_name(Stage s) {
  static const char* names[] = {"assemble", "factorize", "solve", "rows", "sqp_factorize",
                                "sqp_solve", "pgs", "sqp_merit", "integrate", "surface"};
  return names[static_cast<int>(s)];
}

// The constraint solve's stages, Rows to SqpMerit: what the budget controller and the
// benchmarks count as SQP time.
constexpr bool is_constraint_stage(Stage s) { return s >= Stage::Rows && s <= Stage::SqpMerit; }

// Work a step did, counted rather than timed, so that two runs compare on any machine (tests
// assert on these, never on time). Not written to the stats file.
struct StepWork {
  long elements = 0;        // element evaluations: assembly, Newton derivatives, line-search trials
  long rows = 0;            // constraint rows built, over all SQP iterations
  long row_builds = 0;      // row tables built: SQP iterates and line-search trials (not in total())
  long factorizations = 0;  // numeric factorisations (or PCG preconditioner setups)
  long solves = 0;          // right-hand sides solved; each column of a multi-column solve counts
  long total() const { return elements + rows + factorizations + solves; }
};

// Iteration caps that lower the scene's for a step (the real-time budget); 0 keeps the scene's.
struct IterationCaps {
  int sqp = 0, pgs = 0, newton = 0;
  int pcg = 0;  // CG iterations per solve of solver.linear "pcg"
  // The cap in force: the scene's, or this one when it is lower.
  static int effective(int scene_cap, int cap) { return cap > 0 && cap < scene_cap ? cap : scene_cap; }
};

// solver.linear "pcg": CG solves of a step by where they ran (World::attempt_step), for the
// real-time budget's PCG cap. Not written to the stats file (its counts are in `iterations`).
struct PcgWork {
  double step_ms = 0, constraint_ms = 0;  // wall time in the CG solves of stages 2-3 / of stage 4
  int step_solves = 0, constraint_solves = 0;
};

struct StepProfile {
  std::array<double, kStageCount> ms{};               // wall time per stage
  std::array<std::string, kStageCount> skipped{};     // reason when a stage did no work
  ProfileMap<int> rows;                               // active constraint rows by kind
  ProfileMap<int> iterations;                         // by solver: pcg, pgs, sqp; and events
                                                      // (sleeping_bodies: bodies asleep this step)
  ProfileMap<double> violation;                       // worst violation by kind
  StepWork work;
  PcgWork pcg;
  double step_ms = 0;
  double rolled_back_ms = 0;  // of step_ms, in an attempt rolled back before the one that stood
  bool finite = true;
  // Room for every reason up front (the longest is 61 characters), so that a stage first
  // skipped in a warm step does not allocate.
  StepProfile() {
    for (std::string& reason : skipped) reason.reserve(64);
  }
  // Empties it for the next step, keeping the storage (no allocation once warm).
  void clear() {
    ms.fill(0);
    for (std::string& reason : skipped) reason.clear();
    rows.clear(), iterations.clear(), violation.clear();
    work = {};
    pcg = {};
    step_ms = 0;
    rolled_back_ms = 0;
    finite = true;
  }
  // An iteration count or event of the step (0 when not reported).
  int iteration(std::string_view name) const { return iterations.count(name) ? iterations.at(name) : 0; }
  // Whether the step's SQP ran to the cap in force: the scene's, or twice it for a step that
  // extended it (solver.sqp_cap_extension).
  bool ended_at_sqp_cap(int scene_cap) const {
    return iteration("sqp") >= scene_cap * (iteration("sqp_extended") ? 2 : 1);
  }
  // Whether stage s did its work (no reason to skip it was given).
  bool ran(Stage s) const { return skipped[static_cast<int>(s)].empty(); }
  // The constraint solve's time: its stages' sum (is_constraint_stage).
  double constraint_ms() const {
    double sum = 0;
    for (int s = 0; s < kStageCount; ++s)
      if (is_constraint_stage(static_cast<Stage>(s))) sum += ms[s];
    return sum;
  }
};

class StageTimer {
 public:
  StageTimer(StepProfile& profile, Stage stage)
      : m_profile(profile), m_stage(stage), m_start(std::chrono::steady_clock::now()) {}
  ~StageTimer() { stop(); }
  // Adds the time so far to the stage; later calls (and the destructor) add nothing.
  void stop() {
    if (m_stopped) return;
    m_stopped = true;
    const auto end = std::chrono::steady_clock::now();
    m_profile.ms[static_cast<int>(m_stage)] +=
        std::chrono::duration<double, std::milli>(end - m_start).count();
  }
 private:
  bool m_stopped = false;
  StepProfile& m_profile;
  Stage m_stage;
  std::chrono::steady_clock::time_point m_start;
};

}  // namespace sinew
