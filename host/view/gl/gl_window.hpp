#pragma once
// host/view/gl/: the view module (hmp-view.so): the music animation drawn with SDL2 and OpenGL 3.3 core
// (libepoxy loads the GL functions; Mesa's llvmpipe draws where there is no GPU). What it draws comes from
// host/view/ (note_index, roll_layout); this folder only puts it on the screen.
#include <memory>
#include <string>
#include <vector>

#include "host/view/gl/frame_painter.hpp"
#include "host/view/view_backend.hpp"

struct SDL_Window;

namespace hmp::view::gl {

class SdlGlWindow final : public ViewWindow {
 public:
  // Null and `error` set when SDL has no video, the window or an OpenGL 3.3 core context cannot be had.
  static std::unique_ptr<SdlGlWindow> open(const ViewSetup& setup, std::string& error);
  ~SdlGlWindow() override;
  SdlGlWindow(const SdlGlWindow&) = delete;
  SdlGlWindow& operator=(const SdlGlWindow&) = delete;

  bool frame(const FrameState& state, std::vector<ViewEvent>& events) override;
  bool poll(std::vector<ViewEvent>& events) override;
  bool read_pixels(std::vector<std::uint8_t>& rgb, int& width, int& height) override;
  std::string renderer() const override { return renderer_name_; }
  FrameCost last_cost() const override { return cost_; }
  void size(int& width_px, int& height_px, float& scale) const override;

 private:
  SdlGlWindow(const ViewSetup& setup, SDL_Window* window, void* context);

  ViewSetup setup_;
  SDL_Window* window_;
  void* context_;  // SDL_GLContext
  std::unique_ptr<FramePainter> painter_;
  std::string renderer_name_;
  std::vector<std::uint8_t> pixels_;
  int pixels_w_ = 0, pixels_h_ = 0;
  FrameCost cost_;
  bool open_ = true;
  bool fullscreen_ = false;
};

}  // namespace hmp::view::gl
