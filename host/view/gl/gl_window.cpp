#include "host/view/gl/gl_window.hpp"

#include <SDL.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>

#include "host/view/gl/roll_renderer.hpp"

namespace hmp::view::gl {
namespace {

constexpr Rgb kCentreLine{0.85f, 0.85f, 0.85f};
constexpr Rgb kStrip{0.0f, 114 / 255.0f, 178 / 255.0f};
constexpr float kStripHeight = 30.0f;

// SDL's video is initialised once per process and kept: windows come and go (tests open several).
bool video_up(std::string& error) {
  static bool up = false;
  if (up) return true;
  if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) {
    error = std::string("no video: ") + SDL_GetError();
    return false;
  }
  up = true;
  return true;
}

char key_of(SDL_Keycode k, Uint16 mod) {
  const bool shift = (mod & KMOD_SHIFT) != 0;
  switch (k) {
    case SDLK_SPACE: return ' ';
    case SDLK_LEFT: return '<';
    case SDLK_RIGHT: return '>';
    case SDLK_q: case SDLK_ESCAPE: return 'q';
    case SDLK_t: return shift ? 'T' : 't';
    case SDLK_e: return 'e';
    case SDLK_m: return 'm';
    case SDLK_f: return 'f';
    case SDLK_h: return 'h';
    case SDLK_PLUS: case SDLK_KP_PLUS: case SDLK_EQUALS: return '+';
    case SDLK_MINUS: case SDLK_KP_MINUS: return '-';
    case SDLK_LEFTBRACKET: return '[';
    case SDLK_RIGHTBRACKET: return ']';
    default: return 0;
  }
}

}  // namespace

std::unique_ptr<SdlGlWindow> SdlGlWindow::open(const ViewSetup& setup, std::string& error) {
  if (setup.song == nullptr) {
    error = "no song";
    return nullptr;
  }
  if (!video_up(error)) return nullptr;
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
  SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
  Uint32 flags = SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI;
  if (setup.hidden) flags |= SDL_WINDOW_HIDDEN;
  if (setup.fullscreen) flags |= SDL_WINDOW_FULLSCREEN_DESKTOP;
  SDL_Window* window = SDL_CreateWindow(setup.title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                        setup.width, setup.height, flags);
  if (window == nullptr) {
    error = std::string("cannot open a window: ") + SDL_GetError();
    return nullptr;
  }
  SDL_GLContext context = SDL_GL_CreateContext(window);
  if (context == nullptr) {
    error = std::string("no OpenGL 3.3 core context: ") + SDL_GetError();
    SDL_DestroyWindow(window);
    return nullptr;
  }
  if (epoxy_gl_version() < 33) {
    error = "OpenGL " + std::to_string(epoxy_gl_version() / 10) + "." + std::to_string(epoxy_gl_version() % 10) +
            " only (3.3 needed)";
    SDL_GL_DeleteContext(context);
    SDL_DestroyWindow(window);
    return nullptr;
  }
  SDL_GL_SetSwapInterval(setup.vsync ? 1 : 0);
  std::unique_ptr<SdlGlWindow> w(new SdlGlWindow(setup, window, context));
  if (!w->renderer_->ok()) {
    error = "OpenGL: " + w->renderer_->error();
    return nullptr;
  }
  return w;
}

SdlGlWindow::SdlGlWindow(const ViewSetup& setup, SDL_Window* window, void* context)
    : setup_(setup), window_(window), context_(context), index_(*setup.song), fullscreen_(setup.fullscreen) {
  const auto [lo, hi] = key_range(*setup.song);
  layout_params_.key_low = lo;
  layout_params_.key_high = hi;
  renderer_ = std::make_unique<RollRenderer>();
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  renderer_name_ = name != nullptr ? name : "?";
}

SdlGlWindow::~SdlGlWindow() {
  SDL_GL_MakeCurrent(window_, context_);
  renderer_.reset();
  SDL_GL_DeleteContext(context_);
  SDL_DestroyWindow(window_);
}

