#pragma once
// Finding the surface point a user grabs: the first surface under a pixel (a ray from the
// camera through it, intersected by Embree) or the surface vertex nearest a point. The
// grab then holds that vertex (engine/constraints/attachment_rows.hpp).
#include <optional>

#include "engine/constraints/attachment_rows.hpp"
#include "engine/state.hpp"
#include "render/camera.hpp"

namespace sinew {

// The ray through pixel (x right, y down from the top-left corner) of a width x height image.
void pixel_ray(const Camera& camera, float x, float y, int width, int height, Vec3& origin, Vec3& direction);

// The surface vertex of the triangle the ray hits first (its vertex nearest the hit point),
// over every body; empty if the ray misses them all.
std::optional<Attachment> pick_surface(const Model& model, const State& state, const Vec3& origin,
                                       const Vec3& direction);

// The surface vertex nearest p over every body.
Attachment nearest_surface_vertex(const Model& model, const State& state, const Vec3& p);

}  // namespace sinew
