// What wakes a sleeping body before a step (engine/sleep/sleep.hpp).
#include "engine/collision/obstacle_motion.hpp"
#include "engine/collision/obstacle_sdf.hpp"
#include "engine/constraints/contact_rows.hpp"
#include "engine/sleep/sleep.hpp"

namespace sinew {

// Loads and driven regions belong to one body each (build_model), so their first node says which.
bool body_disturbed(const Model& model, int b, double t, const Aabb& bounds) {
  const double t1 = t + model.h;
  for (const NodeLoad& load : model.loads)
    if (!load.nodes.empty() && model.node_body[load.nodes.front()] == b && load.ramp(t1) != load.ramp(t)) return true;
  for (const DrivenNodes& driven : model.driven) {
    if (driven.nodes.empty() || model.node_body[driven.nodes.front()] != b) continue;
    // Bitwise comparison: a finished motion gives identical positions at both times.
    for (int n : driven.nodes) {
      const Vec3 rest = model.rest_x.segment<3>(3 * n);
      if (driven.position(rest, t1) != driven.position(rest, t)) return true;
    }
  }
  // The same test as the contact broad phase, with the obstacle where the step leaves it.
  for (const ObstacleDesc& ob : model.obstacles) {
    const Vec3 origin = obstacle_position(ob, t1);
    if (origin != obstacle_position(ob, t) && obstacle_distance_bound(ob, origin, bounds) < contact_margin(model, b))
      return true;
  }
  return false;
}

void wake_island(SleepState& sleep, int b) {
  const int island = sleep.island[b];
  if (!sleep.asleep[b]) return;
  for (size_t c = 0; c < sleep.asleep.size(); ++c)
    if (sleep.asleep[c] && sleep.island[c] == island) {
      sleep.asleep[c] = 0;
      sleep.island[c] = -1;
      sleep.quiet_steps[c] = 0;
      sleep.changed = true;
    }
}

void wake_disturbed_bodies(const Model& model, State& state) {
  SleepState& sleep = state.sleep;
  for (int b = 0; b < static_cast<int>(model.bodies.size()); ++b) {
    if (!sleep.asleep[b]) continue;
    const Body& body = model.bodies[b];
    const auto seg = [&](const VecX& values) { return values.segment(3 * body.node_offset, 3 * body.num_nodes()); };
    // A caller may set external forces or velocities between steps (World::mutable_state).
    if (body_disturbed(model, b, state.t, sleep.bounds[b]) || seg(state.external_force) != seg(sleep.external_force) ||
        !seg(state.v).isZero(0))
      wake_island(sleep, b);
  }
  // A grabbed body (ui/ attachments) is being moved by the caller: awake while held.
  for (const Attachment& a : state.attachments)
    if (sleep.asleep[a.body]) wake_island(sleep, a.body);
}

}  // namespace sinew
