#include "host/audio/fluid/fluid_runtime.hpp"

#include <SDL.h>
#include <alsa/asoundlib.h>
#include <fluidsynth.h>

#include <atomic>
#include <deque>
#include <mutex>

namespace hmp::audio {

namespace {

constexpr std::size_t kMaxKeptMessages = 32;

std::mutex g_log_mutex;
std::deque<std::string> g_messages;
std::atomic<std::uint64_t> g_driver_attempts{0};

void capture(int level, const char* message, void*) {
  if (level > FLUID_WARN || message == nullptr) return;  // info/debug: "Using 'alsa' audio driver", …
  std::lock_guard lock(g_log_mutex);
  if (g_messages.size() >= kMaxKeptMessages) g_messages.pop_front();
  g_messages.emplace_back(message);
}

// alsa-lib prints configuration errors ("cannot find card '0'") straight to stderr unless the program
// installs a handler; the failure itself reaches us through FluidSynth's return value and log.
void alsa_silent(const char*, int, const char*, int, const char*, ...) {}

}  // namespace

void install_fluid_logging() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int level = FLUID_PANIC; level < LAST_LOG_LEVEL; ++level) fluid_set_log_function(level, capture, nullptr);
    snd_lib_error_set_handler(alsa_silent);
  });
}

std::vector<std::string> take_fluid_messages() {
  std::lock_guard lock(g_log_mutex);
  std::vector<std::string> out(g_messages.begin(), g_messages.end());
  g_messages.clear();
  return out;
}

std::uint64_t fluid_driver_attempts() { return g_driver_attempts.load(); }
void count_audio_driver_attempt() { g_driver_attempts.fetch_add(1); }

bool sdl_audio_acquire() { return SDL_InitSubSystem(SDL_INIT_AUDIO) == 0; }
void sdl_audio_release() { SDL_QuitSubSystem(SDL_INIT_AUDIO); }

}  // namespace hmp::audio
