#include "host/audio/offline_render.hpp"

#include <sndfile.h>

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "host/audio/soundfont.hpp"

namespace hmp::audio {

RenderedAudio render_offline(const std::vector<AudioEvent>& events, std::int64_t from_us, std::int64_t to_us,
                             const AudioOptions& options, const WarningSink& warn) {
  const std::optional<std::string> soundfont = find_soundfont(options.soundfont);
  SongSynth synth(options.synth, soundfont.value_or(""));
  RenderedAudio out;
  out.sample_rate = synth.sample_rate();
  out.start_us = from_us;
  if (!soundfont) {
    warn(options.soundfont.empty() ? "audio: no General MIDI SoundFont found (install fluid-soundfont-gm): rendering silence"
                                   : "audio: SoundFont " + options.soundfont + " not found: rendering silence");
    out.silent_fallback = true;
  } else if (!synth.has_soundfont()) {
    warn("audio: " + synth.load_error() + ": rendering silence");
    out.silent_fallback = true;
  }
  synth.set_events(events);
  synth.seek(from_us);
  const std::int64_t frames = std::max<std::int64_t>(0, synth.frame_of(to_us) - synth.frame_of(from_us));
  out.left.resize(static_cast<std::size_t>(frames));
  out.right.resize(static_cast<std::size_t>(frames));
  // In slices: one render() call per slice keeps FluidSynth's per-call work bounded.
  constexpr std::size_t kSlice = 4096;
  for (std::size_t at = 0; at < out.left.size(); at += kSlice) {
    const std::size_t n = std::min(kSlice, out.left.size() - at);
    synth.render(out.left.data() + at, out.right.data() + at, n);
  }
  return out;
}

void write_wav(const std::string& path, const RenderedAudio& audio) {
  SF_INFO info{};
  info.samplerate = audio.sample_rate;
  info.channels = 2;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
  if (f == nullptr) throw std::runtime_error("cannot write " + path + ": " + sf_strerror(nullptr));
  std::vector<float> interleaved(audio.left.size() * 2);
  for (std::size_t i = 0; i < audio.left.size(); ++i) {
    interleaved[2 * i] = audio.left[i];
    interleaved[2 * i + 1] = audio.right[i];
  }
  const auto frames = static_cast<sf_count_t>(audio.left.size());
  const sf_count_t written = sf_writef_float(f, interleaved.data(), frames);
  sf_close(f);
  if (written != frames) throw std::runtime_error("cannot write " + path + ": disk full?");
}

}  // namespace hmp::audio
