#pragma once
// A scene as read from JSON (SI units). Schema: docs/scenes.md. Parsing validates
// everything it can without building the simulation; errors name the file and JSON path.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/types.hpp"
#include "engine/geometry/shape.hpp"

namespace sinew {

// Nodes selected by a region are fixed (zero velocity) for the whole run.
struct RegionDesc {
  enum class Kind { Box, HalfSpace } kind = Kind::Box;
  Vec3 a = Vec3::Zero();  // box: min corner; half-space: a point on its plane
  Vec3 b = Vec3::Zero();  // box: max corner; half-space: outward normal (selects (x-a).b <= 0)
  bool contains(const Vec3& p) const;
};

// "corotational" is the linear corotational element of papers 000 and 001 (warped
// stiffness, one linear solve per step). Every other model is a hyperelastic energy of
// engine/materials/ solved by Newton's method on the incremental potential (paper 003).
struct MaterialDesc {
  std::string model = "corotational";
  double E = 0;                        // Young's modulus, Pa, > 0
  double nu = 0;                       // Poisson's ratio, [0, 0.5)
  double rho = 0;                      // density, kg/m^3, > 0
  double fung_c = 1;                   // "fung" only: exponent scale, > 0
  double arruda_boyce_n = 8;           // "arruda_boyce" only: chain segments N, > 1
  // "volume_term": "mean_dilatation": hex8 elements integrate the volume term g(J) at the
  // element's mean J instead of at each Gauss point (against locking as nu -> 1/2); only for
  // models of the form f(Ic) + g(J). Default "per_point".
  bool mean_dilatation = false;
  bool hyperelastic() const { return model != "corotational"; }
};
// Scene model name -> engine/materials name ("corotational_hyperelastic" -> "corotational").
const std::vector<std::string>& material_model_names();

// Strain limits (paper 001, section 3) on the singular values of F, per material axis j:
// smin_j <= stretch along j <= smax_j. An axis without limits has smin 0 and smax +inf.
struct StrainLimitDesc {
  bool enabled = false;
  Vec3 smin = Vec3::Zero();
  Vec3 smax = Vec3::Constant(std::numeric_limits<double>::infinity());
  Mat3 frame = Mat3::Identity();     // columns: the material axes in rest (world) coordinates
  // Per-region frames (e.g. fibres that turn): elements whose rest centre is inside take
  // the frame of the last region that holds it.
  std::vector<std::pair<RegionDesc, Mat3>> frame_regions;
  std::string mode = "hyperbolic";   // "hyperbolic", "orthogonal", "linear" or "isotropic"
  std::string pair_cuts = "on";      // hyperbolic: "on" (cuts near equal stretches) or "off"
};

// Energy limit (paper 000, eq. 14), per body with per-region overrides.
struct EnergyLimitRegion {
  RegionDesc region;  // elements whose rest centre is inside
  double Umax = 0;
};
struct EnergyLimitDesc {
  bool enabled = false;
  double Umax = 0;  // J, > 0
  std::vector<EnergyLimitRegion> regions;
  std::string jacobian = "exact";  // "exact" (eqs. 15-18) or "warped" (f_e / Umax)
};

// A force on a region of a body: `force` (N, total) split equally over the nodes of the
// region, ramped linearly from 0 over `ramp_time` seconds, then held.
struct LoadDesc {
  RegionDesc region;
  Vec3 force = Vec3::Zero();
  double ramp_time = 0;
};

// Nodes moved along a prescribed rigid rotation (kinematic boundary, e.g. paper 003's
// elbow): the nodes whose rest position lies in `region` go to
//   pivot + Rot(axis, angle(t)) (X - pivot),  angle(t) = degrees * s(min(1, t / duration)),
// s(u) = 3 u^2 - 2 u^3 (zero angular velocity at both ends of the ramp), then stay there.
// Hyperelastic (Newton) bodies only.
struct DrivenDesc {
  RegionDesc region;
  Vec3 axis = Vec3::UnitZ();       // unit
  Vec3 pivot = Vec3::Zero();       // m
  double degrees = 0;              // total rotation, right-handed about axis
  double duration = 0;             // s, >= 0; 0: the full rotation from the first step
};

struct BodyDesc {
  std::string json_path;   // e.g. "bodies[0]", for later error messages
  std::string name;
  // Geometry: exactly one of shape (union of primitives) or mesh (OBJ path, absolute or
  // resolved against the scene file's folder).
  Shape shape;
  std::string mesh_path;
  std::string tet_mesh_path;       // or a tet mesh (TetGen .node/.ele or Gmsh .msh): a tet body
  // Elements of a shape or OBJ body: "hex" (the lattice cells) or "tet" (each cell split
  // into tets, engine/geometry/lattice_tets.hpp). A tet_mesh body is always "tet".
  std::string elements = "hex";
  // Applied to the mesh or to the shape's primitives: x_world = translate + rotate * (scale * x).
  double scale = 1;
  Mat3 rotate = Mat3::Identity();
  Vec3 translate = Vec3::Zero();
  double cell_size = 0;            // m, > 0
  double surface_resolution = 0;   // m; 0 = cell_size / 3 (procedural shapes only)
  MaterialDesc material;
  double damping_mass = 0;         // Rayleigh alpha, 1/s, >= 0
  double damping_stiffness = 0;    // Rayleigh beta, s, >= 0
  std::vector<RegionDesc> fixed;
  Vec3 velocity = Vec3::Zero();    // initial, m/s
  EnergyLimitDesc energy_limit;
  StrainLimitDesc strain_limit;    // tet bodies only
  std::vector<LoadDesc> loads;
  std::vector<DrivenDesc> driven;  // hyperelastic bodies only
};

// Scripted motion of a kinematic obstacle: a pure translation of its reference point (the
// plane's `point`, the centre of the other types). Rotation is fixed.
struct ObstacleKeyframe {
  double t = 0;                    // s
  Vec3 position = Vec3::Zero();    // m, the reference point at time t
};
struct ObstacleMotion {
  // Constant velocity (used when keyframes is empty): position(t) = point + velocity t.
  Vec3 velocity = Vec3::Zero();    // m/s
  // Else piecewise linear between keyframes (t strictly increasing), held before the first
  // and after the last.
  std::vector<ObstacleKeyframe> keyframes;
};

class MeshSdf;  // engine/collision/mesh_sdf.hpp

// An infinitely stiff obstacle with a signed distance (engine/collision/obstacle_sdf.hpp).
struct ObstacleDesc {
  enum class Kind { Plane, Box, Sphere, Capsule, Mesh };
  std::string json_path;
  std::string type = "plane";      // "plane", "box", "sphere", "capsule" or "mesh"
  Kind kind = Kind::Plane;         // the same, parsed
  Vec3 point = Vec3::Zero();       // plane: a point on it; others: the centre (at t = 0)
  Vec3 normal = Vec3::UnitY();     // plane: normalised by the parser, points to the free side
  Vec3 half_extents = Vec3::Constant(0.5);  // box, m
  double radius = 0.5;             // sphere, capsule, m
  double half_length = 0;          // capsule: half the axis segment (local y), m
  Mat3 rotation = Mat3::Identity();  // box, capsule, mesh: local to world
  std::string mesh_path;           // mesh: OBJ file (absolute), a closed surface
  double scale = 1;                // mesh: x = point + rotation * (scale * x_obj)
  std::shared_ptr<const MeshSdf> mesh;  // mesh: built by build_model(), null before
  double friction = 0.5;           // Coulomb mu, >= 0
  ObstacleMotion motion;
};

struct SolverDesc {
  std::string linear = "cholmod";  // "cholmod" or "pcg"
  double pcg_tolerance = 1e-8;     // relative residual
  int pcg_max_iterations = 1000;
  // Constraint solver (paper 000, section 5).
  int pgs_max_iterations = 200;
  double pgs_tolerance = 0.05;     // stop when every row's LCP natural residual, as a change of its
                                   // C over the step, is below this fraction of its kind's tolerance
                                   // (contacts: 5e-6 m, below sqp_position_tolerance, so that PGS's
                                   // error does not keep SQP from converging)
  // Every this many PGS sweeps that leave pgs_tolerance unmet, a subspace step: conjugate
  // gradients on the rows strictly inside their bounds (lcp_subspace.hpp). 0: plain PGS.
  int pgs_subspace_interval = 8;
  // "active_set": with a factored W (more rows than touched DOFs), PGS sweeps the rows with
  // force with their block of W formed (lcp_active_set.hpp); "all_rows": every row, on T.
  std::string pgs_sweeps = "active_set";
  int sqp_max_iterations = 10;
  double sqp_tolerance = 1e-3;     // worst Ue/Umax - 1 accepted
  double sqp_position_tolerance = 1e-5;  // m: converged when the last correction moves no node further
  double sqp_stall_tolerance = 4e-5;  // m: also converged, within every row's tolerance, when the
                                     // corrections stop shrinking and moved no node further (0: off)
  // "once": a step whose previous accepted step ended within every limit's tolerance and that
  // reaches sqp_max_iterations outside them, with none of its iterates within them, goes on
  // for as many again, once; "none": the cap is final.
  std::string sqp_cap_extension = "once";
  // "accept": a line search's first trial that brings an iterate past some tolerance within
  // every one is taken whatever the l1 merit says (a filter's acceptance; solve_constraints.cpp);
  // "none": the merit alone decides ("accept" did not save time on the flat finger:
  // docs/ARCHITECTURE.md, "SQP globalisation").
  std::string sqp_restoration = "none";
  std::string sqp_kkt_stop = "on";  // "on": stop at a KKT point without a confirming QP (sqp_kkt_stop.hpp)
  // With an earlier step's factorisation and rows without curvature: "conjugate" steps
  // (each QP's step made A-conjugate to the last, taken to the Lagrangian's minimiser along
  // it), or "none" (the QP's step as it is).
  std::string sqp_acceleration = "conjugate";
  // Hyperelastic bodies: "impulse" adds the last step's constraint impulse J^T lambda to
  // Newton's objective as a fixed force, so that Newton solves for the body as it was held
  // and the SQP corrects only the change of lambda; "none": Newton without it.
  std::string newton_predictor = "impulse";
  // "shared": SQP iterations after the first take the Newton step and the correction in one
  // solve where W came from the rows' own columns and that is cheaper; "separate": two.
  std::string sqp_solves = "shared";
  // Factorise the system every this many steps (1: every step, as the paper). In between
  // the last factorisation is reused: the SQP loop's Newton iterations still converge to
  // the same tolerances, at a fraction of the cost while rotations change slowly; a step
  // without SQP iterations keeps the one Newton step of the older H (docs/scenes.md).
  int refactor_interval = 1;
  // A factorisation that carries the constraints' curvature (energy or strain limits with
  // force) is not the step's A either way, so it is kept for up to this many steps while
  // every step after it converges in no more SQP iterations than the step that made it
  // (and refactorises none); 1: a curved system is factorised every step. The settled
  // side-pressed finger: one factorisation in ~16 steps instead of every step.
  int curved_refactor_interval = 16;
  // The precision of the factor's values in solves with an earlier step's factorisation of
  // another matrix (not one with constraint curvature, whose solves read its own values): a
  // preconditioner there (Newton's CG, SQP's iterations, which stop on true residuals and violations at
  // the same tolerances either way; docs/scenes.md).
  // "single": a float copy of the values, read and widened to double (half the memory read
  // by each solve); "double": the factor itself. Exact solves always use the factor itself.
  std::string stale_factor_precision = "single";
  // Hyperelastic tets (one point, invariant materials) keep the projected Hessian formed at an
  // earlier Newton assembly while their F stays within this (entrywise) of the F it was
  // formed at (0: every assembly forms every Hessian); the gradient is always exact, and
  // Newton's tolerances are met either way (docs/scenes.md).
  double hessian_reuse_tolerance = 1e-3;
  // Keep H^-1 on the nodes constraint rows touch (touched_inverse.hpp) for up to this many
  // steps across refactorisations, topping it up with the current factor for nodes touched
  // for the first time. The LCP then runs on that approximate W, corrected by the exact
  // W lambda of its warm start (one extra solve per SQP iteration), so SQP converges to the
  // same tolerances; a stall recomputes it. 1: recompute with every factorisation.
  int delassus_reuse = 64;
  double activation_margin = 0.05; // rows for elements with Ue/Umax > 1 - margin (predicted)
  // Contact (engine/constraints/contact_rows.hpp).
  double contact_tolerance = 1e-4; // m, deepest penetration SQP accepts
  double contact_margin = -1;      // m, rows for vertices nearer than this; < 0: a quarter of the body's cell size
  double body_friction = 0.5;      // Coulomb mu between two bodies
  double max_speed = 1e4;          // m/s: a step that makes any node faster diverged (rolled back, run stops)
  // A step run at lower caps than the scene's (the real-time budget) that ends with some
  // constraint more than this many times its tolerance past it is rolled back and retried
  // at the scene's caps: a budget trades accuracy, never stability.
  double budget_violation_limit = 10;
  // A step that ends with some constraint more than this many times its tolerance past it has
  // diverged, whatever its caps: rolled back and retried like a NaN (afresh, then in 2 and 4
  // sub-steps), the run stopping if none holds. Taken, such steps ran away: a strain-limited
  // column hit by random node moves went 142 -> 1,000 -> 3,220 -> 979,000 tolerances past its
  // limits in four steps, nodes at 4.8 km/s. The shipped scenes stay within 1 tolerance, but
  // for paper 001's orthogonal projection (25.7: its limits cannot all be met); the stress
  // suite's hits leave transients up to 840 that recover when taken (the side-pressed
  // finger; an energy-limited beam 191: at a limit of 100 its run stopped at the hit). A grab's
  // gap (attachment rows) is not counted. In units of the tolerances: tightening one tightens
  // this too (the work-precision references scale it back).
  double divergence_violation_limit = 1000;
  double strain_tolerance = 1e-3;  // worst strain-limit violation (stretch) SQP accepts
  double strain_activation_margin = 0.005;  // rows for constraints with C < this (stretch, predicted)
  // Newton on the incremental potential (hyperelastic bodies, paper 003).
  int newton_max_iterations = 20;
  double newton_tolerance = 1e-6;  // |gradient| relative to its value at the first iterate
  // Sleeping bodies (engine/sleep/): a body whose RMS speed and RMS acceleration stay at or
  // below these for sleep_steps consecutive steps sleeps until disturbed. 0 steps: never.
  double sleep_speed = 0.01;        // m/s, sqrt(2 kinetic energy / mass)
  double sleep_acceleration = 0.1;  // m/s^2, sqrt(sum m |dv/h|^2 / mass): the net force per unit mass
  int sleep_steps = 30;
};

struct SceneDesc {
  std::string path;                // file it came from ("" if parsed from a string)
  std::string name;
  Vec3 gravity = Vec3(0, -9.81, 0);
  double h = 1.0 / 60.0;           // time step, s, > 0
  double fps = 60;                 // frames per second of output, > 0
  int frames = 120;                // frames to run, > 0
  std::vector<BodyDesc> bodies;    // at least one
  std::vector<ObstacleDesc> obstacles;
  SolverDesc solver;
  int steps_per_frame() const;     // max(1, round(1 / (fps * h)))
};

// Reads and validates a scene file. Throws InputError "FILE: JSON.PATH: message".
SceneDesc load_scene(const std::string& path);
// Same, from text; `source_name` appears in messages, `base_dir` resolves mesh paths.
SceneDesc parse_scene_text(const std::string& text, const std::string& source_name,
                           const std::string& base_dir);

}  // namespace sinew
