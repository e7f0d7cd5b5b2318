#pragma once
// Runs a family of the work-precision study: every variant and swept value, each against
// its converged reference (computed once, cached on disk).
#include <string>
#include <vector>

#include "tools/work_precision/errors.hpp"
#include "tools/work_precision/family.hpp"

namespace sinew::wp {

struct StudyOptions {
  bool quick = false;         // the reduced run: quick_values, quick_steps
  bool fresh = false;         // recompute references even when cached
  std::string cache_dir;      // where references are kept
  std::string scenes_dir;     // assets/scenes
};

// One measured point: a variant with one setting changed.
struct Point {
  std::string variant, sweep, label;
  std::string reference;              // the variant whose converged reference `errors` is against
  double value = 0;
  double h = 0;
  RunResult run;                      // samples dropped once the errors are taken
  double seconds_per_simulated_second = 0;  // wall time: median over `repeats` timings of the whole run
  double cpu_seconds_per_simulated_second = 0;  // CPU time, the same way
  int repeats = 1;
  Errors errors;                      // against the point's reference
  // Points at the scene's own h and lattice: against the same scene at that h with tight
  // tolerances, i.e. the error of the solvers alone (the rest is the time step's).
  Errors solver_errors;
  bool has_solver_errors = false;
  // For variants with a reference of their own: against the family's first variant's
  // reference (how far this method is from the first one's converged answer).
  Errors errors_vs_first;
  bool has_errors_vs_first = false;
};

struct ReferenceInfo {
  std::string variant, lattice, hash;  // lattice: "c0" or the sweep label it refines to
  int h_divisor = 16;                  // 16: the converged reference; 1: tight tolerances at h0
  bool cached = false;
  bool finite = true;
  double step_seconds = 0;
  int steps = 0;
  // Against the first variant's reference on the same lattice (model difference), if another.
  Errors vs_first;
  bool has_vs_first = false;
};

struct FamilyResult {
  std::string name, description, violation_kind;
  std::vector<std::pair<std::string, std::string>> reference_notes;  // variant -> why not its own reference
  std::string quick_note;                                            // quick run only
  double h0 = 0, simulated_seconds = 0;
  int base_steps = 0, sample_every = 0;
  std::vector<ReferenceInfo> references;
  std::vector<Point> points;
};

// Progress lines go to stderr.
FamilyResult run_family(const Family& family, const StudyOptions& options);

}  // namespace sinew::wp
