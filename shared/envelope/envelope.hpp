#pragma once
// ADSR envelopes of design §6 (paper Eq. 9–10, Table 1), evaluated per device tick.
//
// Time is in ticks n = 0 … N−1 from the note's start; x = n·T with T = 1/tick_hz. The note lasts D = N·T.
// Phases: attack 0→a over [0, A); decay a→S over [A, A+Dc); sustain S until D−R; release exponential
// from S to r·S at D (Eq. 10's exp(log(r)·…) form, computed without log(0)). Short notes
// (A+Dc+R > D) scale A, Dc, R by D/(A+Dc+R). Optional end fade multiplies by min(1, (D−x)/F).
#include <cstdint>

namespace hmp::envelope {

// How the phases relate to the note's duration D.
enum class Shape : std::uint8_t {
  adsr = 0,      // durations as given (Table 1 presets, square, user presets)
  triangle = 1,  // the whole note is the decay: a at the start falling linearly to S (0 for the preset) at D;
                 // attack_ms, decay_ms and release_ms are ignored
  damped = 2,    // 2013 paper: the whole note is the release, from a at x = 0 to the absolute end level
                 // final_ratio at D (r = min(1, final_ratio/a)); durations and sustain are ignored
};

struct Adsr {
  float attack_ms = 0;
  float decay_ms = 0;
  float release_ms = 0;
  float sustain = 1;      // S as a fraction of the peak a (Table 1's s / 100)
  float final_ratio = 1;  // r (Table 1's r / 100); for Shape::damped: the end level in full-scale units
  Shape shape = Shape::adsr;
};

// Built-in presets: Table 1 and the two simple envelopes of the paper's experiment, plus legacy2013.
// The value is the preset's slot on the wire; its name and ADSR are its row in envelope.cpp's table
// (a static_assert there keeps the rows in this order). The GM → preset `auto` table is gm_auto.hpp.
enum class Preset : std::uint8_t {
  organ,
  flute,
  harpsichord,
  guitar,
  trumpet,
  violin,
  cello,
  contrabass,
  square,
  triangle,
  legacy2013,
  count
};
inline constexpr std::uint8_t kBuiltinCount = static_cast<std::uint8_t>(Preset::count);
// Slot ids on the wire: 0 … kBuiltinCount−1 built-in; kFirstUserSlot … kSlotCount−1 uploaded by the host.
inline constexpr std::uint8_t kFirstUserSlot = 16;
inline constexpr std::uint8_t kSlotCount = 32;

const Adsr& builtin(Preset p);
const char* name(Preset p);
// Case-insensitive lookup of a built-in preset name; false if unknown.
bool find_builtin(const char* name, Preset& out);

// A preset is usable when every field is finite and in range: durations ≥ 0 and ≤ 1e7 ms,
// sustain and final_ratio in [0, 1], shape known.
bool valid(const Adsr& a);

namespace detail {
// 2^x for x ≤ 0 in float, for the release (every voice, every tick of a release: newlib's exp2f goes
// through powf, ~150 instructions on the Cortex-M4F; this is ~25). x = i + f, i the nearest integer and
// f in [−½, ½]; 2^f by a degree-6 polynomial whose constant term is exactly 1 (so 2^0 is exactly 1),
// fitted for the least maximal relative error (tools/bench/firmware-tick-exp2-fit.py: 2.0e-9 exactly,
// 8.5e-8 evaluated in float, under one ulp); 2^i goes straight into the exponent bits.
inline float release_exp2(float x) {
  if (!(x > -126.0f)) return 0.0f;  // below float's normal range (or NaN): the release has reached 0
  if (x > 0.0f) x = 0.0f;           // not reached: log2(r) ≤ 0
  const auto i = -static_cast<std::int32_t>(0.5f - x);  // round(x) for x ≤ 0
  const float f = x - static_cast<float>(i);
  constexpr float c1 = 6.931471825e-01f, c2 = 2.402264774e-01f, c3 = 5.550332367e-02f;
  constexpr float c4 = 9.618436918e-03f, c5 = 1.339888084e-03f, c6 = 1.535337797e-04f;
  const float p = 1.0f + f * (c1 + f * (c2 + f * (c3 + f * (c4 + f * (c5 + f * c6)))));
  const auto scale_bits = static_cast<std::uint32_t>(i + 127) << 23;
  float scale;
  __builtin_memcpy(&scale, &scale_bits, sizeof scale);
  return p * scale;
}
}  // namespace detail

// The evaluator of one note's envelope. start() precomputes everything so that at() is cheap
// (it runs for every voice on every tick, so it is defined inline below).
class Envelope {
 public:
  // peak: a_h, linear in (0, 1] (clamped there; NaN → 0). duration_ticks: N (0 is treated as 1: a note is
  // never silent). end_fade_ms: F ≥ 0 (0 = paper-exact; NaN, negative or infinite → 0; capped at 1e7).
  // Invalid presets, and a tick_hz that is not finite and > 0, fall back to square (without fade).
  // start() works in double (once per note, not per tick: a few µs of soft-float on a Cortex-M4F).
  void start(const Adsr& preset, float peak, std::uint32_t duration_ticks, float tick_hz, float end_fade_ms);
  // A held note (live input, its end not known yet): the preset's attack and decay as given (no short-note
  // scaling), then its sustain until release_at(); `triangle` and `damped`, whose one phase spans the
  // whole note, hold the peak. N is kHeldTicks until the release.
  void start_held(const Adsr& preset, float peak, float tick_hz, float end_fade_ms);
  // The release of a held note from tick n on: from the level E(n) it has then, whatever its phase, down
  // to r·E(n) over R as the preset's release does (Eq. 10), the end fade over the last F ms; the note now
  // ends at n + max(R, F) ticks. Returns the new N. A note that is not held keeps its N.
  std::uint32_t release_at(std::uint32_t n);
  bool held() const { return held_; }
  static constexpr std::uint32_t kHeldTicks = 0xFFFFFFFFu;
  // E at tick n, in [0, peak]; 0 for n ≥ N.
  float at(std::uint32_t n) const { return n < n_end_ ? at_within(n) : 0.0f; }
  // The same for a caller that knows n < N (a voice checks it anyway): one comparison less per tick.
  float at_within(std::uint32_t n) const;
  std::uint32_t duration_ticks() const { return n_end_; }

