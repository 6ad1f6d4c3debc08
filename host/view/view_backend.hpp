#pragma once
// The view module's interface (module "view", host/view/gl/): an SDL2 window drawing the music animation
// with OpenGL 3.3 core. The rest of hmp hands it the song once and, each frame, the song time and the
// player's state; it hands back what the user did in the window. No SDL or GL type crosses, and no
// exception (host/modules/module_loader.hpp).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/midi/song.hpp"
#include "host/view/note_index.hpp"

namespace hmp::view {

struct ViewSetup {
  const midi::Song* song = nullptr;  // outlives the window
  std::string title = "hmp";
  int width = 1280, height = 720;  // logical size (HiDPI screens get more pixels)
  bool fullscreen = false;
  bool hidden = false;                      // tests: draw without showing
  bool capture = false;                     // keep every frame's pixels for read_pixels (tests, screenshots)
  bool vsync = true;                        // wait for the display's refresh (off: as fast as it draws)
  std::optional<std::pair<int, int>> keys;  // the roll's lowest and highest key (default: the song's, with room)
  bool draw_everything = false;             // the view-frame benchmark's comparison: every note of the song sent and
                                            // drawn each frame, as players that do not index their notes do
};

// What the last frame cost (the view-frame benchmark): the CPU time of this thread to work out the frame
// (visible notes, layout, instances, text), of the whole frame() call (plus the GL driver's work on this
// thread), and the wall time from the call to the end of the buffer swap.
struct FrameCost {
  double prepare_cpu_ms = 0, frame_cpu_ms = 0, wall_ms = 0;
  std::size_t instances = 0;
};

// One row of the legend (top right): a track's name, instrument, and whether it is the haptic track or hidden.
struct LegendEntry {
  std::uint32_t track = 0;
  std::string label;  // "2 Flute (Flute)"
  bool haptic = false;
  bool hidden = false;  // its bars are not drawn (clicked off in the legend)
};

// What one frame shows.
struct FrameState {
  std::int64_t song_us = 0;  // the song time this frame shows (when it reaches the screen)
  std::int64_t end_us = 0;   // the song's (or the passage's) end: the progress bar's right edge
  std::uint32_t haptic_track = 0;
  float depth_blend = 1.0f;           // 0 → 1 after a switch of the haptic track: layers glide to their new depth
  std::uint32_t previous_haptic = 0;  // the haptic track before that switch
  bool paused = false;
  double seconds_across = 12.0;     // zoom
  std::string overlay;              // the line at the top: time, track, envelope, mapping, device, late/stolen
  std::vector<LegendEntry> legend;  // one row each, top down (tracks without notes are not listed)
  std::vector<std::string> help;    // lines of the help box (the h key); empty: none
  bool cursor = false;              // the touch cursor (grip or mouse) at (cursor_x, cursor_y) window pixels
  float cursor_x = 0, cursor_y = 0;
  bool cursor_pressing = false;  // pushing in (button held / grip pushed into a bar)
  std::vector<Bar> played;       // notes that are not the song's (`hmp live`'s input), drawn over its tracks
  float vibration[256] = {};     // the strip under the roll: the device's output over the last frames
  int vibration_samples = 0;
};

// What the user did since the last frame.
struct ViewEvent {
  enum class Kind { quit, key, press, release, cursor } kind = Kind::key;
  char key = 0;        // Kind::key: ' ', 'q', 't', 'T', 'e', 'm', '+', '-', '[', ']', 'f', 'h',
                       // '<' / '>' for the arrow keys
  float x = 0, y = 0;  // Kind::press / release / cursor: window pixels, origin top left
};

class ViewWindow {
 public:
  virtual ~ViewWindow() = default;
  // Draws one frame and collects the window's events; false once the window is gone (closed).
  virtual bool frame(const FrameState& state, std::vector<ViewEvent>& events) = 0;
  // Collects the window's events without drawing (between frames); false once the window is gone.
  virtual bool poll(std::vector<ViewEvent>& events) = 0;
  // The last frame's pixels, RGB, rows from the top (tests, screenshots).
  virtual bool read_pixels(std::vector<std::uint8_t>& rgb, int& width, int& height) = 0;
  virtual FrameCost last_cost() const = 0;
  virtual std::string renderer() const = 0;  // the GL renderer's name ("llvmpipe (LLVM 15.0.6, 256 bits)")
  // The drawable's size in pixels (more than the logical size on HiDPI screens), and pixels per logical
  // pixel: events come in logical pixels, layouts are in drawable pixels.
  virtual void size(int& width_px, int& height_px, float& scale) const = 0;
};

// Frames drawn without a window (the video export, host/video/): OpenGL through EGL on Mesa's surfaceless
// platform, so no display server is needed. The same painter as the window's draws them.
class OffscreenFrames {
 public:
  virtual ~OffscreenFrames() = default;
  // Draws `state` at the setup's size (scale 1) and returns its pixels: RGBA, width × 4 bytes a row, rows
  // from the BOTTOM up (OpenGL's order; the encoder flips for free). Valid until the next call or the end.
  // Call from one thread at a time; the context follows the calling thread.
  virtual const std::uint8_t* draw(const FrameState& state) = 0;
  virtual FrameCost last_cost() const = 0;
  virtual std::string renderer() const = 0;
};

class ViewBackend {
 public:
  static constexpr const char* kModule = "view";
  static constexpr int kAbi = 4;
  // A window, or null and `error` says why (no display, no OpenGL 3.3, …) in one line.
  virtual std::unique_ptr<ViewWindow> open(const ViewSetup& setup, std::string& error) const = 0;
  // Off-screen frames of setup.width × setup.height pixels, or null and `error` in one line.
  virtual std::unique_ptr<OffscreenFrames> open_offscreen(const ViewSetup& setup, std::string& error) const = 0;

 protected:
  ~ViewBackend() = default;  // one static object in the module, never deleted through this
};

// Opens the window through the view module (loaded on first use). Null and `error` when it cannot be had:
// the caller warns once and goes on without it.
std::unique_ptr<ViewWindow> open_view(const ViewSetup& setup, std::string& error);

// Off-screen frames through the view module (no display needed). Null and `error` when they cannot be had.
std::unique_ptr<OffscreenFrames> open_offscreen(const ViewSetup& setup, std::string& error);

}  // namespace hmp::view
