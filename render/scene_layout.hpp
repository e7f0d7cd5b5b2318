#pragma once
// Where things go in a picture of a scene: which way is up, where the ground is, and what
// box the default camera frames.
#include "engine/model.hpp"
#include "engine/state.hpp"

namespace sinew {

struct GroundPlane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitY();  // unit, pointing up
  bool from_obstacle = false;   // a "plane" obstacle of the scene, else placed under the bodies
};

// The first plane obstacle's normal, else against gravity, else +y.
Vec3 scene_up(const Model& model);

// Bounds of every body's deformed surface.
Aabb surface_bounds(const Model& model, const State& state);

// The first plane obstacle; without one, the plane through the lowest surface point along up.
GroundPlane choose_ground(const Model& model, const State& state);

// The bodies' bounds, extended by their footprint on the ground when the ground is no
// further below than twice the bounds' diagonal (so a body that will fall onto it is
// framed together with where it lands, but a far-away plane does not shrink the bodies).
Aabb framing_box(const Model& model, const State& state, const GroundPlane& ground);

}  // namespace sinew
