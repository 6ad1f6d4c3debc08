#include "host/view/gl/roll_renderer.hpp"

#include <epoxy/gl.h>

#include <cstddef>

#include "host/view/gl/shader.hpp"

namespace hmp::view::gl {
namespace {

// The unit quad is made from gl_VertexID (a triangle strip of 4): no vertex buffer for it. Each instance's
// rectangle is in window pixels, origin top left; the shader maps it to clip space.
constexpr const char* kVertex = R"(#version 330 core
layout(location = 0) in vec4 rect;    // x0, y0, x1, y1 (pixels)
layout(location = 1) in vec3 colour;
uniform vec2 screen;                  // pixels
out vec3 v_colour;
void main() {
  vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1);
  vec2 p = mix(rect.xy, rect.zw, corner);
  gl_Position = vec4(p.x / screen.x * 2.0 - 1.0, 1.0 - p.y / screen.y * 2.0, 0.0, 1.0);
  v_colour = colour;
}
)";
constexpr const char* kFragment = R"(#version 330 core
in vec3 v_colour;
out vec4 out_colour;
void main() { out_colour = vec4(v_colour, 1.0); }
)";

}  // namespace

RollRenderer::RollRenderer() {
  const unsigned program = link_program(kVertex, kFragment, error_);
  if (program == 0) return;
  program_ = program;
  screen_uniform_ = glGetUniformLocation(program_, "screen");
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &vbo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  const auto stride = static_cast<GLsizei>(sizeof(Instance));
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(Instance, rect)));
  glVertexAttribDivisor(0, 1);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(Instance, colour)));
  glVertexAttribDivisor(1, 1);
  glBindVertexArray(0);
}

RollRenderer::~RollRenderer() {
  if (vbo_ != 0) glDeleteBuffers(1, &vbo_);
  if (vao_ != 0) glDeleteVertexArrays(1, &vao_);
  if (program_ != 0) glDeleteProgram(program_);
}

void RollRenderer::draw(int width_px, int height_px, const std::vector<Instance>& instances) {
  glViewport(0, 0, width_px, height_px);
  glClearColor(kBackground.r, kBackground.g, kBackground.b, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (!ok() || instances.empty()) return;
  glUseProgram(program_);
  glUniform2f(screen_uniform_, static_cast<float>(width_px), static_cast<float>(height_px));
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  // Orphan and refill: this frame's instances only (the visible window), never the whole song.
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(instances.size() * sizeof(Instance)), instances.data(),
               GL_STREAM_DRAW);
  glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(instances.size()));
  glBindVertexArray(0);
}

}  // namespace hmp::view::gl
