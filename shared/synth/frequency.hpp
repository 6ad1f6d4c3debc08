#pragma once
// How the device represents a frequency (design §7, §9).
//
// On the wire: unsigned Q12.20 Hz in 32 bits (LSB 2^-20 Hz ≈ 9.5e-7 Hz, top 4095.999999 Hz). Rounding
// to the nearest LSB errs by ≤ 4.8e-7 Hz, i.e. ≤ 3.0e-5 rad of phase over a 10 s note.
// In the voice: a 64-bit phase accumulator in turns (2^64 = one turn) advanced by
// inc = f_q20 · 2^44 / tick_hz per tick, computed by exact long division; its truncation error
// (< 2^-64 turn per tick) is negligible, and integer wrap-around makes the phase drift-free for hours.
#include <cstdint>

namespace hmp::synth {

inline constexpr unsigned kFreqFracBits = 20;
inline constexpr double kFreqLsbHz = 1.0 / (1u << kFreqFracBits);
inline constexpr double kFreqMaxHz = 4096.0 - kFreqLsbHz;

// Nearest representable frequency; NaN/negative → 0, above the top → the top.
std::uint32_t freq_to_q20(double hz);
inline double q20_to_hz(std::uint32_t q) { return static_cast<double>(q) * kFreqLsbHz; }

// Phase increment per tick in 2^-64 turns. tick_hz must be > 0 (0 yields 0).
std::uint64_t phase_increment(std::uint32_t freq_q20, std::uint32_t tick_hz);

// Amplitude on the wire: u16, 65535 = full scale 1.0.
inline constexpr double kAmpFullScale = 65535.0;
std::uint16_t amp_to_q16(double amplitude);  // clamps to [0, 1]; NaN → 0
inline float q16_to_amp(std::uint16_t q) { return static_cast<float>(q) * (1.0f / 65535.0f); }

}  // namespace hmp::synth
