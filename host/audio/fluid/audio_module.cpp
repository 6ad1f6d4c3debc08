// The audio module's entry (hmp-audio.so): the AudioBackend over FluidSynth (song synthesis and the
// sound card), libsndfile (WAV files) and libsamplerate (resampling).
#include <fluidsynth.h>
#include <samplerate.h>
#include <sndfile.h>

#include <algorithm>
#include <exception>

#include "host/audio/audio_backend.hpp"
#include "host/audio/fluid/fluid_runtime.hpp"
#include "host/audio/fluid/song_synth.hpp"
#include "host/modules/module_loader.hpp"

namespace hmp::audio {
namespace {

// A FluidSynth audio driver pulling from a callback; SDL's audio subsystem held while the sdl2 driver runs.
class FluidOutput final : public OutputStream {
 public:
  FluidOutput(RenderCallback callback, void* context, bool sdl) : callback_(callback), context_(context), sdl_(sdl) {}
  ~FluidOutput() override {
    if (driver_ != nullptr) delete_fluid_audio_driver(driver_);  // returns after the last callback
    if (sdl_) sdl_audio_release();
  }
  FluidOutput(const FluidOutput&) = delete;
  FluidOutput& operator=(const FluidOutput&) = delete;

  bool open(fluid_settings_t* settings) {
    driver_ = new_fluid_audio_driver2(settings, &FluidOutput::on_audio, this);
    return driver_ != nullptr;
  }

 private:
  static int on_audio(void* self, int len, int, float*[], int nout, float* out[]) {
    auto* me = static_cast<FluidOutput*>(self);
    me->callback_(me->context_, len, nout, out);
    return FLUID_OK;
  }

  RenderCallback callback_;
  void* context_;
  bool sdl_;
  fluid_audio_driver_t* driver_ = nullptr;
};

class FluidBackend final : public AudioBackend {
 public:
  std::unique_ptr<Synth> make_synth(const SynthSettings& settings) const override {
    try {
      return std::make_unique<SongSynth>(settings, "");
    } catch (const std::exception&) {
      return nullptr;  // FluidSynth could not create a synthesizer (out of memory)
    }
  }

  std::unique_ptr<OutputStream> open_output(Synth& synth, const std::string& driver, int period_frames, int periods,
                                            RenderCallback callback, void* context, std::string& error) const override {
    // Every Synth this back-end hands out is a SongSynth.
    fluid_settings_t* settings = static_cast<SongSynth&>(synth).fluid_settings();
    fluid_settings_setint(settings, "audio.period-size", period_frames);
    fluid_settings_setint(settings, "audio.periods", periods);
    fluid_settings_setstr(settings, "audio.driver", driver.c_str());
    // FluidSynth's sdl2 driver expects the program to have initialised SDL's audio subsystem.
    const bool sdl = driver == "sdl2" && sdl_audio_acquire();
    auto output = std::make_unique<FluidOutput>(callback, context, sdl);
    take_fluid_messages();
    count_audio_driver_attempt();
    if (output->open(settings)) return output;
    const std::vector<std::string> log = take_fluid_messages();
    error = log.empty() ? "" : log.back();
    return nullptr;
  }

  std::uint64_t driver_attempts() const override { return fluid_driver_attempts(); }

  std::string write_wav(const std::string& path, int rate_hz,
                        std::span<const std::span<const float>> channels) const override {
    if (channels.empty()) return "no channels";
    SF_INFO info{};
    info.samplerate = rate_hz;
    info.channels = static_cast<int>(channels.size());
    info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
    SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
    if (f == nullptr) return sf_strerror(nullptr);
    const std::size_t frames = channels[0].size();
    std::vector<float> interleaved(frames * channels.size());
    for (std::size_t c = 0; c < channels.size(); ++c) {
      const std::span<const float> ch = channels[c];
      for (std::size_t i = 0; i < frames; ++i) interleaved[i * channels.size() + c] = i < ch.size() ? ch[i] : 0.0f;
    }
    const auto n = static_cast<sf_count_t>(frames);
    const sf_count_t written = sf_writef_float(f, interleaved.data(), n);
    const int close_error = sf_close(f);
    if (written != n || close_error != 0) return "write failed (disk full?)";
    return {};
  }

  std::vector<float> resample(std::span<const float> samples, int from_hz, int to_hz,
                              std::string& error) const override {
    if (samples.empty()) return {};
    const double ratio = static_cast<double>(to_hz) / from_hz;
    std::vector<float> out(static_cast<std::size_t>(static_cast<double>(samples.size()) * ratio) + 64);
    SRC_DATA data{};
    data.data_in = samples.data();
    data.input_frames = static_cast<long>(samples.size());
    data.data_out = out.data();
    data.output_frames = static_cast<long>(out.size());
    data.src_ratio = ratio;
    data.end_of_input = 1;
    if (const int err = src_simple(&data, SRC_SINC_BEST_QUALITY, 1); err != 0) {
      error = src_strerror(err);
      return {};
    }
    out.resize(static_cast<std::size_t>(data.output_frames_gen));
    return out;
  }
};

}  // namespace
}  // namespace hmp::audio

HMP_DEFINE_MODULE(hmp::audio::AudioBackend, hmp::audio::FluidBackend)
