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
  env_.start(preset, q16_to_amp(note.amp_q16), note.duration_ticks, static_cast<float>(cfg.tick_hz), cfg.end_fade_ms);
  phase_ = 0;  // Eq. 8: phase 0 on the note's first tick
  inc_ = phase_increment(note.freq_q20, cfg.tick_hz);
  n_ = 0;
  n_end_ = env_.duration_ticks();  // N, with 0 already promoted to 1 by the envelope
}

// Voice::next() is inline in voice.hpp.

}  // namespace hmp::synth
