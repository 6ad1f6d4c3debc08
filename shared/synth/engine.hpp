#pragma once
// The synthesis engine shared by the firmware tick and the host's `hmp render`: a voice pool with
// oldest-first stealing, the envelope preset slots, the polyphony policy and the limiter (design §7).
// The caller starts notes on their tick and calls tick() once per tick.
#include <cstdint>

#include "shared/envelope/envelope.hpp"
#include "shared/synth/voice.hpp"

namespace hmp::synth {

inline constexpr std::uint8_t kVoiceCount = 16;

enum class Polyphony : std::uint8_t { sum, highest, latest };
const char* name(Polyphony p);
bool find_polyphony(const char* name, Polyphony& out);

// Smooth peak limiter: identity while |x| ≤ 1; when the sum exceeds full scale the gain drops at once
// to keep |y| ≤ 1 (the waveform is scaled, never flattened) and recovers with a release time constant.
class Limiter {
 public:
  void configure(float release_ms, std::uint32_t tick_hz);
  float process(float x);  // NaN/±Inf in → 0 out; |result| ≤ 1
  float gain() const { return 1.0f - gap_; }
  void reset() { gap_ = 0.0f; }

 private:
  // The state is the gap to unity gain rather than the gain: it decays geometrically with float's
  // relative precision, so 1 − gap returns to exactly 1.0 (and bit-exact pass-through) instead of
  // stalling an ulp or a few below it.
  float gap_ = 0.0f;
  float keep_ = 0.0f;  // fraction of the gap left after one tick: exp(−1/τ), τ = release in ticks
};

struct EngineCounters {
  std::uint32_t started = 0;
  std::uint32_t stolen = 0;
  std::uint32_t rejected = 0;  // notes naming an empty preset slot or carrying zero/invalid fields
};

class Engine {
 public:
  explicit Engine(const SynthConfig& cfg = {});
  void configure(const SynthConfig& cfg);
  void set_polyphony(Polyphony p) { policy_ = p; }
  Polyphony polyphony() const { return policy_; }

  // Envelope slots: built-ins preloaded; user slots (kFirstUserSlot…) empty until uploaded.
  bool set_preset(std::uint8_t slot, const envelope::Adsr& adsr);  // false: bad slot or invalid preset
  const envelope::Adsr* preset(std::uint8_t slot) const;           // nullptr if empty

  // Start a note now (on this tick). Steals the oldest voice when full (counted). false = rejected and
  // counted: empty preset slot, duration 0 (malformed here, although a voice would play it as 1 tick),
  // frequency 0 or at/above Nyquist (tick_hz / 2). Amplitude 0 is a valid, silent note.
  bool start(const Note& note);
  // The same for a note whose voice was prepared ahead (Voice::prepare with this engine's config and
  // the note's preset as they are now, e.g. outside a tick interrupt): the same checks, counters and
  // choice of voice as start(note), with a copy instead of the envelope's set-up.
  bool start_prepared(const Voice& prepared);
  // Live input (notes whose end is not known when they start; note.held is set here). start_held: as
  // start(), after releasing a note still held under the same track and key (a key struck again).
  // release: the held note of that track and key enters its release; false if there is none (stolen,
  // stopped, or never started). bend: every sounding note of that track and key (held or releasing) takes
  // the frequency; false if there is none, or the frequency is 0 or at/above Nyquist (nothing changes).
  bool start_held(Note note);
  bool release(std::uint8_t track, std::uint8_t key);
  bool bend(std::uint8_t track, std::uint8_t key, std::uint32_t freq_q20);
  // Whether a frequency can be synthesised at this tick rate: above 0 and below Nyquist.
  bool frequency_ok(std::uint32_t freq_q20) const;
  // Advance every voice one tick; returns the mixed, limited sample in [−1, 1].
  float tick();
  void stop_all();

  std::uint8_t active_voices() const;
  const EngineCounters& counters() const { return counters_; }
  const Voice& voice(std::uint8_t i) const { return voices_[i]; }

 private:
  bool playable(const Note& note);  // counts a refusal
  Voice& take_voice();              // a free voice, or else the oldest (counted as stolen)

  SynthConfig cfg_;
  Polyphony policy_ = Polyphony::sum;
  Limiter limiter_;
  Voice voices_[kVoiceCount];
  envelope::Adsr slots_[envelope::kSlotCount]{};
  bool slot_used_[envelope::kSlotCount]{};
  std::uint32_t next_order_ = 0;
  EngineCounters counters_;
};

}  // namespace hmp::synth
