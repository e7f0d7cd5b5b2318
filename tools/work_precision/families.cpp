// The scene families of the work-precision study and what is swept in each. A subset of the
// paper scenes, one per figure family, chosen to cover the three papers' solvers: energy
// limits with and without contact (000), strain limits in two scenes (001), Newton on
// hyperelastic energies (003). Run lengths keep the full study near 20 minutes on 2 cores.
#include <cmath>
#include <cstdio>
#include <utility>

#include "tools/work_precision/family.hpp"

namespace sinew::wp {

namespace {

std::string number_label(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3g", v);
  return s;
}

Sweep make_sweep(const std::string& name, std::vector<double> values, std::vector<double> quick,
                 std::function<void(SceneDesc&, double)> apply, std::function<std::string(double)> label) {
  Sweep sweep;
  sweep.name = name;
  sweep.values = std::move(values);
  sweep.quick_values = std::move(quick);
  sweep.apply = std::move(apply);
  sweep.label = std::move(label);
  return sweep;
}

Sweep time_step_sweep(std::vector<double> divisors, std::vector<double> quick) {
  return make_sweep("h", std::move(divisors), std::move(quick), [](SceneDesc& s, double d) { s.h /= d; },
                    [](double d) { return d == 1 ? std::string("h0") : "h0/" + number_label(d); });
}

// An iteration cap given by a member pointer of SolverDesc.
Sweep cap_sweep(const std::string& name, int SolverDesc::*field, std::vector<double> values, std::vector<double> quick) {
  return make_sweep(name, std::move(values), std::move(quick),
                    [field](SceneDesc& s, double v) { s.solver.*field = static_cast<int>(v); }, number_label);
}

// The SQP's cap as it stands: its one extension (solver.sqp_cap_extension) turned off, so that
// each point costs at most its cap.
Sweep sqp_cap_sweep(std::vector<double> caps, std::vector<double> quick) {
  return make_sweep("sqp_max_iterations", std::move(caps), std::move(quick),
                    [](SceneDesc& s, double v) {
                      s.solver.sqp_max_iterations = static_cast<int>(v);
                      s.solver.sqp_cap_extension = "none";
                    },
                    number_label);
}

Sweep pgs_cap_sweep(std::vector<double> caps, std::vector<double> quick) {
  return cap_sweep("pgs_max_iterations", &SolverDesc::pgs_max_iterations, std::move(caps), std::move(quick));
}

// A solver tolerance given by a member pointer of SolverDesc.
Sweep tolerance_sweep(const std::string& name, double SolverDesc::*field, std::vector<double> values,
                      std::vector<double> quick) {
  return make_sweep(name, std::move(values), std::move(quick), [field](SceneDesc& s, double v) { s.solver.*field = v; },
                    number_label);
}

// A constraint tolerance of the SQP loop. Its stopping test has a second half, the last
// correction's largest node move (sqp_position_tolerance; sqp_stall_tolerance once the
// corrections stop shrinking): alone, a looser row tolerance changes nothing while that half
// still binds. So all move together, in the ratio of their defaults (`metres_per_unit`: the
// position tolerance per unit of the row tolerance).
Sweep sqp_tolerance_sweep(const std::string& name, double SolverDesc::*field, double metres_per_unit,
                          std::vector<double> values, std::vector<double> quick) {
  return make_sweep(name, std::move(values), std::move(quick),
                    [field, metres_per_unit](SceneDesc& s, double v) {
                      s.solver.*field = v;
                      s.solver.sqp_position_tolerance = metres_per_unit * v;
                      // the stall tolerance keeps its default ratio to the position tolerance
                      const SolverDesc defaults;
                      s.solver.sqp_stall_tolerance =
                          metres_per_unit * v * defaults.sqp_stall_tolerance / defaults.sqp_position_tolerance;
                    },
                    number_label);
}

// Lattice refinement by a factor on every body's cell size. An energy limit caps each
// element's energy, so it is scaled with the element volume (factor^3): the energy density
// limit, hence the continuum problem, stays the same while the lattice is refined.
Sweep cell_size_sweep(std::vector<double> factors, std::vector<double> quick) {
  Sweep sweep = make_sweep("cell_size", std::move(factors), std::move(quick),
              [](SceneDesc& s, double f) {
                for (BodyDesc& b : s.bodies) {
                  b.cell_size *= f;
                  b.energy_limit.Umax *= f * f * f;
                  for (EnergyLimitRegion& r : b.energy_limit.regions) r.Umax *= f * f * f;
                }
              },
              [](double f) { return f == 1 ? std::string("c0") : "c0 x " + number_label(f); });
  sweep.refines_lattice = true;
  sweep.first_variant_only = true;
  return sweep;
}

std::function<void(SceneDesc&)> jacobian(const std::string& mode) {
  return [mode](SceneDesc& s) {
    for (BodyDesc& b : s.bodies) b.energy_limit.jacobian = mode;
  };
}

std::function<void(SceneDesc&)> material(const std::string& model) {
  return [model](SceneDesc& s) {
    for (BodyDesc& b : s.bodies) b.material.model = model;
  };
}

}  // namespace

std::vector<Family> make_families() {
  std::vector<Family> families;

  // Paper 000, fig. 3 and sec. 6.2: the energy-limited beam, exact vs warped Jacobians.
  Family beam;
  beam.name = "paper000_beam";
  beam.description = "paper 000 fig. 3 beam (56 hex, E 150 kPa, Umax 0.1 J): exact vs warped Jacobians";
  beam.variants = {{"exact", "paper000_beam_150kPa_U0.1.json", jacobian("exact"), true, ""},
                   {"warped", "paper000_beam_150kPa_U0.1.json", jacobian("warped"), false,
                    "the same constraint, linearised otherwise", true}};
  beam.sweeps = {time_step_sweep({1, 2, 4}, {1, 2}),
                 pgs_cap_sweep({5, 10, 25, 50, 100, 200}, {10, 50, 200}),
                 sqp_tolerance_sweep("sqp_tolerance", &SolverDesc::sqp_tolerance, 1e-2, {1e-1, 1e-2, 1e-3, 1e-4}, {1e-1, 1e-3}),
                 cell_size_sweep({1, 2.0 / 3}, {})};
  Sweep pcg = tolerance_sweep("pcg_tolerance", &SolverDesc::pcg_tolerance, {1e-2, 1e-4, 1e-6}, {1e-2, 1e-6});
  pcg.apply = [](SceneDesc& s, double v) {
    s.solver.linear = "pcg";
    s.solver.pcg_tolerance = v;
  };
  pcg.first_variant_only = true;
  beam.sweeps.push_back(pcg);
  beam.steps = 120, beam.quick_steps = 60, beam.sample_every = 6;
  beam.violation_kind = "energy";
  families.push_back(beam);

  // Paper 000, fig. 6, a short run: the creature's drop and first impact (contact and
  // friction). Its 100 J limit first binds at 1.6 s, after this run, so the Jacobians are
  // compared on the beam only; the variants here are the compliant and the stiff creature.
  Family creature;
  creature.name = "paper000_creature";
  creature.description = "paper 000 fig. 6 creature (356 hex, ground contact), first 0.75 s: 500 kPa (Umax 100 J) vs 5 MPa";
  creature.variants = {{"500kPa_U100", "paper000_creature_500kPa_U100.json", {}, true, ""},
                       {"5MPa", "paper000_creature_5MPa.json", {}, true, ""}};
  creature.sweeps = {time_step_sweep({1, 2, 4}, {1, 2}), pgs_cap_sweep({10, 25, 50, 100, 200}, {25, 200}),
                     sqp_tolerance_sweep("contact_tolerance", &SolverDesc::contact_tolerance, 0.1, {1e-2, 1e-3, 1e-4, 1e-5}, {1e-2, 1e-4})};
  creature.sweeps.back().first_variant_only = true;
  // The scene factorises every 4 steps: what an older factorisation costs in accuracy.
  creature.sweeps.push_back(cap_sweep("refactor_interval", &SolverDesc::refactor_interval, {1, 2, 4, 6, 8}, {1, 4, 6}));
  creature.steps = 45, creature.quick_steps = 30, creature.sample_every = 3;
  creature.violation_kind = "penetration";
  families.push_back(creature);

  // Paper 001, fig. 2: the 5 kPa cantilever with anisotropic or isotropic strain limits.
  Family beam001;
  beam001.name = "paper001_beam";
  beam001.description = "paper 001 fig. 2 beam (240 tets, E 5 kPa): anisotropic vs isotropic strain limits";
  beam001.variants = {{"anisotropic", "paper001_beam_5kPa_anisotropic.json", {}, true, ""},
                      {"isotropic", "paper001_beam_5kPa_isotropic.json", {}, true, ""}};
  beam001.sweeps = {time_step_sweep({1, 2, 4}, {1, 2}), pgs_cap_sweep({10, 25, 50, 100, 200}, {25, 200}),
                    sqp_tolerance_sweep("strain_tolerance", &SolverDesc::strain_tolerance, 1e-2, {1e-1, 1e-2, 1e-3, 1e-4}, {1e-2, 1e-3}),
                    sqp_cap_sweep({2, 5, 10, 20}, {2, 10}),
                    cell_size_sweep({1, 2.0 / 3}, {})};
  beam001.steps = 30, beam001.quick_steps = 15, beam001.sample_every = 3;
  beam001.violation_kind = "strain";
  // Its SQP hits the cap on most steps even at h0/16 with 50 iterations (issue 5's closing
  // notes): the reference takes ~9 s per simulated step and is not converged to the tight
  // tolerances, so the family runs only when asked for.
  beam001.in_default_run = false;
  families.push_back(beam001);

  // Paper 001, fig. 4: the sinking column, the three projections of the limits.
  Family vertical;
  vertical.name = "paper001_vertical";
  vertical.description = "paper 001 fig. 4 column (144 tets, E 10 kPa, x limited to 0.95-1.05): hyperbolic vs orthogonal vs linear";
  vertical.variants = {{"hyperbolic", "paper001_vertical_hyperbolic.json", {}, true, ""},
                       {"orthogonal", "paper001_vertical_orthogonal.json", {}, false,
                        "its limits cannot all be met (they freeze the column and SQP never reaches the tight "
                        "tolerance), so no converged reference of its own exists", false},
                       {"linear", "paper001_vertical_linear.json", {}, true, ""}};
  vertical.sweeps = {time_step_sweep({1, 2, 4}, {1, 2}), pgs_cap_sweep({10, 25, 50, 100, 200}, {25, 200}),
                     sqp_tolerance_sweep("strain_tolerance", &SolverDesc::strain_tolerance, 1e-2, {1e-1, 1e-2, 1e-3, 1e-4}, {1e-2, 1e-3}),
                     cell_size_sweep({1, 2.0 / 3}, {})};
  vertical.sweeps[2].first_variant_only = true;  // the tolerance: orthogonal never meets it anyway
  vertical.steps = 90, vertical.quick_steps = 45, vertical.sample_every = 6;
  vertical.violation_kind = "strain";
  families.push_back(vertical);

  // Paper 003, fig. 2: the elbow bent by 90 degrees over 1.5 s, three materials.
  Family elbow;
  elbow.name = "paper003_elbow";
  elbow.description = "paper 003 fig. 2 elbow (1920 tets, E 1 MPa, nu 0.49, bent 90 degrees in 1.5 s): Stable vs classic Neo-Hookean vs corotational";
  elbow.variants = {{"stable_neo_hookean", "paper003_elbow_snh.json", material("stable_neo_hookean"), true, ""},
                    {"neo_hookean", "paper003_elbow_snh.json", material("neo_hookean"), true, ""},
                    {"corotational", "paper003_elbow_snh.json", material("corotational_hyperelastic"), true, ""}};
  elbow.sweeps = {time_step_sweep({1, 2, 4}, {1, 2}),
                  tolerance_sweep("newton_tolerance", &SolverDesc::newton_tolerance, {1e-2, 1e-4, 1e-6, 1e-8}, {1e-2, 1e-6}),
                  cap_sweep("newton_max_iterations", &SolverDesc::newton_max_iterations, {1, 2, 4, 30}, {1, 30}),
                  cell_size_sweep({2, 4.0 / 3, 1}, {})};
  elbow.sweeps[2].first_variant_only = true;  // the Newton cap: one material shows it
  // Quick: the lattice at 0.1 m (240 tets) instead of 0.05 m (1920), 8x cheaper references.
  elbow.quick_edit = [](SceneDesc& s) {
    for (BodyDesc& b : s.bodies) b.cell_size *= 2;
  };
  elbow.quick_note = "cell size 0.1 m (240 tets)";
  elbow.steps = 90, elbow.quick_steps = 45, elbow.sample_every = 9;
  families.push_back(elbow);
  return families;
}

void make_reference(SceneDesc& scene, int h_divisor) {
  scene.h /= h_divisor;
  SolverDesc& s = scene.solver;
  s.linear = "cholmod";
  s.refactor_interval = 1;
  s.pgs_max_iterations = std::max(s.pgs_max_iterations, 2000);
  s.pgs_tolerance = 1e-9;
  s.sqp_max_iterations = std::max(s.sqp_max_iterations, 50);
  s.sqp_tolerance = 1e-6;
  s.sqp_position_tolerance = 1e-8;
  s.sqp_stall_tolerance = 0;  // no stalls accepted: converge to the tolerances above
  s.strain_tolerance = 1e-6;
  s.contact_tolerance = 1e-6;
  // The divergence test counts in tolerances: back to the defaults' absolute thresholds (1 in
  // stretch and in Ue/Umax - 1; for contact 1 m instead of 0.1 m), or a reference that ends a
  // step at its SQP cap a little past the tight tolerances would be refused.
  s.divergence_violation_limit *= 1e3;
  s.newton_tolerance = 1e-10;
  s.newton_max_iterations = std::max(s.newton_max_iterations, 100);
  s.sleep_steps = 0;
}

void prepare_for_study(SceneDesc& scene) {
  scene.solver.sleep_steps = 0;
  for (BodyDesc& b : scene.bodies)
    if (b.mesh_path.empty() && b.tet_mesh_path.empty() && b.surface_resolution == 0) b.surface_resolution = b.cell_size / 3;
}

}  // namespace sinew::wp
