#include "host/view/gl/gl_window.hpp"

#include <SDL.h>
#include <epoxy/gl.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cmath>

#include "host/view/gl/roll_renderer.hpp"
#include "host/view/gl/text_layer.hpp"

namespace hmp::view::gl {
namespace {

constexpr Rgb kCentreLine{0.85f, 0.85f, 0.85f};
constexpr Rgb kStrip{0.0f, 114 / 255.0f, 178 / 255.0f};
constexpr Rgb kPanel{0.13f, 0.13f, 0.15f};
constexpr Rgb kProgressDone{0.45f, 0.45f, 0.5f};
constexpr Rgb kText{0.92f, 0.92f, 0.92f};
constexpr Rgb kTextDim{0.55f, 0.55f, 0.58f};
constexpr Rgb kCursor{1.0f, 1.0f, 1.0f};

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

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
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
  text_ = std::make_unique<TextLayer>();
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  renderer_name_ = name != nullptr ? name : "?";
}

SdlGlWindow::~SdlGlWindow() {
  SDL_GL_MakeCurrent(window_, context_);
  renderer_.reset();
  text_.reset();
  SDL_GL_DeleteContext(context_);
  SDL_DestroyWindow(window_);
}

void SdlGlWindow::size(int& width_px, int& height_px, float& scale) const {
  int lw = 0, lh = 0;
  SDL_GetWindowSize(window_, &lw, &lh);
  SDL_GL_GetDrawableSize(window_, &width_px, &height_px);
  scale = lw > 0 ? static_cast<float>(width_px) / static_cast<float>(lw) : 1.0f;
}

bool SdlGlWindow::poll(std::vector<ViewEvent>& events) {
  int w = 0, h = 0;
  float scale = 1.0f;
  size(w, h, scale);
  auto at = [scale](ViewEvent::Kind kind, int x, int y) {  // events come in logical pixels
    return ViewEvent{kind, 0, static_cast<float>(x) * scale, static_cast<float>(y) * scale};
  };
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
        if (e.button.button == SDL_BUTTON_LEFT) events.push_back(at(ViewEvent::Kind::press, e.button.x, e.button.y));
        break;
      case SDL_MOUSEBUTTONUP:
        if (e.button.button == SDL_BUTTON_LEFT) events.push_back(at(ViewEvent::Kind::release, e.button.x, e.button.y));
        break;
      case SDL_MOUSEMOTION:
        events.push_back(at(ViewEvent::Kind::cursor, e.motion.x, e.motion.y));
        break;
      default: break;
    }
  }
  return open_;
}

