#include "host/view/gl/gl_window.hpp"

#include <SDL.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdint>
#include <cmath>

#include "host/common/cpu_time.hpp"

namespace hmp::view::gl {
namespace {

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

char plain_key_of(SDL_Keycode k) {
  switch (k) {
    case SDLK_SPACE: return ' ';
    case SDLK_LEFT: return '<';
    case SDLK_RIGHT: return '>';
    case SDLK_q: return 'q';
    case SDLK_t: return 't';
    case SDLK_e: return 'e';
    case SDLK_m: return 'm';
    case SDLK_f: return 'f';
    case SDLK_h: return 'h';
    case SDLK_PLUS:
    case SDLK_KP_PLUS:
    case SDLK_EQUALS: return '+';
    case SDLK_MINUS:
    case SDLK_KP_MINUS: return '-';
    case SDLK_LEFTBRACKET: return '[';
    case SDLK_RIGHTBRACKET: return ']';
    case SDLK_n: return 'n';  // next song (and, in the study, next round, as Enter)
    case SDLK_p:
      return 'p';  // previous song
    // The study's keys: 0/1/2 switch, a/b/c rank, u undo, Enter next.
    case SDLK_0:
    case SDLK_KP_0: return '0';
    case SDLK_1:
    case SDLK_KP_1: return '1';
    case SDLK_2:
    case SDLK_KP_2: return '2';
    case SDLK_a: return 'a';
    case SDLK_b: return 'b';
    case SDLK_c: return 'c';
    case SDLK_u: return 'u';
    case SDLK_RETURN:
    case SDLK_KP_ENTER: return '\n';
    default: return 0;
  }
}

// The character a key gives, as a terminal sends it (host/player/live_terminal.hpp, KeyDecoder), so that
// the window and the terminal read one alphabet: Shift or Caps Lock makes a letter upper case ('Q' is not
// quit there either; the window's own f and h stay as they are), Esc is 'q' as a lone ESC is there, and a
// key with Ctrl, Alt or the system key held gives nothing (Ctrl+C is SIGINT, raised by the caller, as a
// terminal's).
char key_of(SDL_Keycode k, Uint16 mod) {
  if ((mod & (KMOD_CTRL | KMOD_ALT | KMOD_GUI)) != 0) return 0;
  if (k == SDLK_ESCAPE) return 'q';
  const char c = plain_key_of(k);
  const bool upper = ((mod & KMOD_SHIFT) != 0) != ((mod & KMOD_CAPS) != 0);
  const bool window_own = c == 'f' || c == 'h';
  return upper && !window_own && c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c;
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
  if (!w->painter_->ok()) {
    error = "OpenGL: " + w->painter_->error();
    return nullptr;
  }
  return w;
}

SdlGlWindow::SdlGlWindow(const ViewSetup& setup, SDL_Window* window, void* context)
    : setup_(setup), window_(window), context_(context), fullscreen_(setup.fullscreen) {
  painter_ = std::make_unique<FramePainter>(*setup.song, setup.draw_everything, setup.keys);
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  renderer_name_ = name != nullptr ? name : "?";
}

SdlGlWindow::~SdlGlWindow() {
  SDL_GL_MakeCurrent(window_, context_);
  painter_.reset();
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
        if (e.key.keysym.sym == SDLK_c && (e.key.keysym.mod & KMOD_CTRL) != 0) std::raise(SIGINT);
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
      case SDL_MOUSEMOTION: events.push_back(at(ViewEvent::Kind::cursor, e.motion.x, e.motion.y)); break;
      default: break;
    }
  }
  return open_;
}

bool SdlGlWindow::frame(const FrameState& state, std::vector<ViewEvent>& events) {
  if (!poll(events)) return false;
  const double cpu0 = 1e3 * thread_cpu_seconds();
  const auto wall0 = std::chrono::steady_clock::now();
  SDL_GL_MakeCurrent(window_, context_);
  int w = 0, h = 0;
  float scale = 1.0f;
  size(w, h, scale);
  painter_->paint(state, std::max(1, w), std::max(1, h), scale, cost_);
  if (setup_.capture) {
    pixels_w_ = std::max(1, w);
    pixels_h_ = std::max(1, h);
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
  cost_.frame_cpu_ms = 1e3 * thread_cpu_seconds() - cpu0;
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
