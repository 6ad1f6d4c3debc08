#pragma once
// How the song's sound is synthesised (design §14): the settings the player and the offline renderer
// hand to the audio module's synthesiser.
#include <cstdint>

namespace hmp::audio {

struct SynthSettings {
  int sample_rate = 48000;
  float gain = 0.3f;  // FluidSynth's master gain (its default is 0.2; a GM mix rarely clips at 0.3)
  bool reverb = true;
  bool chorus = true;
  bool onset_compensation = true;
  double max_onset_lead_ms = 20.0;  // longer measured delays are taken as the instrument's sound, not lag
};

// The frame nearest to song time `us` at `rate` Hz (halves away from zero), exact in integers.
inline std::int64_t nearest_frame(std::int64_t us, int rate) {
  const std::int64_t scaled = us * rate;
  return scaled >= 0 ? (scaled + 500'000) / 1'000'000 : -((-scaled + 500'000) / 1'000'000);
}

}  // namespace hmp::audio
