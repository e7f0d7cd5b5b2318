#pragma once
// The constant part of a simulation: everything that does not change during a run.
// Built once from a SceneDesc by build_model(); read by every stage of World::step().
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "engine/assembly/element_schedule.hpp"
#include "engine/assembly/node_elements.hpp"
#include "engine/assembly/system_pattern.hpp"
#include "engine/collision/surface_cells.hpp"
#include "engine/fem/hex8.hpp"
#include "engine/fem/tet4.hpp"
#include "engine/materials/material.hpp"
#include "engine/geometry/embedding.hpp"
#include "engine/geometry/hex_lattice.hpp"
#include "engine/scene/scene.hpp"

namespace sinew {

enum class ElementType { Hex8, Tet4 };

struct Body {
  std::string name;
  ElementType element_type = ElementType::Hex8;
  // The simulation mesh at rest, world coordinates. Hex bodies: the voxel lattice. Tet
  // bodies: the tets in `cells` (nodes 0-3, the rest -1), `cell_coords` empty and
  // `cell_size` the lattice's (a lattice split into tets) or 0 (a tet mesh file).
  HexLattice lattice;
  int node_offset = 0;         // first global node
  int element_offset = 0;      // first global element
  TriMesh rest_surface;        // embedded surface at rest (renders and collides)
  Embedding embedding;         // surface vertex -> cell + trilinear weights
  SurfaceCells surface_cells;  // cell -> its surface vertices (contact broad phase)
  MaterialDesc material;
  double damping_mass = 0;     // Rayleigh alpha
  double damping_stiffness = 0;  // Rayleigh beta
  EnergyLimitDesc energy_limit;
  StrainLimitDesc strain_limit;
  std::shared_ptr<const Material> hyperelastic;  // null: linear corotational (warped stiffness)
  double rest_volume = 0;      // sum of the elements' rest volumes (m^3)
  // Hyperelastic bodies: sum_e ((2 mu_L + lambda_L) V_e^(2/3))^2, the squares of its elements'
  // forces at unit strain (N^2); 0 for a linear body.
  double unit_strain_forces2 = 0;
  int num_nodes() const { return static_cast<int>(lattice.nodes.size()); }
  int num_elements() const { return static_cast<int>(lattice.cells.size()); }
};

// A scene load on nodes (LoadDesc): per-node force, ramped in over ramp_time.
struct NodeLoad {
  std::vector<int> nodes;  // global
  Vec3 node_force = Vec3::Zero();
  double ramp_time = 0;
  // Fraction of the force applied at time t: min(1, t / ramp_time), 1 without a ramp.
  double ramp(double t) const { return ramp_time > 0 ? std::min(1.0, t / ramp_time) : 1.0; }
};

// Nodes on a prescribed rigid rotation (DrivenDesc): solved like fixed nodes (free_index
// -1, not unknowns of the step), but placed where the motion puts them at the end of the
// step (solve_newton) and given the step's mean velocity.
struct DrivenNodes {
  std::vector<int> nodes;      // global
  Vec3 axis = Vec3::UnitZ();   // unit
  Vec3 pivot = Vec3::Zero();
  double radians = 0;          // total rotation
  double duration = 0;         // s; 0: the full rotation at once
  // pivot + Rot(axis, radians s(min(1, t / duration))) (rest - pivot), s(u) = 3u^2 - 2u^3.
  Vec3 position(const Vec3& rest, double t) const;
};

struct Model {
  std::string scene_name;
  std::vector<Body> bodies;
  std::vector<Hex8Reference> references;       // hex8: one per (cell size, material)
  std::vector<Tet4Reference> tet_references;   // tet4: one per element
  std::vector<Mat83> tet_gradients;            // tet4: dN/dX padded to 8 rows (hyperelastic path)
  // tet4: rest volumes, beside tet_references[i].volume: the hyperelastic passes read them
  // per tet, and a reference is 1.6 kB (a cache line and often a page a tet).
  std::vector<double> tet_volumes;
  std::vector<ObstacleDesc> obstacles;
  SolverDesc solver;
  Vec3 gravity = Vec3::Zero();
  std::vector<NodeLoad> loads;
  std::vector<DrivenNodes> driven;
  double h = 1.0 / 60.0;

  int num_nodes = 0;
  VecX rest_x;                                 // 3 * num_nodes, rest positions
  VecX node_mass;                              // num_nodes, lumped mass, kg
  std::vector<int> node_body;                  // num_nodes
  std::vector<int> free_index;                 // num_nodes: free node index, -1 if fixed or driven
  int num_free = 0;

  int num_elements = 0;
  // Global node indices, paper order; a tet uses the first 4 and holds -1 in the rest.
  std::vector<std::array<int, 8>> element_nodes;
  std::vector<ElementType> element_type;
  std::vector<int> element_body;
  std::vector<int> element_reference;          // into references (hex8) or tet_references (tet4)
  bool has_hyperelastic = false;               // some body is solved by Newton (solve_newton)
  // The awake hyperelastic bodies' elements' forces at unit strain: the square root of the sum
  // of their Body::unit_strain_forces2 (N), the scale of Newton's residual for a body with no
  // load, momentum or stress (update_unit_strain_forces).
  double hyperelastic_unit_strain_forces = 0;
  bool has_strain_limits = false;
  std::vector<Mat3> element_strain_frame;      // per element: the strain limits' material axes
  std::vector<double> element_Umax;            // energy limit, 0 when the element has none
  // Elements split into colours that share no node, so that each colour can be
  // scattered in parallel without locks and in a fixed order (deterministic sums):
  // scatter_warped_stiffness (the constraints' curvature). A sleeping body's elements are in
  // no colour (frozen_model.cpp). Stage 1 (assemble_system) sums per-element results by
  // node instead (node_elements below; ARCHITECTURE.md, "Determinism and threads").
  std::vector<std::vector<int>> element_colors;
  // Per node, its elements in ascending order: stage 1's sums into nodes (forces, b, b - A v0,
  // element-by-element products) run in parallel by node, each in element order
  // (node_elements.hpp). The same in a frozen model (sleepers' elements have stiffness_scale 0).
  NodeElements node_elements;
  // The same guarantee by blocks of consecutive elements (element_schedule.hpp), read in
  // memory order: solve_newton's hyperelastic assembly, and the system matrix before a
  // factorisation (assemble_system_matrix).
  ElementSchedule element_schedule;

  SystemPattern pattern;                       // sparsity of the free-DOF system matrix

  // Per body, 1 if asleep: set only in the model World::step passes to the stages while some
  // bodies sleep (engine/sleep/sleep.hpp, freeze_sleeping_bodies); empty: every body awake.
  std::vector<char> body_asleep;
  bool asleep(int body) const { return !body_asleep.empty() && body_asleep[body]; }
};

// Builds geometry, lattices, element references, masses and the system pattern.
// Throws InputError (naming the scene file and JSON path) on empty lattices or bad meshes;
// warnings (open mesh) go to `warn`.
Model build_model(const SceneDesc& scene, const std::function<void(const std::string&)>& warn);

// Model::hyperelastic_unit_strain_forces over the bodies that have a hyperelastic energy (a
// sleeper's is taken away by freeze_sleeping_bodies, so a large stiff body asleep does not
// raise the floor of a small one awake).
inline void update_unit_strain_forces(Model& model) {
  double sum = 0;
  for (const Body& body : model.bodies)
    if (body.hyperelastic) sum += body.unit_strain_forces2;
  model.hyperelastic_unit_strain_forces = std::sqrt(sum);
}

}  // namespace sinew
