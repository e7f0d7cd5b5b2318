#pragma once
// A linked GLSL program with uniform setters by name (locations cached).
#include <Eigen/Core>
#include <map>
#include <string>

#include "render/gl.hpp"

namespace sinew {

class GlProgram {
 public:
  // Throws RenderError with the compiler or linker log, naming `name`.
  GlProgram(const char* vertex_source, const char* fragment_source, const std::string& name);
  ~GlProgram();
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;

  void use() const;
  void set(const char* uniform, float value);
  void set(const char* uniform, const Eigen::Vector2f& value);
  void set(const char* uniform, const Eigen::Vector3f& value);
  void set(const char* uniform, const Eigen::Vector4f& value);
  void set(const char* uniform, const Eigen::Matrix4f& value);

 private:
  GLint location(const char* uniform);
  GLuint m_program = 0;
  std::string m_name;
  std::map<std::string, GLint> m_locations;
};

}  // namespace sinew
