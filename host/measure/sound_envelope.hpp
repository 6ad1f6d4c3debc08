#pragma once
// host/measure/: the envelope of the sound a participant hears, measured as the 2015 paper measured
// Table 1 (§5.5: an oscilloscope on the synthesiser's output), but from FluidSynth's render of one note,
// and fitted twice (docs/envelopes.md, "Measured envelopes"):
//  - to FluidSynth's own volume envelope (SF2 2.04 §8.1.3 as FluidSynth renders it: delay; attack linear
//    in amplitude; hold; decay and release linear in decibels, their "time" the time to fall 96 dB);
//  - to the paper's Eq. 9–10 (envelope::Adsr), the preset the device plays, with its RMS error.
// No I/O here; render_notes.hpp renders the notes.
#include <cstdint>
#include <vector>

#include "shared/envelope/envelope.hpp"

namespace hmp::measure {

// A held note's amplitude every `step_s` from its note-on: the RMS of both channels over two periods of
// the key's fundamental (a harmonic sound repeats with that period, so the window sees no ripple), × √2
// (a sine's peak).
struct SoundEnvelope {
  double step_s = 0.001;
  double note_off_s = 0;          // when the note was released
  std::vector<double> amplitude;  // linear, the render's full scale
};

// `left`/`right` from the note-on on; the window is two periods of `fundamental_hz`.
SoundEnvelope envelope_of(const float* left, const float* right, std::size_t frames, int sample_rate,
                          double fundamental_hz, double note_off_s, double step_s = 0.001);

// FluidSynth's stages, as measured. Times in seconds; NaN where the sound does not show them.
struct Stages {
  bool sounded = false;     // false: silent (the SoundFont has no such program, or it makes no sound)
  double peak = 0;          // linear, the render's full scale
  double delay_s = 0;       // note-on → the attack's start
  double attack_s = 0;      // linear rise to the peak
  double hold_s = 0;        // at the peak
  double decay_s = 0;       // 96 dB per decay_s, down to the sustain level; NaN: no decay
  double sustain = 1;       // level while held, fraction of the peak; 0: it dies away
  double release_s = 0;     // 96 dB per release_s after the note-off; NaN: not measurable
  double level_at_off = 0;  // fraction of the peak at the note-off
};

Stages fit_stages(const SoundEnvelope& e);

// When the level at the note-off is too low to see the release: the time at which the held note first
// fell to `level` of its peak (after the attack), for a second render released there. NaN if never.
double time_to_fall_to(const SoundEnvelope& e, const Stages& s, double level);
// The release measured from a second render released while still loud (time_to_fall_to).
double release_of(const SoundEnvelope& e);

// The paper's Eq. 9–10 fitted to the held note: R and r = 1 % from the measured release slope (Eq. 10's
// release is FluidSynth's curve); A, Dc and S, starting from the stages, for the least RMS error against
// the sound's envelope over the note and its release (its duration D = note-off − delay + R).
// `rms_error`: that error, full scale = the sound's peak.
envelope::Adsr fit_adsr(const SoundEnvelope& e, const Stages& s, double* rms_error);

// The note's duration D as Eq. 10 plays it: the attack's start to the note-off, plus R.
double note_duration(const SoundEnvelope& e, const Stages& s, const envelope::Adsr& preset);

// `preset` played as a note of duration `duration_s` from the attack's start, one point per device tick
// (1 ms) paired with the envelope's sample at that time: what rms_error compares and --plot draws.
struct CurvePoint {
  std::size_t index;  // into SoundEnvelope::amplitude
  double value;       // the preset's level, full scale = 1
};
std::vector<CurvePoint> preset_curve(const SoundEnvelope& e, const Stages& s, const envelope::Adsr& preset,
                                     double duration_s);

// The RMS difference (full scale = the sound's peak) between the sound's envelope and preset_curve().
double rms_error(const SoundEnvelope& e, const Stages& s, const envelope::Adsr& preset, double duration_s);

}  // namespace hmp::measure
