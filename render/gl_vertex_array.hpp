#pragma once
// A vertex array with one interleaved float buffer and an optional index buffer.
// Attribute i has sizes[i] floats; vertices are re-uploaded whole each frame.
#include <cstdint>
#include <vector>

#include "render/gl.hpp"

namespace sinew {

class GlVertexArray {
 public:
  explicit GlVertexArray(std::vector<int> attribute_sizes);
  ~GlVertexArray();
  GlVertexArray(const GlVertexArray&) = delete;
  GlVertexArray& operator=(const GlVertexArray&) = delete;

  int floats_per_vertex() const { return m_stride; }
  void set_vertices(const std::vector<float>& data);
  void set_indices(const std::vector<uint32_t>& indices);
  // Draws the indexed elements if indices were set, else all vertices.
  void draw(GLenum mode) const;
  // Draws `count` vertices that the shader makes up itself (gl_VertexID), ignoring the buffer.
  void draw_generated(GLenum mode, GLsizei count) const;

 private:
  GLuint m_vao = 0, m_vbo = 0, m_ebo = 0;
  int m_stride = 0;
  GLsizei m_vertex_count = 0, m_index_count = 0;
};

}  // namespace sinew
