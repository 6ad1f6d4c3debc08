#include "shared/envelope/envelope.hpp"

#include <cmath>

#include "shared/common/text.hpp"
#include "shared/mapping/mapping.hpp"

namespace hmp::envelope {

namespace {

// The built-in presets, one row each: its enum value (= its slot on the wire), its name and its ADSR.
// Adding a preset is a new Preset value before `count` and its row here, in the same place.
// Table 1 as design §6 reads it: A, Dc, R in ms; s and r as fractions of the peak.
struct BuiltinRow {
  Preset preset;
  const char* name;
  Adsr adsr;
};
constexpr BuiltinRow kBuiltins[] = {
    {Preset::organ, "organ", {5, 0, 25, 1.0f, 0.01f, Shape::adsr}},
    {Preset::flute, "flute", {75, 0, 60, 1.0f, 0.01f, Shape::adsr}},
    {Preset::harpsichord, "harpsichord", {55, 0, 55, 1.0f, 0.1739f, Shape::adsr}},
    {Preset::guitar, "guitar", {15, 0, 15, 1.0f, 0.0136f, Shape::adsr}},
    {Preset::trumpet, "trumpet", {30, 110, 100, 0.3209f, 0.01f, Shape::adsr}},
    {Preset::violin, "violin", {66, 376, 225, 0.5714f, 0.01f, Shape::adsr}},
    {Preset::cello, "cello", {40, 290, 200, 0.4745f, 0.01f, Shape::adsr}},
    {Preset::contrabass, "contrabass", {55, 355, 225, 0.5274f, 0.01f, Shape::adsr}},
    // square: the peak for the whole note
    {Preset::square, "square", {0, 0, 0, 1.0f, 1.0f, Shape::adsr}},
    // triangle: the peak falling linearly to 0 at D
    {Preset::triangle, "triangle", {0, 0, 0, 0.0f, 1.0f, Shape::triangle}},
    {Preset::legacy2013, "legacy2013", {0, 0, 0, 1.0f, static_cast<float>(mapping::kLegacyForceMin), Shape::damped}},
};

// builtin() and name() index the table by the enum value, and the firmware's slots are those values:
// the table must hold one row per Preset, in the enum's order.
constexpr bool rows_follow_enum() {
  if (sizeof kBuiltins / sizeof kBuiltins[0] != kBuiltinCount) return false;
  for (std::uint8_t i = 0; i < kBuiltinCount; ++i) {
    if (static_cast<std::uint8_t>(kBuiltins[i].preset) != i) return false;
  }
  return true;
}
static_assert(rows_follow_enum(), "kBuiltins needs one row per envelope::Preset, in the enum's order");

constexpr float kMaxDurationMs = 1e7f;

bool duration_ok(float ms) { return ms >= 0.0f && ms <= kMaxDurationMs; }  // false for NaN
bool fraction_ok(float v) { return v >= 0.0f && v <= 1.0f; }

float clamp_peak(float peak) {
  if (!(peak > 0.0f)) return 0.0f;  // also NaN
  return peak < 1.0f ? peak : 1.0f;
}
// A per-tick rate num / den. Rates of phases far shorter than a tick can exceed float's range; they only
// ever multiply 0 then (such a phase holds a sample only at its very start), so saturating keeps
// 0·rate = 0 instead of NaN; 0 / anything is 0.
float rate(float num, float den) {
  if (num == 0.0f) return 0.0f;
  constexpr float kMax = 3.4e38f;
  if (den == 0.0f) return num > 0.0f ? kMax : -kMax;  // a phase too short for a float (a 1e-45 ms attack)
  const float q = num / den;
  return q > kMax ? kMax : (q < -kMax ? -kMax : q);
}

// First tick at or after the (fractional) tick position t, with 0 ≤ t ≤ N ≤ 2^32 − 1.
std::uint32_t first_tick_at_or_after(double t) { return static_cast<std::uint32_t>(std::ceil(t)); }

// The first tick whose end-fade factor (N − n)·(1/F) is below 1: found with at()'s own float product, so
// that at() needs only an integer comparison per tick. N when there is no fade.
std::uint32_t fade_first_tick(std::uint32_t n_end, float fade_per_tick) {
  if (!(fade_per_tick > 0.0f)) return n_end;
  const float k_max = 1.0f / fade_per_tick + 2.0f;
  auto k = k_max < static_cast<float>(n_end) ? static_cast<std::uint32_t>(k_max) : n_end;
  while (k > 0 && !(static_cast<float>(k) * fade_per_tick < 1.0f)) --k;
  return n_end - k;
}
}  // namespace

const Adsr& builtin(Preset p) {
  const auto i = static_cast<std::uint8_t>(p);
  return kBuiltins[i < kBuiltinCount ? i : static_cast<std::uint8_t>(Preset::square)].adsr;
}

const char* name(Preset p) {
  const auto i = static_cast<std::uint8_t>(p);
  return i < kBuiltinCount ? kBuiltins[i].name : "unknown";
}

bool find_builtin(const char* wanted, Preset& out) {
  for (const BuiltinRow& row : kBuiltins) {
    if (text::iequals(wanted, row.name)) {
      out = row.preset;
      return true;
    }
  }
  return false;
}

bool valid(const Adsr& a) {
  return duration_ok(a.attack_ms) && duration_ok(a.decay_ms) && duration_ok(a.release_ms) && fraction_ok(a.sustain) &&
         fraction_ok(a.final_ratio) && static_cast<std::uint8_t>(a.shape) <= 2;
}

void Envelope::start(const Adsr& preset, float peak, std::uint32_t duration_ticks, float tick_hz, float end_fade_ms) {
  const bool time_base_ok = std::isfinite(tick_hz) && tick_hz > 0.0f;
  const Adsr& p = (valid(preset) && time_base_ok) ? preset : builtin(Preset::square);
  const double ticks_per_ms = time_base_ok ? static_cast<double>(tick_hz) / 1000.0 : 0.0;

  held_ = false;
  n_end_ = duration_ticks == 0 ? 1 : duration_ticks;
  const double n = n_end_;
  peak_ = clamp_peak(peak);
  sustain_level_ = p.shape == Shape::damped ? peak_ : peak_ * p.sustain;  // ≤ peak_: sustain ≤ 1

  // The phase boundaries in double: they must stay exact to a small fraction of a tick for notes and
  // phases of hours, and a boundary that moves by a rounding error can move a step (decay 0, s < 1).
  double attack = static_cast<double>(p.attack_ms) * ticks_per_ms;
  double decay = static_cast<double>(p.decay_ms) * ticks_per_ms;
  double release = static_cast<double>(p.release_ms) * ticks_per_ms;
  if (p.shape != Shape::adsr) {  // the shape's one phase spans the whole note
    attack = 0;
    decay = p.shape == Shape::triangle ? n : 0.0;
    release = p.shape == Shape::damped ? n : 0.0;
  }
  // Short notes keep the proportions of the phases and drop the sustain (design §6).
  const double phases = attack + decay + release;
  if (phases > n) {
    const double scale = n / phases;
    attack *= scale;
    decay *= scale;
    release *= scale;
  }
  // Rounding must not reorder the boundaries: 0 ≤ t1 ≤ t2 ≤ t3 ≤ N.
  const double t1 = attack < n ? attack : n;
  const double t2 = t1 + decay < n ? t1 + decay : n;
  const double t3 = n - release > t2 ? n - release : t2;

  decay_first_ = first_tick_at_or_after(t1);
  sustain_first_ = first_tick_at_or_after(t2);
  release_first_ = first_tick_at_or_after(t3);
  decay_offset_ = static_cast<float>(static_cast<double>(decay_first_) - t1);
  release_offset_ = static_cast<float>(static_cast<double>(release_first_) - t3);

  // The per-tick rates are floats: worked out in float from the boundaries (start() runs on the tick that
  // starts the note, and double is a software library on the Cortex-M4F). Each is within 2 ulp of its
  // value in double, a relative error the envelope inherits; the boundaries themselves are unaffected.
  const auto span = [](double from, double to) { return static_cast<float>(to - from); };
  attack_slope_ = t1 > 0.0 ? rate(peak_, span(0.0, t1)) : 0.0f;
  decay_slope_ = t2 > t1 ? rate(sustain_level_ - peak_, span(t1, t2)) : 0.0f;

  // r: Table 1's ratio, or for the damped shape the ratio that lands on the absolute end level.
  float ratio = p.final_ratio;
  if (p.shape == Shape::damped) ratio = sustain_level_ > 0.0f ? std::fmin(1.0f, ratio / sustain_level_) : 1.0f;
  const float release_ticks = span(t3, n);
  release_zero_ = !(ratio > 0.0f);
  release_log2_per_tick_ = (release_zero_ || release_ticks <= 0.0f) ? 0.0f : rate(std::log2(ratio), release_ticks);

  const bool fade_ok = time_base_ok && std::isfinite(end_fade_ms) && end_fade_ms > 0.0f;
  const float fade_ticks = fade_ok ? std::fmin(end_fade_ms, 1e7f) * static_cast<float>(ticks_per_ms) : 0.0f;
  fade_per_tick_ = fade_ticks > 0.0f ? rate(1.0f, fade_ticks) : 0.0f;
  // at() multiplies by the fade factor (N − n)·(1/F) where it is below 1: the ticks from fade_first_ on.
  fade_first_ = fade_first_tick(n_end_, fade_per_tick_);
  // In double and clamped: the float span rounds up to 2^32 for N near 2^32, beyond a uint32.
  const double held_release = std::ceil(std::fmax(n - t3, static_cast<double>(fade_ticks)));
  release_ticks_ = held_release < 4294967295.0 ? static_cast<std::uint32_t>(held_release) : 0xFFFFFFFFu;
}

void Envelope::start_held(const Adsr& preset, float peak, float tick_hz, float end_fade_ms) {
  Adsr held = valid(preset) ? preset : builtin(Preset::square);
  if (held.shape != Shape::adsr) held = builtin(Preset::square);
  // A scheduled note as long as N can be: the same phases, its release at the far end, out of reach
  // until release_at() moves it.
  start(held, peak, kHeldTicks, tick_hz, end_fade_ms);
  held_ = true;
}

std::uint32_t Envelope::release_at(std::uint32_t n) {
  if (!held_ || n >= n_end_) return n_end_;
  held_ = false;
  // The release goes on from the level this tick would have had; the decay and sustain are over.
  sustain_level_ = at_within(n);
  release_first_ = n;
  release_offset_ = 0.0f;
  const std::uint32_t room = n_end_ - n;
  n_end_ = n + (release_ticks_ < room ? (release_ticks_ > 0 ? release_ticks_ : 1) : room);
  fade_first_ = fade_first_tick(n_end_, fade_per_tick_);
  return n_end_;
}

// Envelope::at() is inline in envelope.hpp: it runs for every voice on every tick.

}  // namespace hmp::envelope
