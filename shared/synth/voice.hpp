#pragma once
// One sounding note: y[n] = E(n·T) · sin(2π f n T), phase 0 at the note's start (design §6 Eq. 8).
#include <cstdint>

#include "shared/envelope/envelope.hpp"
#include "shared/synth/sine.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::synth {

// A note as the device receives it (decoded from the wire; see shared/protocol).
struct Note {
  std::uint64_t start_tick = 0;
  std::uint32_t duration_ticks = 1;  // N ≥ 1
  std::uint32_t freq_q20 = 0;        // see frequency.hpp
  std::uint16_t amp_q16 = 0;         // 65535 = 1.0
  std::uint8_t preset = 0;           // envelope slot
  std::uint8_t track = 0;            // which track/voice group it belongs to (for reports)
  std::uint8_t key = 0;              // a held note: the host's handle, paired with track by release and bend
  bool held = false;                 // live input: sounds until released (duration_ticks is ignored)
};

struct SynthConfig {
  std::uint32_t tick_hz = kNominalTickHz;
  float end_fade_ms = 2.0f;
  SineImpl sine = kDefaultSine;
  float limiter_release_ms = 50.0f;  // Engine's limiter recovery time constant (see engine.hpp)
};

class Voice {
 public:
  void start(const Note& note, const envelope::Adsr& preset, const SynthConfig& cfg, std::uint32_t order);
  // All of start() but the start order: the costly part (the envelope's set-up, in double), which the
  // firmware does ahead of the note's tick outside the tick interrupt. A voice prepared from the same
  // note, preset and config plays exactly what start() would; Engine::start_prepared puts it to work.
  void prepare(const Note& note, const envelope::Adsr& preset, const SynthConfig& cfg);
  // This voice becomes a copy of a prepared one, with its start order.
  void adopt(const Voice& prepared, std::uint32_t order) {
    *this = prepared;
    order_ = order;
  }
  // The sample for the current tick, then advance one tick. Returns 0 once finished. Inline below: the
  // engine calls it for every voice on every tick.
  float next();
  bool active() const { return n_ < n_end_; }
  std::uint32_t order() const { return order_; }  // start order: smaller = older (for stealing)
  std::uint32_t freq_q20() const { return freq_q20_; }
  const Note& note() const { return note_; }
  void stop() { n_ = n_end_; }
  // A held note that has not been released yet.
  bool held() const { return active() && env_.held(); }
  // A held note's release from this tick on (Envelope::release_at); nothing for any other note.
  void release() { n_end_ = env_.release_at(n_); }
  // The frequency from this tick on, the phase going on where it is (a pitch bend).
  void set_frequency(std::uint32_t freq_q20, std::uint32_t tick_hz);

 private:
  envelope::Envelope env_;
  std::uint64_t phase_ = 0, inc_ = 0;
  std::uint32_t n_ = 0, n_end_ = 0, order_ = 0, freq_q20_ = 0;
  SineImpl sine_ = kDefaultSine;
  Note note_{};
};

inline float Voice::next() {
  if (!active()) return 0.0f;
  // The top 32 bits address the sine; the low 32 keep the sub-LSB phase so it never drifts.
  const float y = env_.at_within(n_) * sine(sine_, static_cast<std::uint32_t>(phase_ >> 32));
  phase_ += inc_;
  ++n_;
  return y;
}

}  // namespace hmp::synth
