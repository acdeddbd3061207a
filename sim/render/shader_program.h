#pragma once

#include <string_view>

namespace incise::render {

// A linked GLSL vertex + fragment program. Needs a current EglContext for its whole life.
class ShaderProgram {
 public:
  // Throws RenderError carrying the compiler or linker log if either stage fails.
  ShaderProgram(std::string_view vertex_source, std::string_view fragment_source);
  ~ShaderProgram();
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  void use() const;
  // Location of an active uniform; throws RenderError if the program has no such uniform, which
  // catches a misspelt name or a uniform the compiler removed as unused.
  int uniform_location(const char* name) const;

 private:
  unsigned int program_ = 0;  // GL object name
};

}  // namespace incise::render
