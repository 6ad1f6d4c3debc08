// The view module's entry (hmp-view.so): the ViewBackend over SDL2 and OpenGL, and EGL for off-screen frames.
#include "host/modules/module_loader.hpp"
#include "host/view/gl/gl_window.hpp"
#include "host/view/gl/offscreen_frames.hpp"
#include "host/view/view_backend.hpp"

namespace hmp::view::gl {
namespace {

class SdlGlBackend final : public ViewBackend {
 public:
  std::unique_ptr<ViewWindow> open(const ViewSetup& setup, std::string& error) const override {
    return SdlGlWindow::open(setup, error);
  }
  std::unique_ptr<OffscreenFrames> open_offscreen(const ViewSetup& setup, std::string& error) const override {
    return EglOffscreenFrames::open(setup, error);
  }
};

}  // namespace
}  // namespace hmp::view::gl

HMP_DEFINE_MODULE(hmp::view::ViewBackend, hmp::view::gl::SdlGlBackend)
