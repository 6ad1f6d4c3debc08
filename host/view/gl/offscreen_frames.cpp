#include "host/view/gl/offscreen_frames.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <chrono>
#include <cstdio>
#include <cstring>

#include "host/common/cpu_time.hpp"

namespace hmp::view::gl {
namespace {

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = std::strstr(list, name); p != nullptr; p = std::strstr(p + n, name)) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

std::string egl_error(const char* what) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(eglGetError()));
  return std::string(what) + " failed (EGL error " + code + ")";
}

// The surfaceless platform needs no display server; where it is missing (not Mesa), EGL's default display
// is the next best (it may need $DISPLAY).
EGLDisplay get_display() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (has_extension(client, "EGL_MESA_platform_surfaceless") && has_extension(client, "EGL_EXT_platform_base")) {
    const auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display != nullptr) {
      const EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (d != EGL_NO_DISPLAY) return d;
    }
  }
  return eglGetDisplay(EGL_DEFAULT_DISPLAY);
}

}  // namespace

std::unique_ptr<EglOffscreenFrames> EglOffscreenFrames::open(const ViewSetup& setup, std::string& error) {
  if (setup.song == nullptr) {
    error = "no song";
    return nullptr;
  }
  if (setup.width < 16 || setup.height < 16 || setup.width > 8192 || setup.height > 8192) {
    error = "frame size " + std::to_string(setup.width) + "x" + std::to_string(setup.height) + " out of 16..8192";
    return nullptr;
  }
  const EGLDisplay display = get_display();
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || eglInitialize(display, &major, &minor) != EGL_TRUE) {
    error = egl_error("EGL initialisation");
    return nullptr;
  }
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  if (!has_extension(extensions, "EGL_KHR_surfaceless_context")) {
    error = "EGL has no surfaceless contexts (EGL_KHR_surfaceless_context)";
    return nullptr;
  }
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    error = egl_error("binding desktop OpenGL");
    return nullptr;
  }
  // No config is needed to draw only into frame buffer objects; where that is not offered, any config will do.
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_extension(extensions, "EGL_KHR_no_config_context")) {
    const EGLint wanted[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint found = 0;
    if (eglChooseConfig(display, wanted, &config, 1, &found) != EGL_TRUE || found < 1) {
      error = egl_error("choosing an EGL config");
      return nullptr;
    }
  }
  const EGLint attributes[] = {
      EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  const EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    error = egl_error("creating an OpenGL 3.3 core context");
    return nullptr;
  }
  if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
    error = egl_error("making the context current");
    eglDestroyContext(display, context);
    return nullptr;
  }
  std::unique_ptr<EglOffscreenFrames> f(new EglOffscreenFrames(setup, display, context));
  if (!f->complete_) {
    error = "OpenGL: the off-screen frame buffer is incomplete";
    return nullptr;
  }
  if (!f->painter_->ok()) {
    error = "OpenGL: " + f->painter_->error();
    return nullptr;
  }
  return f;
}

EglOffscreenFrames::EglOffscreenFrames(const ViewSetup& setup, void* display, void* context)
    : setup_(setup), display_(display), context_(context) {
  glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glGenTextures(1, &colour_);
  glBindTexture(GL_TEXTURE_2D, colour_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, setup.width, setup.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // no mipmaps
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour_, 0);
  complete_ = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  painter_ = std::make_unique<FramePainter>(*setup.song, setup.draw_everything, setup.keys);
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  renderer_name_ = name != nullptr ? name : "?";
  pixels_.resize(static_cast<std::size_t>(setup.width) * static_cast<std::size_t>(setup.height) * 4);
}

EglOffscreenFrames::~EglOffscreenFrames() {
  make_current();
  painter_.reset();
  glDeleteTextures(1, &colour_);
  glDeleteFramebuffers(1, &framebuffer_);
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  // The display stays initialised: EGL counts no references, and another user in the process may hold it.
}

void EglOffscreenFrames::make_current() const {
  if (eglGetCurrentContext() != context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_);
}

const std::uint8_t* EglOffscreenFrames::draw(const FrameState& state) {
  const double cpu0 = 1e3 * thread_cpu_seconds();
  const auto wall0 = std::chrono::steady_clock::now();
  make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  painter_->paint(state, setup_.width, setup_.height, 1.0f, cost_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, setup_.width, setup_.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels_.data());
  cost_.frame_cpu_ms = 1e3 * thread_cpu_seconds() - cpu0;
  cost_.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
  return pixels_.data();
}

}  // namespace hmp::view::gl
