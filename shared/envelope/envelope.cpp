#include "shared/envelope/envelope.hpp"

#include <cmath>

#include "shared/common/text.hpp"
#include "shared/mapping/mapping.hpp"

namespace hmp::envelope {

namespace {

// Table 1 as SPEC §6 reads it: A, Dc, R in ms; s and r as fractions of the peak.
constexpr Adsr kBuiltins[kBuiltinCount] = {
    {5, 0, 25, 1.0f, 0.01f, Shape::adsr},          // organ
    {75, 0, 60, 1.0f, 0.01f, Shape::adsr},         // flute
    {55, 0, 55, 1.0f, 0.1739f, Shape::adsr},       // harpsichord
    {15, 0, 15, 1.0f, 0.0136f, Shape::adsr},       // guitar
    {30, 110, 100, 0.3209f, 0.01f, Shape::adsr},   // trumpet
    {66, 376, 225, 0.5714f, 0.01f, Shape::adsr},   // violin
    {40, 290, 200, 0.4745f, 0.01f, Shape::adsr},   // cello
    {55, 355, 225, 0.5274f, 0.01f, Shape::adsr},   // contrabass
    {0, 0, 0, 1.0f, 1.0f, Shape::adsr},            // square: the peak for the whole note
    {0, 0, 0, 0.0f, 1.0f, Shape::triangle},        // triangle: the peak falling linearly to 0 at D
    {0, 0, 0, 1.0f, static_cast<float>(mapping::kLegacyForceMin), Shape::damped},  // legacy2013
};

constexpr const char* kNames[kBuiltinCount] = {
    "organ", "flute", "harpsichord", "guitar", "trumpet", "violin",
    "cello", "contrabass", "square", "triangle", "legacy2013",
};

constexpr float kMaxDurationMs = 1e7f;

bool duration_ok(float ms) { return ms >= 0.0f && ms <= kMaxDurationMs; }  // false for NaN
bool fraction_ok(float v) { return v >= 0.0f && v <= 1.0f; }

double clamp_peak(float peak) {
  if (!(peak > 0.0f)) return 0.0;  // also NaN
  return peak < 1.0f ? static_cast<double>(peak) : 1.0;
}

// Slopes of phases far shorter than a tick can exceed float's range; they only ever multiply 0 then
// (such a phase holds a sample only at its very start), so saturating keeps 0·slope = 0 instead of NaN.
float saturate_to_float(double v) {
  constexpr double kMax = 3.4e38;
  return static_cast<float>(v > kMax ? kMax : (v < -kMax ? -kMax : v));
}

// First tick at or after the (fractional) tick position t, with 0 ≤ t ≤ N ≤ 2^32 − 1.
std::uint32_t first_tick_at_or_after(double t) { return static_cast<std::uint32_t>(std::ceil(t)); }

}  // namespace

const Adsr& builtin(Preset p) {
  const auto i = static_cast<std::uint8_t>(p);
  return kBuiltins[i < kBuiltinCount ? i : static_cast<std::uint8_t>(Preset::square)];
}

const char* name(Preset p) {
  const auto i = static_cast<std::uint8_t>(p);
  return i < kBuiltinCount ? kNames[i] : "unknown";
}

bool find_builtin(const char* wanted, Preset& out) {
  for (std::uint8_t i = 0; i < kBuiltinCount; ++i) {
    if (text::iequals(wanted, kNames[i])) {
      out = static_cast<Preset>(i);
      return true;
    }
  }
  return false;
}

bool valid(const Adsr& a) {
  return duration_ok(a.attack_ms) && duration_ok(a.decay_ms) && duration_ok(a.release_ms) &&
         fraction_ok(a.sustain) && fraction_ok(a.final_ratio) && static_cast<std::uint8_t>(a.shape) <= 2;
}

void Envelope::start(const Adsr& preset, float peak, std::uint32_t duration_ticks, float tick_hz,
                     float end_fade_ms) {
  const bool time_base_ok = std::isfinite(tick_hz) && tick_hz > 0.0f;
  const Adsr& p = (valid(preset) && time_base_ok) ? preset : builtin(Preset::square);
  const double ticks_per_ms = time_base_ok ? static_cast<double>(tick_hz) / 1000.0 : 0.0;

  n_end_ = duration_ticks == 0 ? 1 : duration_ticks;
  const double n = n_end_;
  const double a_h = clamp_peak(peak);

  double attack = static_cast<double>(p.attack_ms) * ticks_per_ms;
  double decay = static_cast<double>(p.decay_ms) * ticks_per_ms;
  double release = static_cast<double>(p.release_ms) * ticks_per_ms;
  if (p.shape != Shape::adsr) {  // the shape's one phase spans the whole note
    attack = 0;
    decay = p.shape == Shape::triangle ? n : 0.0;
    release = p.shape == Shape::damped ? n : 0.0;
  }
  // Short notes keep the proportions of the phases and drop the sustain (SPEC §6).
  const double phases = attack + decay + release;
  if (phases > n) {
    const double scale = n / phases;
    attack *= scale;
    decay *= scale;
    release *= scale;
  }
  // Rounding must not reorder the boundaries: 0 ≤ t1 ≤ t2 ≤ t3 ≤ N.
  const double t1 = std::fmin(attack, n);
  const double t2 = std::fmin(t1 + decay, n);
  const double t3 = std::fmax(n - release, t2);

  decay_first_ = first_tick_at_or_after(t1);
  sustain_first_ = first_tick_at_or_after(t2);
  release_first_ = first_tick_at_or_after(t3);
  decay_offset_ = static_cast<float>(static_cast<double>(decay_first_) - t1);
  release_offset_ = static_cast<float>(static_cast<double>(release_first_) - t3);

  const double level = p.shape == Shape::damped ? a_h : a_h * static_cast<double>(p.sustain);
  peak_ = static_cast<float>(a_h);
  sustain_level_ = static_cast<float>(level);
  attack_slope_ = t1 > 0.0 ? saturate_to_float(a_h / t1) : 0.0f;
  decay_slope_ = t2 > t1 ? saturate_to_float((level - a_h) / (t2 - t1)) : 0.0f;

  // r: Table 1's ratio, or for the damped shape the ratio that lands on the absolute end level.
  double ratio = p.final_ratio;
  if (p.shape == Shape::damped) ratio = level > 0.0 ? std::fmin(1.0, ratio / level) : 1.0;
  const double release_ticks = n - t3;
  release_zero_ = !(ratio > 0.0);
  release_log2_per_tick_ =
      (release_zero_ || release_ticks <= 0.0) ? 0.0f : saturate_to_float(std::log2(ratio) / release_ticks);

  const bool fade_ok = time_base_ok && std::isfinite(end_fade_ms) && end_fade_ms > 0.0f;
  const double fade_ticks = fade_ok ? std::fmin(static_cast<double>(end_fade_ms), 1e7) * ticks_per_ms : 0.0;
  fade_per_tick_ = fade_ticks > 0.0 ? saturate_to_float(1.0 / fade_ticks) : 0.0f;
}

float Envelope::at(std::uint32_t n) const {
  if (n >= n_end_) return 0.0f;
  float v;
  if (n < decay_first_) {
    v = static_cast<float>(n) * attack_slope_;
  } else if (n < sustain_first_) {
    const float into = static_cast<float>(n - decay_first_) + decay_offset_;
    v = peak_ + into * decay_slope_;
  } else if (n < release_first_) {
    v = sustain_level_;
  } else {
    const float into = static_cast<float>(n - release_first_) + release_offset_;
    if (release_zero_) {
      v = into == 0.0f ? sustain_level_ : 0.0f;  // exp(log(0)·…) is a step to 0 right after t3
    } else {
      v = sustain_level_ * std::exp2(into * release_log2_per_tick_);
    }
  }
  if (fade_per_tick_ > 0.0f) {
    const float fade = static_cast<float>(n_end_ - n) * fade_per_tick_;
    if (fade < 1.0f) v *= fade;
  }
  // Rounding of the products above may overshoot by an ulp; the contract is [0, peak].
  return v < 0.0f ? 0.0f : (v > peak_ ? peak_ : v);
}

}  // namespace hmp::envelope
