#pragma once
// Off-screen frames for the video export: an OpenGL 3.3 core context from EGL with no surface (Mesa's
// surfaceless platform: no display server, no window) drawing into a frame buffer object of the video's
// size, read back after each frame (RGBA). The drawing is
// FramePainter's, as in the window.
#include <memory>
#include <string>
#include <vector>

#include "host/view/gl/frame_painter.hpp"
#include "host/view/view_backend.hpp"

namespace hmp::view::gl {

class EglOffscreenFrames final : public OffscreenFrames {
 public:
  static std::unique_ptr<EglOffscreenFrames> open(const ViewSetup& setup, std::string& error);
  ~EglOffscreenFrames() override;
  EglOffscreenFrames(const EglOffscreenFrames&) = delete;
  EglOffscreenFrames& operator=(const EglOffscreenFrames&) = delete;

  const std::uint8_t* draw(const FrameState& state) override;
  FrameCost last_cost() const override { return cost_; }
  std::string renderer() const override { return renderer_name_; }

 private:
  EglOffscreenFrames(const ViewSetup& setup, void* display, void* context);
  void make_current() const;

  ViewSetup setup_;
  void* display_;  // EGLDisplay
  void* context_;  // EGLContext
  unsigned framebuffer_ = 0, colour_ = 0;
  bool complete_ = false;
  std::unique_ptr<FramePainter> painter_;
  std::string renderer_name_;
  std::vector<std::uint8_t> pixels_;
  FrameCost cost_;
};

}  // namespace hmp::view::gl
