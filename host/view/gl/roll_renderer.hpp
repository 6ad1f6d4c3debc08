#pragma once
// Draws coloured rectangles, many at once: one instanced draw of a unit quad, each instance a rectangle in
// window pixels and its colour. Bars, the centre line and the vibration strip are all rectangles.
#include <vector>

#include "host/view/roll_layout.hpp"

namespace hmp::view::gl {

struct Instance {
  Rect rect;
  Rgb colour;
};

class RollRenderer {
 public:
  RollRenderer();  // needs a current OpenGL 3.3 core context
  ~RollRenderer();
  RollRenderer(const RollRenderer&) = delete;
  RollRenderer& operator=(const RollRenderer&) = delete;

  bool ok() const { return program_ != 0; }
  const std::string& error() const { return error_; }
  // Clears to the background and draws the instances in order (later ones on top).
  void draw(int width_px, int height_px, const std::vector<Instance>& instances);

 private:
  unsigned program_ = 0, vao_ = 0, vbo_ = 0;
  int screen_uniform_ = -1;
  std::string error_;
};

}  // namespace hmp::view::gl
