#include "host/view/view_backend.hpp"

#include <cstdlib>

#include "host/modules/module_loader.hpp"

namespace hmp::view {

std::unique_ptr<ViewWindow> open_view(const ViewSetup& setup, std::string& error) {
  // Without a display server there is nothing to open: say so without loading SDL at all.
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((x11 == nullptr || *x11 == '\0') && (wayland == nullptr || *wayland == '\0')) {
    error = "no display (DISPLAY and WAYLAND_DISPLAY are unset)";
    return nullptr;
  }
  std::string why;
  const ViewBackend* backend = modules::backend<ViewBackend>(&why);
  if (backend == nullptr) {
    error = "the view module is not available (" + why + ")";
    return nullptr;
  }
  return backend->open(setup, error);
}

std::unique_ptr<OffscreenFrames> open_offscreen(const ViewSetup& setup, std::string& error) {
  std::string why;
  const ViewBackend* backend = modules::backend<ViewBackend>(&why);
  if (backend == nullptr) {
    error = "the view module is not available (" + why + ")";
    return nullptr;
  }
  return backend->open_offscreen(setup, error);
}

}  // namespace hmp::view
