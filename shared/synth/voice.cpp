#include "shared/synth/voice.hpp"

#include "shared/synth/frequency.hpp"

namespace hmp::synth {

void Voice::start(const Note& note, const envelope::Adsr& preset, const SynthConfig& cfg, std::uint32_t order) {
  prepare(note, preset, cfg);
  order_ = order;
}

void Voice::prepare(const Note& note, const envelope::Adsr& preset, const SynthConfig& cfg) {
  note_ = note;
  order_ = 0;
  freq_q20_ = note.freq_q20;
  sine_ = cfg.sine;
  const float peak = q16_to_amp(note.amp_q16);
  if (note.held) {
    env_.start_held(preset, peak, static_cast<float>(cfg.tick_hz), cfg.end_fade_ms);
  } else {
    env_.start(preset, peak, note.duration_ticks, static_cast<float>(cfg.tick_hz), cfg.end_fade_ms);
  }
  phase_ = 0;  // Eq. 8: phase 0 on the note's first tick
  inc_ = phase_increment(note.freq_q20, cfg.tick_hz);
  n_ = 0;
  n_end_ = env_.duration_ticks();  // N, with 0 already promoted to 1 by the envelope
}

void Voice::set_frequency(std::uint32_t freq_q20, std::uint32_t tick_hz) {
  freq_q20_ = freq_q20;
  note_.freq_q20 = freq_q20;
  inc_ = phase_increment(freq_q20, tick_hz);
}

// Voice::next() is inline in voice.hpp.

}  // namespace hmp::synth
