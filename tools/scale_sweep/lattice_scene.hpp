#pragma once
// The scene of the scale sweep: one block of hexahedra resting on a ground plane with
// friction, sagging under gravity, with a per-element energy limit that some elements reach.
// The block is 1 m x 0.5 m x 0.5 m at every size, 2k x k x k cells of edge 0.5 m / k, with the
// same embedded surface and contact margin: the physics stays the same and only the lattice
// changes.
#include <string>

namespace sinew::sweep {

struct LatticeDims {
  int nx = 0, ny = 0, nz = 0;
  double cell_size = 0;  // m
  int cells() const { return nx * ny * nz; }
};

// The scene's physical parameters, the same at every size.
struct RestingBlock {
  double height = 0.5;                   // m, the y and z extent (x is twice that)
  double E = 1e5, nu = 0.3, rho = 1000;  // Pa, -, kg/m^3: ~5 % static strain at the bottom
  double stiffness_damping = 0.01;       // s (Rayleigh beta)
  // J/m^3; each element's Umax is this times its volume. The static energy density at the
  // bottom is ~120 J/m^3; the sag overshoots it and the edges of the contact concentrate it.
  double energy_density_limit = 600;
  double surface_resolution = 0.1;  // m, the embedded surface's edge length (638 vertices)
  double contact_margin = 0.01;     // m (solver.contact_margin; its default, cell / 4, varies with the size)
  double friction = 0.5;            // Coulomb coefficient with the ground
  double h = 1.0 / 60;              // s
};

// The lattice of 2k x k x k cells nearest `target` cells: k = round(cbrt(target / 2)), at
// least 1. (100 -> 128, 300 -> 250, 1000 -> 1024, 3000 -> 2662, 10000 -> 9826, 20000 -> 21296.)
LatticeDims lattice_for(int target, const RestingBlock& block);

// The scene as JSON text for parse_scene_text (docs/scenes.md). Bodies never sleep
// (solver.sleep_steps 0), so that every timed step simulates the block.
std::string lattice_scene_text(const LatticeDims& dims, const RestingBlock& block);

}  // namespace sinew::sweep
