#include "host/view/gl/shader.hpp"

#include <epoxy/gl.h>

namespace hmp::view::gl {
namespace {

unsigned compile(GLenum kind, const char* source, std::string& error) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[512] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    error = std::string("shader: ") + log;
    glDeleteShader(shader);
    return 0;
  }
  return shader;
}

}  // namespace

unsigned link_program(const char* vertex_source, const char* fragment_source, std::string& error) {
  const unsigned vs = compile(GL_VERTEX_SHADER, vertex_source, error);
  if (vs == 0) return 0;
  const unsigned fs = compile(GL_FRAGMENT_SHADER, fragment_source, error);
  if (fs == 0) {
    glDeleteShader(vs);
    return 0;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) {
    error = "shader program does not link";
    glDeleteProgram(program);
    return 0;
  }
  return program;
}

}  // namespace hmp::view::gl
