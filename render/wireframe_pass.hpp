#pragma once
// The simulation lattice as lines (every hex edge once, at the current node positions).
// Edges in front of the surfaces are drawn dark, edges behind them faint, so the lattice
// reads through the skin without hiding it.
#include <vector>

#include "engine/model.hpp"
#include "engine/state.hpp"
#include "render/gl_program.hpp"
#include "render/gl_vertex_array.hpp"
#include "render/view_setup.hpp"

namespace sinew {

// Unique node pairs joined by a hex edge: (a, b) with a < b, each once, sorted.
std::vector<std::array<int, 2>> lattice_edges(const Model& model);

class WireframePass {
 public:
  WireframePass();
  void update(const Model& model, const State& state);
  void draw(const ViewSetup& view);

 private:
  GlProgram m_program;
  GlVertexArray m_lines;
  const Model* m_model = nullptr;
  int m_num_elements = -1;
  std::vector<float> m_positions;  // scratch
};

}  // namespace sinew
