#include "host/audio/offline_render.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "host/audio/audio_backend.hpp"
#include "host/audio/soundfont.hpp"

namespace hmp::audio {

RenderedAudio render_offline(const std::vector<AudioEvent>& events, std::int64_t from_us, std::int64_t to_us,
                             const AudioOptions& options, const WarningSink& warn,
                             const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
  RenderedAudio out;
  out.sample_rate = options.synth.sample_rate;
  out.start_us = from_us;
  const auto frames_between = [&](std::int64_t a, std::int64_t b) {
    const std::int64_t n = nearest_frame(b, out.sample_rate) - nearest_frame(a, out.sample_rate);
    return static_cast<std::size_t>(std::max<std::int64_t>(0, n));
  };
  const auto silence = [&](const std::string& why) {
    warn("audio: " + why + ": rendering silence");
    out.silent_fallback = true;
    out.left.assign(frames_between(from_us, to_us), 0.0f);
    out.right = out.left;
    return out;
  };
  const std::optional<std::string> soundfont = find_soundfont(options.soundfont);
  if (!soundfont) {
    return silence(options.soundfont.empty() ? "no General MIDI SoundFont found (install fluid-soundfont-gm)"
                                             : "SoundFont " + options.soundfont + " not found");
  }
  std::string why;
  const AudioBackend* backend = audio_backend(&why);
  if (backend == nullptr) return silence("the audio module is not available (" + why + ")");
  const std::unique_ptr<Synth> synth = backend->make_synth(options.synth);
  if (!synth) return silence("FluidSynth could not create a synthesizer");
  if (!synth->load_soundfont(*soundfont)) return silence(synth->load_error());
  synth->set_events(events);
  synth->seek(from_us);
  out.left.resize(frames_between(from_us, to_us));
  out.right.resize(out.left.size());
  // In slices: one render() call per slice keeps FluidSynth's per-call work bounded.
  constexpr std::size_t kSlice = 4096;
  for (std::size_t at = 0; at < out.left.size(); at += kSlice) {
    const std::size_t n = std::min(kSlice, out.left.size() - at);
    synth->render(out.left.data() + at, out.right.data() + at, n);
    if (progress) progress(at + n, out.left.size());
  }
  return out;
}

void write_wav(const std::string& path, const RenderedAudio& audio) {
  std::string why;
  const AudioBackend* backend = audio_backend(&why);
  if (backend == nullptr)
    throw std::runtime_error("cannot write " + path + ": the audio module is not available (" + why + ")");
  const std::span<const float> channels[] = {audio.left, audio.right};
  if (const std::string error = backend->write_wav(path, audio.sample_rate, channels); !error.empty()) {
    throw std::runtime_error("cannot write " + path + ": " + error);
  }
}

}  // namespace hmp::audio
