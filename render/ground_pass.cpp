#include "render/ground_pass.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace sinew {
namespace {

const Eigen::Vector3f kSkyTop(0.60f, 0.70f, 0.82f), kSkyBottom(0.90f, 0.92f, 0.94f);
constexpr double kGroundRadii = 6;  // half size of the ground square, in scene radii

// A triangle covering the screen, from gl_VertexID alone.
const char* kBackgroundVs = R"(#version 330 core
out float v_height;
void main() {
  vec2 p = vec2((gl_VertexID & 1) * 4 - 1, (gl_VertexID & 2) * 2 - 1);
  v_height = p.y * 0.5 + 0.5;
  gl_Position = vec4(p, 0.999, 1.0);
})";
const char* kBackgroundFs = R"(#version 330 core
in float v_height;
uniform vec3 top, bottom;
out vec4 color;
void main() { color = vec4(mix(bottom, top, clamp(v_height, 0.0, 1.0)), 1.0); })";

const char* kGroundVs = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view_projection;
out vec3 v_world;
void main() { v_world = position; gl_Position = view_projection * vec4(position, 1.0); })";
const char* kGroundFs = R"(#version 330 core
in vec3 v_world;
uniform vec3 origin, axis_u, axis_v, centre, normal, light, sky_top, sky_bottom;
uniform float spacing, fade_radius, screen_height;
out vec4 color;
// 1 on a grid line of about `width` pixels, 0 away from it (antialiased by the
// screen-space derivative of the grid coordinate).
float line(vec2 c, float width) {
  vec2 w = fwidth(c);
  vec2 d = abs(fract(c - 0.5) - 0.5) / max(w, vec2(1e-6));
  float on = 1.0 - clamp(min(d.x, d.y) - 0.5 * width + 0.5, 0.0, 1.0);
  return on * (1.0 - smoothstep(0.15, 0.4, max(w.x, w.y)));  // drop lines denser than ~3 px
}
void main() {
  vec3 r = v_world - origin;
  vec2 c = vec2(dot(r, axis_u), dot(r, axis_v)) / spacing;
  vec3 base = vec3(0.80, 0.80, 0.78) * (0.45 + 0.55 * max(dot(normal, light), 0.0));
  vec3 col = mix(base, base * 0.78, line(c, 1.0));
  col = mix(col, base * 0.55, line(c / 5.0, 1.6));
  // Fade into the background pixel behind, so the ground's edge leaves no horizon line.
  vec3 sky = mix(sky_bottom, sky_top, gl_FragCoord.y / screen_height);
  float fade = smoothstep(0.45 * fade_radius, fade_radius, length(v_world - centre));
  color = vec4(mix(col, sky, fade), 1.0);
})";

}  // namespace

double grid_spacing(double scene_radius) {
  const double target = scene_radius / 4;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * decade * 1.5 >= target) return m * decade;
  return 10 * decade;
}

GroundPass::GroundPass()
    : m_background(kBackgroundVs, kBackgroundFs, "background"),
      m_ground(kGroundVs, kGroundFs, "ground"),
      m_empty({}),
      m_quad({3}) {}

void GroundPass::draw_background() {
  glDisable(GL_DEPTH_TEST);
  m_background.use();
  m_background.set("top", kSkyTop);
  m_background.set("bottom", kSkyBottom);
  m_empty.draw_generated(GL_TRIANGLES, 3);
}

void GroundPass::draw_ground(const ViewSetup& view) {
  const Vec3 n = view.ground.normal;
  const Vec3 u = orbit_reference(n), v = n.cross(u);
  const Vec3 centre = view.scene_centre - (view.scene_centre - view.ground.point).dot(n) * n;
  const double half = kGroundRadii * view.scene_radius;
  std::vector<float> corners;
  for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    const Vec3 p = centre + half * (a * u + b * v);
    corners.insert(corners.end(), {float(p.x()), float(p.y()), float(p.z())});
  }
  m_quad.set_vertices(corners);

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  m_ground.use();
  m_ground.set("view_projection", view.view_projection);
  // Grid lines at world multiples of the spacing: origin is the world origin on the plane.
  const Vec3 origin = view.ground.point.dot(n) * n;
  m_ground.set("origin", Eigen::Vector3f(origin.cast<float>()));
  m_ground.set("axis_u", Eigen::Vector3f(u.cast<float>()));
  m_ground.set("axis_v", Eigen::Vector3f(v.cast<float>()));
  m_ground.set("centre", Eigen::Vector3f(centre.cast<float>()));
  m_ground.set("normal", Eigen::Vector3f(n.cast<float>()));
  m_ground.set("light", view.light);
  m_ground.set("sky_top", kSkyTop);
  m_ground.set("sky_bottom", kSkyBottom);
  m_ground.set("screen_height", float(view.height));
  m_ground.set("spacing", float(grid_spacing(view.scene_radius)));
  m_ground.set("fade_radius", float(half));
  m_quad.draw(GL_TRIANGLE_FAN);
  glDisable(GL_STENCIL_TEST);
}

}  // namespace sinew
