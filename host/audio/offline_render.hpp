#pragma once
// The song's audio rendered to memory or a WAV file (tests, previews): the same SongSynth and event
// timing as the live player, pulled as fast as the CPU allows instead of by a sound card.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host/audio/audio_events.hpp"
#include "host/audio/audio_options.hpp"

namespace hmp::audio {

struct RenderedAudio {
  int sample_rate = 0;
  std::int64_t start_us = 0;  // song time of the first frame
  std::vector<float> left, right;
  bool silent_fallback = false;  // no SoundFont: all zeros, and a warning was given
};

// Renders song time [from_us, to_us). A SoundFont that is missing or does not load gives silence of the
// right length and one warning through `warn` (options.enabled is ignored: rendering to memory needs
// no audio device either way).
// `progress` (if given) hears (frames done, frames in all) as the render goes.
RenderedAudio render_offline(const std::vector<AudioEvent>& events, std::int64_t from_us, std::int64_t to_us,
                             const AudioOptions& options, const WarningSink& warn = print_warning,
                             const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});

// Stereo 32-bit float WAV (libsndfile). Throws std::runtime_error naming the path on failure.
void write_wav(const std::string& path, const RenderedAudio& audio);

}  // namespace hmp::audio
