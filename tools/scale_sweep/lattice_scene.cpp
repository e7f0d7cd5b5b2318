#include "tools/scale_sweep/lattice_scene.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace sinew::sweep {

LatticeDims lattice_for(int target, const RestingBlock& block) {
  LatticeDims d;
  d.ny = d.nz = std::max(1, static_cast<int>(std::lround(std::cbrt(target / 2.0))));
  d.nx = 2 * d.ny;
  d.cell_size = block.height / d.ny;
  return d;
}

// The block's sides are whole multiples of the cell size, so the voxeliser tiles it exactly
// (docs/voxelization.md). Its underside lies on the plane y = 0 at t = 0, at rest: the first
// steps are the sag under gravity (no impact, whose steps cost many times more at large
// sizes), then it settles. The surface is meshed at a fixed 0.1 m rather than the default
// cell / 3, so that the contact rows (one normal and two friction rows per surface vertex
// on the ground) are about the same at every size.
std::string lattice_scene_text(const LatticeDims& dims, const RestingBlock& block) {
  const double c = dims.cell_size;
  const double hx = 0.5 * c * dims.nx, hy = 0.5 * c * dims.ny, hz = 0.5 * c * dims.nz;
  const nlohmann::json body = {
      {"name", "block"},
      {"shape", {{{"type", "box"}, {"half_extents", {hx, hy, hz}}}}},
      {"transform", {{"translate", {0.0, hy, 0.0}}}},
      {"cell_size", c},
      {"surface_resolution", block.surface_resolution},
      {"material", {{"E", block.E}, {"nu", block.nu}, {"rho", block.rho}}},
      {"damping", {{"stiffness", block.stiffness_damping}}},
      {"energy_limit", {{"Umax", block.energy_density_limit * c * c * c}}}};
  const nlohmann::json scene = {
      {"name", "scale_sweep_block_" + std::to_string(dims.cells())},
      {"h", block.h},
      {"solver", {{"sleep_steps", 0}, {"contact_margin", block.contact_margin}}},
      {"bodies", {body}},
      {"obstacles", {{{"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 1, 0}}, {"friction", block.friction}}}}};
  return scene.dump();
}

}  // namespace sinew::sweep
