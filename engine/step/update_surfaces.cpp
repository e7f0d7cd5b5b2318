#include "engine/step/stages.hpp"

namespace sinew {

void update_surfaces(const Model& model, State& state) {
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.asleep(static_cast<int>(b))) continue;  // x unchanged since it fell asleep
    const Body& body = model.bodies[b];
    compute_embedded_positions(body.embedding, body.lattice, state.x, body.node_offset,
                               state.surface[b]);
  }
}

}  // namespace sinew
