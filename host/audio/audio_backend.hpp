#pragma once
// The audio module's interface (module "audio", host/audio/fluid/): everything that needs FluidSynth,
// SDL2's audio, ALSA, libsndfile or libsamplerate. The player, the offline renderer and the WAV exports
// reach those libraries only through this, so a command that makes no sound never loads them
// (host/modules/module_loader.hpp). No library type and no exception crosses it.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "host/audio/audio_events.hpp"
#include "host/audio/synth_settings.hpp"

namespace hmp::audio {

// The song's sound, rendered against a sample position it owns (fluid/song_synth.hpp says how).
class Synth {
 public:
  virtual ~Synth() = default;
  // false: the SoundFont could not be loaded; load_error() says why and render() writes silence.
  virtual bool load_soundfont(const std::string& path) = 0;
  virtual bool has_soundfont() const = 0;
  virtual const std::string& load_error() const = 0;
  // Replaces the events (sorted as audio_events() returns them) and goes to song time 0.
  virtual void set_events(const std::vector<AudioEvent>& events) = 0;
  virtual void seek(std::int64_t song_us) = 0;  // sounding voices stop at once
  virtual void release_all() = 0;               // notes go into their release (pause)
  // Applies one event now, whatever its time (live input): heard from the next render().
  virtual void apply_now(const AudioEvent& e) = 0;
  // Writes `frames` frames from the present position into left/right and advances by as much.
  virtual void render(float* left, float* right, std::size_t frames) = 0;
  virtual std::int64_t position_us() const = 0;
  virtual std::int64_t frame_of(std::int64_t song_us) const = 0;  // nearest frame
  virtual int sample_rate() const = 0;
  // The song frame at which a note starting at `song_us` is first heard.
  virtual std::int64_t heard_frame(std::uint8_t channel, std::uint8_t program, std::uint8_t key,
                                   std::int64_t song_us) const = 0;
};

// An open audio output; destroying it stops the callbacks (and returns after the last one).
class OutputStream {
 public:
  virtual ~OutputStream() = default;
};

// Called from the driver's thread for every buffer: fill out[0..outputs) with `frames` frames.
using RenderCallback = void (*)(void* context, int frames, int outputs, float* out[]);

class AudioBackend {
 public:
  static constexpr const char* kModule = "audio";
  static constexpr int kAbi = 2;

  virtual std::unique_ptr<Synth> make_synth(const SynthSettings& settings) const = 0;
  // Opens FluidSynth's audio driver `driver` (pulseaudio, alsa, sdl2, …) with this buffering, pulling
  // from `callback`. Null when it cannot be opened; `error` then says why in FluidSynth's words.
  virtual std::unique_ptr<OutputStream> open_output(Synth& synth, const std::string& driver, int period_frames,
                                                    int periods, RenderCallback callback, void* context,
                                                    std::string& error) const = 0;
  // Audio drivers tried since the process started (opened or not): tests prove --no-audio tries none.
  virtual std::uint64_t driver_attempts() const = 0;
  // WAV files, 32-bit float. Empty string: written; else the error (the caller names the file).
  virtual std::string write_wav(const std::string& path, int rate_hz,
                                std::span<const std::span<const float>> channels) const = 0;
  // Band-limited resampling (libsamplerate, best sinc). Empty `error`: done.
  virtual std::vector<float> resample(std::span<const float> samples, int from_hz, int to_hz,
                                      std::string& error) const = 0;

 protected:
  ~AudioBackend() = default;  // one static object in the module, never deleted through this
};

// The audio module, loaded on first call. Null when it cannot be had; `why` then says why.
const AudioBackend* audio_backend(std::string* why = nullptr);

// Audio drivers tried so far (AudioBackend::driver_attempts); 0 while the module is not loaded.
std::uint64_t audio_driver_attempts();

}  // namespace hmp::audio
