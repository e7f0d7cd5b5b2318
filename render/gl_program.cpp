#include "render/gl_program.hpp"

#include "render/render_error.hpp"

namespace sinew {
namespace {

GLuint compile(GLenum type, const char* source, const std::string& name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return shader;
  char log[4096] = {};
  glGetShaderInfoLog(shader, sizeof log, nullptr, log);
  glDeleteShader(shader);
  throw RenderError("shader '" + name + "' (" + (type == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                    ") does not compile:\n" + log);
}

}  // namespace

GlProgram::GlProgram(const char* vertex_source, const char* fragment_source, const std::string& name)
    : m_name(name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source, name);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, fragment_source, name);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  m_program = glCreateProgram();
  glAttachShader(m_program, vs);
  glAttachShader(m_program, fs);
  glLinkProgram(m_program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(m_program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetProgramInfoLog(m_program, sizeof log, nullptr, log);
    glDeleteProgram(m_program);
    throw RenderError("shader program '" + name + "' does not link:\n" + log);
  }
}

GlProgram::~GlProgram() { glDeleteProgram(m_program); }

void GlProgram::use() const { glUseProgram(m_program); }

GLint GlProgram::location(const char* uniform) {
  auto it = m_locations.find(uniform);
  if (it == m_locations.end()) it = m_locations.emplace(uniform, glGetUniformLocation(m_program, uniform)).first;
  return it->second;  // -1 (ignored by glUniform*) if the compiler removed an unused uniform
}

void GlProgram::set(const char* uniform, float value) { glUniform1f(location(uniform), value); }
void GlProgram::set(const char* uniform, const Eigen::Vector2f& v) { glUniform2fv(location(uniform), 1, v.data()); }
void GlProgram::set(const char* uniform, const Eigen::Vector3f& v) { glUniform3fv(location(uniform), 1, v.data()); }
void GlProgram::set(const char* uniform, const Eigen::Vector4f& v) { glUniform4fv(location(uniform), 1, v.data()); }
void GlProgram::set(const char* uniform, const Eigen::Matrix4f& m) {
  glUniformMatrix4fv(location(uniform), 1, GL_FALSE, m.data());  // Eigen is column-major, like GL
}

}  // namespace sinew
