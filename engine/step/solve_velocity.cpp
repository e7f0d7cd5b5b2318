#include "engine/step/stages.hpp"

namespace sinew {

bool solve_velocity(const Model& model, LinearSolver& solver, State& state) {
  {
    StageTimer timer(state.profile, Stage::Factorize);
    if (!solver.factorize(state.system)) return false;
  }
  StageTimer timer(state.profile, Stage::Solve);
  // PCG warm start: the previous step's velocities.
  for (int n = 0; n < model.num_nodes; ++n) {
    const int fi = model.free_index[n];
    if (fi >= 0) state.v_free.segment<3>(3 * fi) = state.v.segment<3>(3 * n);
  }
  const int iterations = solver.solve(state.rhs, state.v_free);
  if (!solver.uses_cholmod()) state.profile.iterations["pcg"] += iterations;
  for (int n = 0; n < model.num_nodes; ++n) {
    const int fi = model.free_index[n];
    state.v.segment<3>(3 * n) = fi >= 0 ? Vec3(state.v_free.segment<3>(3 * fi)) : Vec3::Zero();
  }
  return true;
}

}  // namespace sinew
