#include "render/surface_pass.hpp"

#include "render/surface_normals.hpp"

namespace sinew {
namespace {

constexpr float kAmbient = 0.35f;
constexpr float kShadowAlpha = 0.38f;

const char* kLitVs = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 albedo;
uniform mat4 view_projection;
out vec3 v_normal;
out vec3 v_albedo;
void main() {
  v_normal = normal;
  v_albedo = albedo;
  gl_Position = view_projection * vec4(position, 1.0);
})";
const char* kLitFs = R"(#version 330 core
in vec3 v_normal;
in vec3 v_albedo;
uniform vec3 light;
uniform float ambient;
out vec4 color;
void main() {
  float len = length(v_normal);
  vec3 n = len > 0.0 ? v_normal / len : vec3(0.0);
  if (!gl_FrontFacing) n = -n;  // inside of an open surface
  float lambert = max(dot(n, light), 0.0);
  color = vec4(v_albedo * (ambient + (1.0 - ambient) * lambert), 1.0);
})";

const char* kShadowVs = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view_projection;
uniform vec3 plane_point, plane_normal, light;
void main() {
  // Slide the point along the light direction until it meets the plane.
  float height = dot(position - plane_point, plane_normal);
  vec3 p = position - light * (height / dot(light, plane_normal));
  gl_Position = view_projection * vec4(p, 1.0);
})";
const char* kShadowFs = R"(#version 330 core
uniform float alpha;
out vec4 color;
void main() { color = vec4(0.0, 0.0, 0.0, alpha); })";

}  // namespace

Eigen::Vector3f body_color(size_t b) {
  static const Eigen::Vector3f palette[] = {{0.92f, 0.52f, 0.22f}, {0.85f, 0.30f, 0.30f},
                                            {0.90f, 0.72f, 0.25f}, {0.75f, 0.38f, 0.55f}};
  return palette[b % 4];
}

SurfacePass::SurfacePass() : m_lit(kLitVs, kLitFs, "surface"), m_shadow(kShadowVs, kShadowFs, "shadow") {}

void SurfacePass::update(const Model& model, const State& state, ColorMapKind map, const ColorScale& scale,
                         const std::vector<std::vector<double>>& vertex_values) {
  std::vector<size_t> counts;
  for (const Body& body : model.bodies) counts.push_back(body.rest_surface.triangles.size());
  if (m_model != &model || counts != m_triangle_counts) {
    m_bodies.clear();
    for (const Body& body : model.bodies) {
      m_bodies.push_back(std::make_unique<GlVertexArray>(std::vector<int>{3, 3, 3}));
      std::vector<uint32_t> indices;
      for (const auto& t : body.rest_surface.triangles) indices.insert(indices.end(), t.begin(), t.end());
      m_bodies.back()->set_indices(indices);
    }
    m_model = &model;
    m_triangle_counts = counts;
  }
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const std::vector<Vec3>& points = state.surface[b];
    smooth_normals(points, model.bodies[b].rest_surface.triangles, m_normals);
    const bool mapped = b < vertex_values.size() && !vertex_values[b].empty();
    m_vertices.resize(9 * points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3f c = mapped ? map_color(map, scale, vertex_values[b][i]) : body_color(b);
      float* v = &m_vertices[9 * i];
      for (int k = 0; k < 3; ++k) v[k] = float(points[i][k]), v[3 + k] = m_normals[i][k], v[6 + k] = c[k];
    }
    m_bodies[b]->set_vertices(m_vertices);
  }
}

void SurfacePass::draw_shadows(const ViewSetup& view) {
  if (view.light.dot(view.ground.normal.cast<float>()) <= 0.05f) return;  // light at the horizon
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(-1, -1);  // in front of the ground it lies on
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_EQUAL, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
  m_shadow.use();
  m_shadow.set("view_projection", view.view_projection);
  m_shadow.set("plane_point", Eigen::Vector3f(view.ground.point.cast<float>()));
  m_shadow.set("plane_normal", Eigen::Vector3f(view.ground.normal.cast<float>()));
  m_shadow.set("light", view.light);
  m_shadow.set("alpha", kShadowAlpha);
  for (const auto& body : m_bodies) body->draw(GL_TRIANGLES);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDepthMask(GL_TRUE);
}

void SurfacePass::draw_surfaces(const ViewSetup& view) {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  m_lit.use();
  m_lit.set("view_projection", view.view_projection);
  m_lit.set("light", view.light);
  m_lit.set("ambient", kAmbient);
  for (const auto& body : m_bodies) body->draw(GL_TRIANGLES);
}

}  // namespace sinew
