// The view module's entry (hmp-view.so): the ViewBackend over SDL2 and OpenGL.
#include "host/modules/module_loader.hpp"
#include "host/view/gl/gl_window.hpp"
#include "host/view/view_backend.hpp"

namespace hmp::view::gl {
namespace {

class SdlGlBackend final : public ViewBackend {
 public:
  std::unique_ptr<ViewWindow> open(const ViewSetup& setup, std::string& error) const override {
    return SdlGlWindow::open(setup, error);
  }
};

}  // namespace
}  // namespace hmp::view::gl

HMP_DEFINE_MODULE(hmp::view::ViewBackend, hmp::view::gl::SdlGlBackend)
