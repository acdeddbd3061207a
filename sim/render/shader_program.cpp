#include "sim/render/shader_program.h"

#include <string>

#include "sim/render/gl_api.h"
#include "sim/render/render_error.h"

namespace incise::render {
namespace {

GLuint compile(GLenum stage, std::string_view source) {
  const GLuint shader = glCreateShader(stage);
  const GLchar* text = source.data();
  const GLint length = static_cast<GLint>(source.size());
  glShaderSource(shader, 1, &text, &length);
  glCompileShader(shader);
  GLint compiled = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
  if (compiled == GL_TRUE) return shader;

  GLint log_length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &log_length);
  std::string log(log_length > 0 ? log_length : 0, '\0');
  glGetShaderInfoLog(shader, log_length, nullptr, log.data());
  glDeleteShader(shader);
  const char* name = stage == GL_VERTEX_SHADER ? "vertex" : "fragment";
  throw RenderError(std::string(name) + " shader does not compile: " + log.c_str());
}

}  // namespace

ShaderProgram::ShaderProgram(std::string_view vertex_source, std::string_view fragment_source) {
  const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source);
  GLuint fragment = 0;
  try {
    fragment = compile(GL_FRAGMENT_SHADER, fragment_source);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  program_ = glCreateProgram();
  glAttachShader(program_, vertex);
  glAttachShader(program_, fragment);
  glLinkProgram(program_);
  // The linked program keeps what it needs; the shader objects are no longer used.
  glDeleteShader(vertex);
  glDeleteShader(fragment);

  GLint linked = GL_FALSE;
  glGetProgramiv(program_, GL_LINK_STATUS, &linked);
  if (linked != GL_TRUE) {
    GLint log_length = 0;
    glGetProgramiv(program_, GL_INFO_LOG_LENGTH, &log_length);
    std::string log(log_length > 0 ? log_length : 0, '\0');
    glGetProgramInfoLog(program_, log_length, nullptr, log.data());
    glDeleteProgram(program_);
    throw RenderError(std::string("shader program does not link: ") + log.c_str());
  }
}

ShaderProgram::~ShaderProgram() {
  glDeleteProgram(program_);
}

void ShaderProgram::use() const {
  glUseProgram(program_);
}

int ShaderProgram::uniform_location(const char* name) const {
  const GLint location = glGetUniformLocation(program_, name);
  if (location < 0) {
    throw RenderError(std::string("shader program has no active uniform '") + name + "'");
  }
  return location;
}

}  // namespace incise::render
