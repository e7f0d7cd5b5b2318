// After a step: rows wake sleepers, quiet islands fall asleep (engine/sleep/sleep.hpp).
#include <cmath>
#include <numeric>

#include "engine/constraints/contact_candidates.hpp"
#include "engine/sleep/sleep.hpp"

namespace sinew {
namespace {

// Mass-weighted RMS of the velocity (sqrt(2 kinetic energy / mass)) and of its change over
// the step divided by h (the net force on the body per unit mass, the step's residual).
struct BodyMotion {
  double speed = 0, acceleration = 0;
};
BodyMotion body_motion(const Model& model, int b, const VecX& v0, const VecX& v) {
  const Body& body = model.bodies[b];
  double mass = 0, v2 = 0, dv2 = 0;
  for (int n = body.node_offset; n < body.node_offset + body.num_nodes(); ++n) {
    const double m = model.node_mass[n];
    mass += m;
    v2 += m * v.segment<3>(3 * n).squaredNorm();
    dv2 += m * (v.segment<3>(3 * n) - v0.segment<3>(3 * n)).squaredNorm();
  }
  if (mass <= 0) return {};
  return {std::sqrt(v2 / mass), std::sqrt(dv2 / mass) / model.h};
}

// Union-find over bodies; the root of a set is its lowest body.
int find(std::vector<int>& parent, int b) {
  while (parent[b] != b) b = parent[b] = parent[parent[b]];
  return b;
}
void unite(std::vector<int>& parent, int a, int b) {
  a = find(parent, a), b = find(parent, b);
  if (a != b) parent[std::max(a, b)] = std::min(a, b);
}

}  // namespace

void update_sleep(const Model& model, const VecX& v0, State& state) {
  SleepState& sleep = state.sleep;
  const SolverDesc& cfg = model.solver;
  const int nb = static_cast<int>(model.bodies.size());
  // Kept storage (a warm step allocates nothing), bound to local references as in the row
  // builders.
  thread_local std::vector<char> slept_storage, ready_storage;
  thread_local std::vector<int> parent_storage;
  thread_local std::vector<Aabb> bounds_storage;
  std::vector<char>& slept = slept_storage;
  std::vector<char>& ready = ready_storage;
  std::vector<int>& parent = parent_storage;
  std::vector<Aabb>& bounds = bounds_storage;
  slept = sleep.asleep;  // during this step

  // Islands: bodies that share a row. A row that reaches a sleeper comes from an awake body
  // (sleepers get no rows of their own): that body touches it, so it wakes.
  parent.resize(nb);
  std::iota(parent.begin(), parent.end(), 0);
  const RowTable& rows = state.rows;
  for (int i = 0; i < rows.size(); ++i)
    for (int k = rows.begin[i]; k < rows.begin[i + 1]; ++k) {
      const int b = model.node_body[rows.nodes[k]];
      unite(parent, model.node_body[rows.nodes[rows.begin[i]]], b);
      if (sleep.asleep[b]) wake_island(sleep, b);
    }

  for (int b = 0; b < nb; ++b) {
    if (slept[b]) continue;
    const BodyMotion motion = body_motion(model, b, v0, state.v);
    const bool quiet = motion.speed <= cfg.sleep_speed && motion.acceleration <= cfg.sleep_acceleration;
    sleep.quiet_steps[b] = quiet ? sleep.quiet_steps[b] + 1 : 0;
  }
  for (const Attachment& a : state.attachments) sleep.quiet_steps[a.body] = 0;  // held: never asleep

  // An island sleeps when all its bodies have been quiet long enough and nothing is about
  // to move any of them during the next step.
  ready.assign(nb, 1);
  bounds.assign(nb, Aabb{});
  for (int b = 0; b < nb; ++b) {
    const int root = find(parent, b);
    if (sleep.asleep[b] || sleep.quiet_steps[b] < cfg.sleep_steps) {
      ready[root] = 0;
      continue;
    }
    bounds[b] = body_surface_bounds(state.x, model.bodies[b]);
    if (body_disturbed(model, b, state.t, bounds[b])) ready[root] = 0;
  }
  for (int b = 0; b < nb; ++b) {
    if (!ready[find(parent, b)]) continue;
    const Body& body = model.bodies[b];
    sleep.asleep[b] = 1;
    sleep.island[b] = find(parent, b);
    sleep.bounds[b] = bounds[b];
    state.v.segment(3 * body.node_offset, 3 * body.num_nodes()).setZero();
    sleep.external_force = state.external_force;
    sleep.changed = true;
  }
}

}  // namespace sinew