void SdlGlWindow::poll(std::vector<ViewEvent>& events) {
  SDL_Event e;
  while (SDL_PollEvent(&e) != 0) {
    switch (e.type) {
      case SDL_QUIT:
        events.push_back({ViewEvent::Kind::quit});
        open_ = false;
        break;
      case SDL_KEYDOWN:
        if (const char k = key_of(e.key.keysym.sym, e.key.keysym.mod); k != 0) {
          if (k == 'f') {
            fullscreen_ = !fullscreen_;
            SDL_SetWindowFullscreen(window_, fullscreen_ ? SDL_WINDOW_FULLSCREEN_DESKTOP : 0);
          }
          events.push_back({ViewEvent::Kind::key, k});
        }
        break;
      case SDL_MOUSEBUTTONDOWN:
        events.push_back({ViewEvent::Kind::click, 0, static_cast<float>(e.button.x), static_cast<float>(e.button.y)});
        break;
      case SDL_MOUSEMOTION:
        events.push_back({ViewEvent::Kind::cursor, 0, static_cast<float>(e.motion.x), static_cast<float>(e.motion.y)});
        break;
      default: break;
    }
  }
}

bool SdlGlWindow::frame(const FrameState& state, std::vector<ViewEvent>& events) {
  poll(events);
  if (!open_) return false;
  SDL_GL_MakeCurrent(window_, context_);
  int w = 0, h = 0;
  SDL_GL_GetDrawableSize(window_, &w, &h);  // pixels (more than the logical size on HiDPI screens)
  LayoutParams p = layout_params_;
  p.width_px = std::max(1, w);
  p.height_px = std::max(1, h);
  p.seconds_across = state.seconds_across;
  const auto tracks = static_cast<std::uint32_t>(index_.tracks());
  const RollLayout layout(p, tracks, state.haptic_track);

  // Back to front: the deepest layer first, the haptic track last (on top). Only the visible bars.
  std::vector<std::uint32_t> order(tracks);
  for (std::uint32_t t = 0; t < tracks; ++t) order[t] = t;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return layout.depth_of(a) > layout.depth_of(b); });
  std::vector<Instance> instances;
  const std::int64_t t0 = layout.window_begin_us(state.song_us), t1 = layout.window_end_us(state.song_us);
  for (const std::uint32_t t : order) {
    index_.visible(t, t0, t1, visible_);
    for (const Bar& b : visible_) instances.push_back({layout.bar_rect(b, state.song_us), layout.colour(b, state.song_us)});
  }
  // The present: a thin line at the centre.
  const float cx = static_cast<float>(p.width_px) * 0.5f;
  instances.push_back({{cx - 1.0f, 0.0f, cx + 1.0f, static_cast<float>(p.height_px) - kStripHeight}, kCentreLine});
  // The vibration the device plays now: a strip along the bottom, one column per sample.
  const int n = std::clamp(state.vibration_samples, 0, 256);
  const float base = static_cast<float>(p.height_px) - kStripHeight * 0.5f;
  for (int i = 0; i < n; ++i) {
    const float x0 = static_cast<float>(p.width_px) * static_cast<float>(i) / static_cast<float>(n);
    const float x1 = static_cast<float>(p.width_px) * static_cast<float>(i + 1) / static_cast<float>(n);
    const float v = std::clamp(state.vibration[i], -1.0f, 1.0f) * kStripHeight * 0.45f;
    instances.push_back({{x0, std::min(base, base - v), x1, std::max(base, base - v) + 1.0f}, kStrip});
  }
  renderer_->draw(p.width_px, p.height_px, instances);
  if (setup_.capture) {
    pixels_w_ = p.width_px;
    pixels_h_ = p.height_px;
    std::vector<std::uint8_t> flipped(static_cast<std::size_t>(pixels_w_) * pixels_h_ * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, pixels_w_, pixels_h_, GL_RGB, GL_UNSIGNED_BYTE, flipped.data());
    pixels_.resize(flipped.size());
    const std::size_t row = static_cast<std::size_t>(pixels_w_) * 3;
    for (int y = 0; y < pixels_h_; ++y) {  // GL's rows start at the bottom
      std::copy_n(flipped.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(pixels_h_ - 1 - y)), row,
                  pixels_.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y)));
    }
  }
  SDL_GL_SwapWindow(window_);
  return true;
}

bool SdlGlWindow::read_pixels(std::vector<std::uint8_t>& rgb, int& width, int& height) {
  if (pixels_.empty()) return false;
  rgb = pixels_;
  width = pixels_w_;
  height = pixels_h_;
  return true;
}

}  // namespace hmp::view::gl
