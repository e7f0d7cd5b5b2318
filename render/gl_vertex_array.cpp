#include "render/gl_vertex_array.hpp"

#include <cstddef>

namespace sinew {

GlVertexArray::GlVertexArray(std::vector<int> attribute_sizes) {
  for (int s : attribute_sizes) m_stride += s;
  glGenVertexArrays(1, &m_vao);
  glGenBuffers(1, &m_vbo);
  glBindVertexArray(m_vao);
  glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < attribute_sizes.size(); ++i) {
    glEnableVertexAttribArray(static_cast<GLuint>(i));
    glVertexAttribPointer(static_cast<GLuint>(i), attribute_sizes[i], GL_FLOAT, GL_FALSE,
                          m_stride * sizeof(float), reinterpret_cast<const void*>(offset * sizeof(float)));
    offset += attribute_sizes[i];
  }
  glBindVertexArray(0);
}

GlVertexArray::~GlVertexArray() {
  glDeleteBuffers(1, &m_vbo);
  if (m_ebo) glDeleteBuffers(1, &m_ebo);
  glDeleteVertexArrays(1, &m_vao);
}

void GlVertexArray::set_vertices(const std::vector<float>& data) {
  glBindBuffer(GL_ARRAY_BUFFER, m_vbo);
  // Re-specifying the store lets the driver hand out fresh memory instead of waiting
  // for draws that still read the old contents.
  glBufferData(GL_ARRAY_BUFFER, data.size() * sizeof(float), data.data(), GL_STREAM_DRAW);
  m_vertex_count = static_cast<GLsizei>(data.size() / m_stride);
}

void GlVertexArray::set_indices(const std::vector<uint32_t>& indices) {
  glBindVertexArray(m_vao);
  if (!m_ebo) glGenBuffers(1, &m_ebo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_ebo);  // recorded in the VAO
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(uint32_t), indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  m_index_count = static_cast<GLsizei>(indices.size());
}

void GlVertexArray::draw(GLenum mode) const {
  glBindVertexArray(m_vao);
  if (m_ebo) glDrawElements(mode, m_index_count, GL_UNSIGNED_INT, nullptr);
  else glDrawArrays(mode, 0, m_vertex_count);
  glBindVertexArray(0);
}

void GlVertexArray::draw_generated(GLenum mode, GLsizei count) const {
  glBindVertexArray(m_vao);  // the core profile draws nothing without a bound vertex array
  glDrawArrays(mode, 0, count);
  glBindVertexArray(0);
}

}  // namespace sinew
