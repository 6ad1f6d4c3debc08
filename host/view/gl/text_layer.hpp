#pragma once
// Text over the animation (overlay line, legend, help): each line rasterised by cairo into a texture of
// its own size, kept while the line stays the same and blended over the frame as one quad. Only a line
// that changed costs CPU (the overlay's clock, ten times a second: a few hundred pixels wide), so the
// text does not weigh on a frame's time.
#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "host/view/roll_layout.hpp"

namespace hmp::view::gl {

struct TextItem {
  float x = 0, y = 0;  // the text's top left, pixels
  float size_px = 13;
  Rgb colour{1, 1, 1};
  std::string text;     // UTF-8, one line
  float max_width = 0;  // pixels: the line is cut there (0: never)
  friend bool operator==(const TextItem&, const TextItem&) = default;
};

class TextLayer {
 public:
  TextLayer();  // needs a current OpenGL 3.3 core context
  ~TextLayer();
  TextLayer(const TextLayer&) = delete;
  TextLayer& operator=(const TextLayer&) = delete;

  bool ok() const { return program_ != 0; }
  // The text of the next draw(): lines not drawn in the last frame are rasterised (on the CPU) now.
  void prepare(int width_px, int height_px, const std::vector<TextItem>& items);
  // Draws the prepared text over what is in the frame buffer (alpha blended).
  void draw();

 private:
  // A rasterised line: its texture and size in pixels.
  struct Line {
    unsigned texture = 0;
    int width = 0, height = 0;
    bool used = false;
  };
  using Key = std::tuple<std::string, float, float, float, float, float>;  // text, size, colour, max width
  Line rasterise(const TextItem& item);

  unsigned program_ = 0, vao_ = 0;
  int rect_uniform_ = -1, screen_uniform_ = -1;
  int width_ = 0, height_ = 0;
  std::map<Key, Line> lines_;
  struct Placed {
    float x, y;
    const Line* line;
  };
  std::vector<Placed> placed_;
};

}  // namespace hmp::view::gl
