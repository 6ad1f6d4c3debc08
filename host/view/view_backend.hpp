#pragma once
// The view module's interface (module "view", host/view/gl/): an SDL2 window drawing the music animation
// with OpenGL 3.3 core. The rest of hmp hands it the song once and, each frame, the song time and the
// player's state; it hands back what the user did in the window. No SDL or GL type crosses, and no
// exception (host/modules/module_loader.hpp).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "host/midi/song.hpp"

namespace hmp::view {

struct ViewSetup {
  const midi::Song* song = nullptr;  // outlives the window
  std::string title = "hmp";
  int width = 1280, height = 720;    // logical size (HiDPI screens get more pixels)
  bool fullscreen = false;
  bool hidden = false;               // tests: draw without showing
  bool capture = false;              // keep every frame's pixels for read_pixels (tests, screenshots)
  bool vsync = true;                 // wait for the display's refresh (off: as fast as it draws)
};

// What one frame shows.
struct FrameState {
  std::int64_t song_us = 0;          // the song time this frame shows (when it reaches the screen)
  std::uint32_t haptic_track = 0;
  bool paused = false;
  double seconds_across = 12.0;      // zoom
  float vibration[256] = {};         // the strip under the roll: the device's output over the last frames
  int vibration_samples = 0;
};

// What the user did since the last frame.
struct ViewEvent {
  enum class Kind { quit, key, click, cursor } kind = Kind::key;
  char key = 0;                      // Kind::key: ' ', 'q', 't', 'T', 'e', 'm', '+', '-', '[', ']', 'f', 'h',
                                     // '<' / '>' for the arrow keys
  float x = 0, y = 0;                // Kind::click / cursor: window pixels, origin top left
};

class ViewWindow {
 public:
  virtual ~ViewWindow() = default;
  // Draws one frame and collects the window's events; false once the window is gone (closed).
  virtual bool frame(const FrameState& state, std::vector<ViewEvent>& events) = 0;
  // The last frame's pixels, RGB, rows from the top (tests, screenshots).
  virtual bool read_pixels(std::vector<std::uint8_t>& rgb, int& width, int& height) = 0;
  virtual std::string renderer() const = 0;  // the GL renderer's name ("llvmpipe (LLVM 15.0.6, 256 bits)")
};

class ViewBackend {
 public:
  static constexpr const char* kModule = "view";
  static constexpr int kAbi = 1;
  // A window, or null and `error` says why (no display, no OpenGL 3.3, …) in one line.
  virtual std::unique_ptr<ViewWindow> open(const ViewSetup& setup, std::string& error) const = 0;

 protected:
  ~ViewBackend() = default;  // one static object in the module, never deleted through this
};

// Opens the window through the view module (loaded on first use). Null and `error` when it cannot be had:
// the caller warns once and goes on without it.
std::unique_ptr<ViewWindow> open_view(const ViewSetup& setup, std::string& error);

}  // namespace hmp::view
