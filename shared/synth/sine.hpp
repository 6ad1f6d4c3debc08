#pragma once
// sin(2π·phase) for a phase given as a fraction of a turn in 32 bits (2^32 = one turn).
// Three implementations, compared for error and speed by `scripts/bench synth-accuracy`
// (docs/performance.md); kDefaultSine is the one the voices use.
#include <cstdint>

namespace hmp::synth {

enum class SineImpl : std::uint8_t { libm, table, poly };
const char* name(SineImpl s);

float sine_libm(std::uint32_t phase);   // sinf() on the phase mapped to [−π, π)
float sine_table(std::uint32_t phase);  // 1024-entry table + linear interpolation
float sine_poly(std::uint32_t phase);   // quadrant folding + odd minimax polynomial

float sine(SineImpl impl, std::uint32_t phase);

inline constexpr SineImpl kDefaultSine = SineImpl::table;  // chosen from the benchmark table

}  // namespace hmp::synth
