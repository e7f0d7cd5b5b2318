#include "render/wireframe_pass.hpp"

#include <algorithm>

namespace sinew {
namespace {

const char* kVs = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view_projection;
void main() { gl_Position = view_projection * vec4(position, 1.0); })";
const char* kFs = R"(#version 330 core
uniform vec4 tint;
out vec4 color;
void main() { color = tint; })";

}  // namespace

std::vector<std::array<int, 2>> lattice_edges(const Model& model) {
  std::vector<std::array<int, 2>> edges;
  edges.reserve(12 * model.element_nodes.size());
  for (const auto& nodes : model.element_nodes) {
    if (nodes[4] < 0) {  // a tet: all six pairs of its four nodes
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) edges.push_back({std::min(nodes[i], nodes[j]), std::max(nodes[i], nodes[j])});
      continue;
    }
    // Paper order: local node 4a + 2b + c sits at (a, b, c); an edge flips one of the bits.
    for (int local = 0; local < 8; ++local)
      for (int bit : {1, 2, 4})
        if (!(local & bit)) {
          const int a = nodes[local], b = nodes[local | bit];
          edges.push_back({std::min(a, b), std::max(a, b)});
        }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

WireframePass::WireframePass() : m_program(kVs, kFs, "wireframe"), m_lines({3}) {}

void WireframePass::update(const Model& model, const State& state) {
  if (m_model != &model || m_num_elements != model.num_elements) {
    std::vector<uint32_t> indices;
    for (const auto& e : lattice_edges(model)) indices.insert(indices.end(), {uint32_t(e[0]), uint32_t(e[1])});
    m_lines.set_indices(indices);
    m_model = &model;
    m_num_elements = model.num_elements;
  }
  m_positions.resize(state.x.size());
  for (Eigen::Index i = 0; i < state.x.size(); ++i) m_positions[i] = float(state.x[i]);
  m_lines.set_vertices(m_positions);
}

void WireframePass::draw(const ViewSetup& view) {
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  m_program.use();
  m_program.set("view_projection", view.view_projection);
  glDepthFunc(GL_GREATER);  // hidden part
  m_program.set("tint", Eigen::Vector4f(0.08f, 0.08f, 0.12f, 0.18f));
  m_lines.draw(GL_LINES);
  glDepthFunc(GL_LEQUAL);  // visible part
  m_program.set("tint", Eigen::Vector4f(0.08f, 0.08f, 0.12f, 0.85f));
  m_lines.draw(GL_LINES);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
}

}  // namespace sinew
