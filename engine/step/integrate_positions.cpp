#include "engine/step/stages.hpp"

namespace sinew {

void integrate_positions(const Model& model, State& state) {
  state.x += model.h * state.v;
}

}  // namespace sinew
