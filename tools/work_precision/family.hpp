#pragma once
// What sinew_work_precision measures: scene families (a paper scene and its method
// variants), the settings swept in each (what trades run time for error), and the converged
// reference each point is compared with.
#include <functional>
#include <string>
#include <vector>

#include "engine/scene/scene.hpp"

namespace sinew::wp {

// A method of the family: one of the papers' comparisons (exact or warped Jacobians, a
// strain-limit projection, a material).
struct Variant {
  std::string name;
  std::string scene_file;                   // under assets/scenes/
  std::function<void(SceneDesc&)> edit;     // may be empty
  // The variant changes the model, hence its converged solution: it gets a reference of its
  // own. Otherwise it is measured against the reference of the family's first variant, for
  // the reason in `reference_note`: the same problem linearised otherwise (warped
  // Jacobians), or a problem with no converged solution to compute (constraints that
  // cannot all be met, so SQP never reaches the tight tolerances).
  bool own_reference = true;
  std::string reference_note;
  // Without its own reference: whether the first variant's problem is this one's (then the
  // first variant's tight run at h0 also measures this one's solver error).
  bool same_problem_as_first = false;
};

// One setting swept over values, the others held at the scene's.
struct Sweep {
  std::string name;                          // e.g. "h", "pgs_max_iterations"
  std::vector<double> values, quick_values;  // the scene's own value among them; empty: skipped
  // Sets the value on a scene that already has the variant's edits.
  std::function<void(SceneDesc&, double)> apply;
  std::function<std::string(double)> label;  // e.g. "h0/4"
  // Spatial refinement: compared with a reference on the finest lattice of the sweep (the
  // other sweeps' reference has the scene's own lattice).
  bool refines_lattice = false;
  bool first_variant_only = false;           // too costly to repeat for every variant
};

struct Family {
  std::string name;          // e.g. "paper000_beam"
  std::string description;   // one line for the summary
  std::vector<Variant> variants;
  std::vector<Sweep> sweeps;
  // Simulated time: `steps` (quick: `quick_steps`) steps of the scene's h, sampled every
  // `sample_every` of them; a run with h = h0 / d takes d times as many steps of its own.
  int steps = 0, quick_steps = 0, sample_every = 1;
  std::string violation_kind;  // StepProfile::violation key plotted against time ("" none)
  bool in_default_run = true;  // false: only when named by --only (too costly for the full run)
  // Applied to every scene of the family (references too) in the quick run, e.g. a coarser
  // lattice; may be empty.
  std::function<void(SceneDesc&)> quick_edit;
  std::string quick_note;      // what quick_edit does, for the summary
};

// The families of the full run (a representative subset of the paper scenes; docs/work_precision.md).
std::vector<Family> make_families();

// The reference of a family: h / 16 and tight solver tolerances (every SolverDesc tolerance
// far below its default, caps raised), bodies never sleep. With h_divisor 1: the same
// tolerances at the scene's own h, which isolates the solvers' share of a point's error
// from the time discretisation's.
void make_reference(SceneDesc& scene, int h_divisor = 16);

// Settings every run of the study shares: no sleeping (it would freeze a body between
// samples), and the surface meshed at the lattice's own default resolution even when a
// sweep changes the lattice, so that every run of a family has the same surface vertices.
void prepare_for_study(SceneDesc& scene);

}  // namespace sinew::wp
