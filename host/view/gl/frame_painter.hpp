#pragma once
// One frame of the animation drawn into whatever OpenGL frame buffer is bound: the window's (gl_window)
// or an off-screen one for the video export (offscreen_frames). Both draw through this one painter, so a
// video frame shows exactly what the window would at the same song time and size.
#include <memory>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "host/view/gl/roll_renderer.hpp"
#include "host/view/note_index.hpp"
#include "host/view/roll_layout.hpp"
#include "host/view/view_backend.hpp"

namespace hmp::view::gl {

class TextLayer;

class FramePainter {
 public:
  // Needs a current OpenGL 3.3 core context; `song` outlives the painter.
  FramePainter(const midi::Song& song, bool draw_everything, std::optional<std::pair<int, int>> keys);
  ~FramePainter();
  FramePainter(const FramePainter&) = delete;
  FramePainter& operator=(const FramePainter&) = delete;

  bool ok() const;
  std::string error() const;
  // Draws `state` into a width × height pixel frame buffer; `scale` is pixels per logical pixel. Fills
  // the CPU part of `cost` (prepare_cpu_ms, instances).
  void paint(const FrameState& state, int width_px, int height_px, float scale, FrameCost& cost);

 private:
  bool draw_everything_;
  NoteIndex index_;
  LayoutParams layout_params_;
  std::unique_ptr<RollRenderer> renderer_;
  std::unique_ptr<TextLayer> text_;
  std::vector<Bar> visible_;
  std::vector<Instance> instances_;  // this frame's rectangles (kept: no allocation per frame)
  std::vector<std::uint32_t> order_;
};

}  // namespace hmp::view::gl
