#include "shared/synth/frequency.hpp"

namespace hmp::synth {

std::uint32_t freq_to_q20(double hz) {
  if (!(hz > 0.0)) return 0;  // also catches NaN
  // hz · 2^20 is exact (a power-of-two scale); anything at or above the top LSB's rounding edge saturates.
  const double scaled = hz * static_cast<double>(1u << kFreqFracBits);
  if (scaled >= 4294967295.5) return 0xFFFFFFFFu;
  auto q = static_cast<std::uint32_t>(scaled);  // truncation; the remainder below is exact in double
  if (scaled - static_cast<double>(q) >= 0.5) ++q;
  return q;
}

// floor(f · 2^44 / fs) by long division in two 32-bit digits, so it needs only 64-bit arithmetic
// (the firmware has no 128-bit integers). With a = f · 2^12 (< 2^44) and fs < 2^32:
//   a = q1·fs + r1  ⇒  f · 2^44 = q1·fs·2^32 + r1·2^32,  and r1·2^32 < 2^64,
// so the quotient is q1·2^32 + floor(r1·2^32 / fs). The result is taken mod 2^64: for f ≥ fs the
// increment wraps, which is exactly the alias the sampled sine has anyway (one turn = 2^64).
std::uint64_t phase_increment(std::uint32_t freq_q20, std::uint32_t tick_hz) {
  if (tick_hz == 0) return 0;
  const std::uint64_t a = static_cast<std::uint64_t>(freq_q20) << (44 - 32);
  const std::uint64_t q1 = a / tick_hz;
  const std::uint64_t r1 = a % tick_hz;
  const std::uint64_t q2 = (r1 << 32) / tick_hz;
  return (q1 << 32) + q2;
}

std::uint16_t amp_to_q16(double amplitude) {
  if (!(amplitude > 0.0)) return 0;  // also catches NaN
  if (amplitude >= 1.0) return 0xFFFFu;
  return static_cast<std::uint16_t>(amplitude * kAmpFullScale + 0.5);
}

}  // namespace hmp::synth
