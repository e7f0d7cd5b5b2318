#pragma once
// The bodies' embedded surfaces: smooth normals recomputed each frame, Lambert + ambient
// lighting, a body colour or a per-vertex colour map; and their planar projected shadow.
//
// Shadow: each surface is drawn a second time flattened onto the ground plane along the
// light direction, in translucent black. The stencil (ground = 1, see GroundPass) limits it
// to ground pixels and is incremented where it lands, so overlapping triangles darken a pixel
// only once. Exact for a flat ground and a directional light, which is all the scene has;
// no shadow-map resolution or bias to tune.
#include <memory>
#include <vector>

#include "engine/model.hpp"
#include "engine/state.hpp"
#include "render/color_map.hpp"
#include "render/gl_program.hpp"
#include "render/gl_vertex_array.hpp"
#include "render/view_setup.hpp"

namespace sinew {

// Body b's colour when no colour map is shown (warm tones, distinct per body).
Eigen::Vector3f body_color(size_t b);

class SurfacePass {
 public:
  SurfacePass();
  // Uploads this frame's surfaces. `vertex_values[b]` (one per surface vertex) is coloured
  // with `map` on `scale`; empty: the body colour.
  void update(const Model& model, const State& state, ColorMapKind map, const ColorScale& scale,
              const std::vector<std::vector<double>>& vertex_values);
  void draw_shadows(const ViewSetup& view);
  void draw_surfaces(const ViewSetup& view);

 private:
  GlProgram m_lit, m_shadow;
  // Whose index buffers are loaded; the counts guard against a new model at a reused address.
  const Model* m_model = nullptr;
  std::vector<size_t> m_triangle_counts;
  std::vector<std::unique_ptr<GlVertexArray>> m_bodies;
  std::vector<Eigen::Vector3f> m_normals;  // scratch
  std::vector<float> m_vertices;           // scratch
};

}  // namespace sinew
