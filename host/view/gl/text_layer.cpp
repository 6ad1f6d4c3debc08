#include "host/view/gl/text_layer.hpp"

#include <cairo.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

#include "host/view/gl/shader.hpp"

namespace hmp::view::gl {
namespace {

// One quad per line from gl_VertexID, placed in window pixels; texture row 0 is the line's top row
// (cairo's order).
constexpr const char* kVertex = R"(#version 330 core
uniform vec4 rect;     // x0, y0, x1, y1 (pixels)
uniform vec2 screen;   // pixels
out vec2 uv;
void main() {
  vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1);
  vec2 p = mix(rect.xy, rect.zw, corner);
  gl_Position = vec4(p.x / screen.x * 2.0 - 1.0, 1.0 - p.y / screen.y * 2.0, 0.0, 1.0);
  uv = corner;
}
)";
// cairo's pixels are premultiplied by alpha: blended with (1, 1 − α).
constexpr const char* kFragment = R"(#version 330 core
in vec2 uv;
uniform sampler2D text;
out vec4 out_colour;
void main() { out_colour = texture(text, uv); }
)";

void set_font(cairo_t* cr, float size_px) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, static_cast<double>(size_px));
}

}  // namespace

TextLayer::TextLayer() {
  std::string error;
  program_ = link_program(kVertex, kFragment, error);
  if (program_ == 0) return;
  rect_uniform_ = glGetUniformLocation(program_, "rect");
  screen_uniform_ = glGetUniformLocation(program_, "screen");
  glGenVertexArrays(1, &vao_);
}

TextLayer::~TextLayer() {
  for (auto& [key, line] : lines_) glDeleteTextures(1, &line.texture);
  if (vao_ != 0) glDeleteVertexArrays(1, &vao_);
  if (program_ != 0) glDeleteProgram(program_);
}

TextLayer::Line TextLayer::rasterise(const TextItem& item) {
  // Measure on a scratch surface, then draw on one of the line's size.
  cairo_surface_t* scratch = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 1, 1);
  cairo_t* m = cairo_create(scratch);
  set_font(m, item.size_px);
  cairo_font_extents_t fe;
  cairo_font_extents(m, &fe);
  cairo_text_extents_t te;
  cairo_text_extents(m, item.text.c_str(), &te);
  cairo_destroy(m);
  cairo_surface_destroy(scratch);
  Line line;
  line.width = std::max(1, static_cast<int>(std::ceil(te.x_advance + 2)));
  if (item.max_width > 0) line.width = std::min(line.width, std::max(1, static_cast<int>(item.max_width)));
  line.height = std::max(1, static_cast<int>(std::ceil(fe.height + 1)));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, line.width, line.height);
  cairo_t* cr = cairo_create(surface);
  set_font(cr, item.size_px);
  cairo_set_source_rgb(cr, static_cast<double>(item.colour.r), static_cast<double>(item.colour.g),
                       static_cast<double>(item.colour.b));
  cairo_move_to(cr, 0.0, fe.ascent);
  cairo_show_text(cr, item.text.c_str());
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  glGenTextures(1, &line.texture);
  glBindTexture(GL_TEXTURE_2D, line.texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, cairo_image_surface_get_stride(surface) / 4);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  // cairo's ARGB32 is a native-endian 32-bit word: B, G, R, A in memory on the little-endian machines we
  // build for.
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, line.width, line.height, 0, GL_BGRA, GL_UNSIGNED_BYTE,
               cairo_image_surface_get_data(surface));
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  cairo_surface_destroy(surface);
  return line;
}

void TextLayer::prepare(int width_px, int height_px, const std::vector<TextItem>& items) {
  placed_.clear();
  width_ = width_px;
  height_ = height_px;
  if (!ok()) return;
  for (auto& [key, line] : lines_) line.used = false;
  for (const TextItem& item : items) {
    if (item.text.empty()) continue;
    const Key key{item.text, item.size_px, item.colour.r, item.colour.g, item.colour.b, item.max_width};
    auto it = lines_.find(key);
    if (it == lines_.end()) it = lines_.emplace(key, rasterise(item)).first;
    it->second.used = true;
    placed_.push_back({std::round(item.x), std::round(item.y), &it->second});
  }
  // Lines not shown this frame go (the overlay's old clock readings).
  for (auto it = lines_.begin(); it != lines_.end();) {
    if (it->second.used) {
      ++it;
    } else {
      glDeleteTextures(1, &it->second.texture);
      it = lines_.erase(it);
    }
  }
}

void TextLayer::draw() {
  if (placed_.empty()) return;
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glUseProgram(program_);
  glUniform2f(screen_uniform_, static_cast<float>(width_), static_cast<float>(height_));
  glActiveTexture(GL_TEXTURE0);
  glUniform1i(glGetUniformLocation(program_, "text"), 0);
  glBindVertexArray(vao_);
  for (const Placed& p : placed_) {
    glBindTexture(GL_TEXTURE_2D, p.line->texture);
    glUniform4f(rect_uniform_, p.x, p.y, p.x + static_cast<float>(p.line->width),
                p.y + static_cast<float>(p.line->height));
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

}  // namespace hmp::view::gl
