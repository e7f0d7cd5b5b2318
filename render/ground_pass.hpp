#pragma once
// The background gradient and the ground: a square around the scene on the ground plane
// with a grid (minor lines every `spacing`, major every 5), fading into the background
// towards its edge so there is no hard horizon. Marks its pixels with stencil value 1 so
// that the shadow lands only on the ground.
#include <memory>

#include "render/gl_program.hpp"
#include "render/gl_vertex_array.hpp"
#include "render/view_setup.hpp"

namespace sinew {

// A round grid spacing (1, 2 or 5 times a power of ten) near radius / 4.
double grid_spacing(double scene_radius);

class GroundPass {
 public:
  GroundPass();
  void draw_background();
  void draw_ground(const ViewSetup& view);

 private:
  GlProgram m_background, m_ground;
  GlVertexArray m_empty, m_quad;
};

}  // namespace sinew