bool SdlGlWindow::frame(const FrameState& state, std::vector<ViewEvent>& events) {
  if (!poll(events)) return false;
  const double cpu0 = thread_cpu_ms();
  const auto wall0 = std::chrono::steady_clock::now();
  SDL_GL_MakeCurrent(window_, context_);
  int w = 0, h = 0;
  float scale = 1.0f;
  size(w, h, scale);
  LayoutParams p = layout_params_;
  p.width_px = std::max(1, w);
  p.height_px = std::max(1, h);
  p.seconds_across = state.seconds_across;
  p.margin_px *= scale;
  p.depth_step_px *= scale;
  const auto tracks = static_cast<std::uint32_t>(index_.tracks());
  RollLayout layout(p, tracks, std::min(state.haptic_track, tracks == 0 ? 0u : tracks - 1));
  layout.set_depth_blend(state.previous_haptic, state.depth_blend);
  const Chrome chrome = chrome_layout(p, scale);
  auto hidden = [&](std::uint32_t t) {
    return std::any_of(state.legend.begin(), state.legend.end(), [t](const LegendEntry& e) { return e.track == t && e.hidden; });
  };

  // Back to front: the deepest layer first, the haptic track last (on top). Only the visible bars.
  std::vector<std::uint32_t> order(tracks);
  for (std::uint32_t t = 0; t < tracks; ++t) order[t] = t;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return layout.depth_of(a) > layout.depth_of(b); });
  instances_.clear();
  const std::int64_t t0 = layout.window_begin_us(state.song_us), t1 = layout.window_end_us(state.song_us);
  for (const std::uint32_t t : order) {
    if (hidden(t)) continue;
    if (setup_.draw_everything) {
      index_.visible(t, INT64_MIN / 2, INT64_MAX / 2, visible_);
    } else {
      index_.visible(t, t0, t1, visible_);
    }
    for (const Bar& b : visible_) instances_.push_back({layout.bar_rect(b, state.song_us), layout.colour(b, state.song_us)});
  }
  // The present: a thin line at the centre, over the roll.
  const float cx = static_cast<float>(p.width_px) * 0.5f;
  instances_.push_back({{cx - scale, chrome.overlay.y1, cx + scale, chrome.progress.y0}, kCentreLine});
  // The progress bar: the part played so far lighter.
  instances_.push_back({chrome.progress, kPanel});
  if (state.end_us > 0) {
    const double f = std::clamp(static_cast<double>(state.song_us) / static_cast<double>(state.end_us), 0.0, 1.0);
    const float x = chrome.progress.x0 + static_cast<float>(f) * (chrome.progress.x1 - chrome.progress.x0);
    instances_.push_back({{chrome.progress.x0, chrome.progress.y0, x, chrome.progress.y1}, kProgressDone});
  }
  // The vibration the device plays now: a strip along the bottom, one column per sample.
  const int n = std::clamp(state.vibration_samples, 0, 256);
  const float strip_h = chrome.strip.y1 - chrome.strip.y0;
  const float base = chrome.strip.y0 + strip_h * 0.5f;
  for (int i = 0; i < n; ++i) {
    const float x0 = static_cast<float>(p.width_px) * static_cast<float>(i) / static_cast<float>(n);
    const float x1 = static_cast<float>(p.width_px) * static_cast<float>(i + 1) / static_cast<float>(n);
    const float v = std::clamp(state.vibration[i], -1.0f, 1.0f) * strip_h * 0.45f;
    instances_.push_back({{x0, std::min(base, base - v), x1, std::max(base, base - v) + 1.0f}, kStrip});
  }
  // The legend: a panel per track with its colour swatch (hidden tracks dimmed).
  std::vector<TextItem> text;
  if (!state.overlay.empty()) text.push_back({6.0f * scale, (chrome.overlay.y1 - chrome.text_px * 1.2f) * 0.5f, chrome.text_px, kText, state.overlay});
  for (std::size_t row = 0; row < state.legend.size(); ++row) {
    const LegendEntry& entry = state.legend[row];
    if (entry.track >= tracks) continue;
    const Rect r = chrome.legend_row_rect(row);
    instances_.push_back({r, kPanel});
    const Bar probe{0, 0, 0, 0, entry.track};
    const Rgb swatch = layout.colour(probe, 1);  // not sounding at t = 1 µs: the track's own colour
    const float sw = r.y1 - r.y0 - 6.0f * scale;
    instances_.push_back({{r.x0 + 3.0f * scale, r.y0 + 3.0f * scale, r.x0 + 3.0f * scale + sw, r.y1 - 3.0f * scale},
                          entry.hidden ? kPanel : swatch});
    text.push_back({r.x0 + 8.0f * scale + sw, r.y0 + 2.0f * scale, chrome.text_px, entry.hidden ? kTextDim : kText,
                    (entry.haptic ? "\u25B6 " : "") + entry.label});
  }
  // The touch cursor: a cross with a box, filled while pushing in.
  if (state.cursor) {
    const float c = 7.0f * scale, t = scale;
    const float x = state.cursor_x, y = state.cursor_y;
    instances_.push_back({{x - c, y - t, x + c, y + t}, kCursor});
    instances_.push_back({{x - t, y - c, x + t, y + c}, kCursor});
    if (state.cursor_pressing) instances_.push_back({{x - c * 0.5f, y - c * 0.5f, x + c * 0.5f, y + c * 0.5f}, kSoundingYellow});
  }
  // Help: a panel in the middle.
  if (!state.help.empty()) {
    const float line = chrome.text_px * 1.5f, width = 420.0f * scale;
    const float x0 = (static_cast<float>(p.width_px) - width) * 0.5f, y0 = chrome.overlay.y1 + 20.0f * scale;
    instances_.push_back({{x0, y0, x0 + width, y0 + line * static_cast<float>(state.help.size()) + 12.0f * scale}, kPanel});
    for (std::size_t i = 0; i < state.help.size(); ++i) {
      text.push_back({x0 + 10.0f * scale, y0 + 6.0f * scale + line * static_cast<float>(i), chrome.text_px, kText, state.help[i]});
    }
  }
  text_->prepare(p.width_px, p.height_px, text);
  cost_.prepare_cpu_ms = thread_cpu_ms() - cpu0;
  cost_.instances = instances_.size();
  renderer_->draw(p.width_px, p.height_px, instances_);
  text_->draw();
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
  cost_.frame_cpu_ms = thread_cpu_ms() - cpu0;
  cost_.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
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