 private:
  // start() works out the phase boundaries t1 ≤ t2 ≤ t3 ≤ N (in ticks, fractional) in double, then keeps
  // only what at() needs in a form that stays exact for notes of hours: the first tick of each later phase
  // as an integer (n < t ⟺ n < ceil(t)), and the fraction ceil(t) − t, so that the time into a phase is
  // (integer tick difference) + (small fraction) and never a difference of two large floats.
  std::uint32_t n_end_ = 1;          // N
  std::uint32_t decay_first_ = 0;    // ceil(t1): first tick after the attack
  std::uint32_t sustain_first_ = 0;  // ceil(t2)
  std::uint32_t release_first_ = 1;  // ceil(t3); = N when there is no release
  float decay_offset_ = 0;           // ceil(t1) − t1, in [0, 1)
  float release_offset_ = 0;         // ceil(t3) − t3, in [0, 1)
  float peak_ = 0, sustain_level_ = 0;
  float attack_slope_ = 0, decay_slope_ = 0;  // per tick
  float release_log2_per_tick_ = 0;           // log2(r)/R in ticks; r = 0 handled by release_zero_
  float fade_per_tick_ = 0;                   // 1/F in ticks; 0 = no end fade
  std::uint32_t fade_first_ = 1;              // first tick whose end-fade factor is below 1 (N: none)
  bool release_zero_ = false;
  bool held_ = false;
  std::uint32_t release_ticks_ = 0;  // a held note's release and end fade, max(R, F), in whole ticks
};

inline float Envelope::at_within(std::uint32_t n) const {
  // Later phases first: the sustain (the most common tick) returns after three comparisons, without
  // the clamp (0 ≤ S ≤ peak by construction).
  float v;
  if (n >= release_first_) {
    const float into = static_cast<float>(n - release_first_) + release_offset_;
    if (release_zero_) {
      v = into == 0.0f ? sustain_level_ : 0.0f;  // exp(log(0)·…) is a step to 0 right after t3
    } else {
      v = sustain_level_ * detail::release_exp2(into * release_log2_per_tick_);
    }
  } else if (n >= sustain_first_) {
    if (n < fade_first_) return sustain_level_;
    v = sustain_level_;
  } else if (n >= decay_first_) {
    const float into = static_cast<float>(n - decay_first_) + decay_offset_;
    v = peak_ + into * decay_slope_;
  } else {
    v = static_cast<float>(n) * attack_slope_;
  }
  if (n >= fade_first_) v *= static_cast<float>(n_end_ - n) * fade_per_tick_;
  // Rounding of the products above may overshoot by an ulp; the contract is [0, peak].
  return v < 0.0f ? 0.0f : (v > peak_ ? peak_ : v);
}

}  // namespace hmp::envelope
