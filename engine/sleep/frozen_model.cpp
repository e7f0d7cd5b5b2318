#include <algorithm>

#include "engine/sleep/sleep.hpp"

namespace sinew {

// A copy of the whole model, made only when the sleeping set changes (rare next to steps):
// every stage then runs unchanged on it, which keeps sleeping out of the stages' code except
// for obstacle contact and the surface update (Model::asleep).
Model freeze_sleeping_bodies(const Model& model, const std::vector<char>& asleep) {
  Model frozen = model;
  frozen.body_asleep = asleep;
  // Unknowns: the awake free nodes, renumbered in node order.
  frozen.num_free = 0;
  for (int n = 0; n < frozen.num_nodes; ++n)
    frozen.free_index[n] = model.free_index[n] >= 0 && !asleep[model.node_body[n]] ? frozen.num_free++ : -1;
  for (std::vector<int>& color : frozen.element_colors)
    std::erase_if(color, [&](int e) { return asleep[model.element_body[e]]; });
  // Blocks never span bodies (element_schedule.hpp): a sleeper's blocks go whole.
  for (std::vector<ElementBlock>& color : frozen.element_schedule.colors)
    std::erase_if(color, [&](const ElementBlock& block) { return asleep[model.element_body[block.first]]; });
  for (int e = 0; e < frozen.num_elements; ++e)
    if (asleep[model.element_body[e]]) frozen.element_Umax[e] = 0;
  frozen.has_hyperelastic = frozen.has_strain_limits = false;
  for (size_t b = 0; b < frozen.bodies.size(); ++b) {
    Body& body = frozen.bodies[b];
    if (asleep[b]) {
      body.energy_limit.enabled = body.strain_limit.enabled = false;
      body.hyperelastic = nullptr;  // hyperelastic energies are summed over bodies that have one
    }
    frozen.has_hyperelastic = frozen.has_hyperelastic || body.hyperelastic;
    frozen.has_strain_limits = frozen.has_strain_limits || body.strain_limit.enabled;
  }
  update_unit_strain_forces(frozen);  // Newton's residual floor: awake bodies only
  // Driven nodes of a sleeper are not moving (else it would not sleep): not placed again.
  std::erase_if(frozen.driven, [&](const DrivenNodes& d) { return !d.nodes.empty() && asleep[model.node_body[d.nodes.front()]]; });
  frozen.pattern = build_system_pattern(frozen.element_nodes, frozen.free_index, frozen.num_free);
  return frozen;
}

}  // namespace sinew
