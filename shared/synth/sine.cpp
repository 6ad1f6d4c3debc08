#include "shared/synth/sine.hpp"

#include <cmath>
#include <numbers>

namespace hmp::synth {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kTurnToRad = static_cast<float>(2.0 * kPi / 4294967296.0);  // 2π / 2^32

// ---- table -------------------------------------------------------------------------------------------
// 1024 intervals per turn: linear interpolation errs by at most (2π/1024)²/8 ≈ 4.7e-6.
constexpr unsigned kTableBits = 10;
constexpr unsigned kTableSize = 1u << kTableBits;
constexpr unsigned kFracBits = 32 - kTableBits;

// sin(2π k / kTableSize), evaluated by the compiler (std::sin is not constexpr everywhere): fold k into
// [−¼, ¼] turn with exact integer symmetries, then a Taylor series that converges to double precision there.
constexpr double sine_of_table_step(int k) {
  const int quarter = static_cast<int>(kTableSize / 4);
  if (k > quarter && k <= 3 * quarter)
    k = 2 * quarter - k;  // sin(π − x) = sin(x)
  else if (k > 3 * quarter)
    k -= 4 * quarter;  // sin(x − 2π) = sin(x)
  const double x = 2.0 * kPi * k / kTableSize;
  double term = x, sum = x;
  for (int i = 1; i < 30; ++i) {
    term *= -x * x / ((2 * i) * (2 * i + 1));
    sum += term;
  }
  return sum;
}

struct SineTable {
  float v[kTableSize + 1];  // one guard entry (= v[0]) so interpolation never wraps
};

constexpr SineTable make_table() {
  SineTable t{};
  for (unsigned k = 0; k <= kTableSize; ++k) t.v[k] = static_cast<float>(sine_of_table_step(static_cast<int>(k)));
  return t;
}

// constexpr at namespace scope: computed at compile time and placed in read-only data (flash).
constexpr SineTable kTable = make_table();
static_assert(kTable.v[0] == 0.0f && kTable.v[kTableSize / 4] == 1.0f && kTable.v[kTableSize] == 0.0f);

// ---- polynomial --------------------------------------------------------------------------------------
// sin(π/2 · x) on x ∈ [−1, 1] by an odd degree-7 minimax polynomial. Coefficients from
// tools/bench/fit_sine_poly.py (Remez exchange on max |error|, then rounded to float):
// max |error| 6.0e-7 with these float coefficients in exact arithmetic, 7.4e-7 evaluated in float.
constexpr float kC1 = 1.570791006e+00f;
constexpr float kC3 = -6.458928585e-01f;
constexpr float kC5 = 7.943434268e-02f;
constexpr float kC7 = -4.333095159e-03f;

}  // namespace

const char* name(SineImpl s) {
  switch (s) {
    case SineImpl::libm: return "libm";
    case SineImpl::table: return "table";
    case SineImpl::poly: return "poly";
  }
  return "?";
}

float sine_libm(std::uint32_t phase) {
  // As a signed number the phase is in [−½, ½) turn, i.e. [−π, π): sinf's most accurate range.
  return std::sin(static_cast<float>(static_cast<std::int32_t>(phase)) * kTurnToRad);
}

float sine_table(std::uint32_t phase) {
  const std::uint32_t i = phase >> kFracBits;
  const float frac = static_cast<float>(phase & ((1u << kFracBits) - 1)) * (1.0f / (1u << kFracBits));
  const float a = kTable.v[i];
  return a + (kTable.v[i + 1] - a) * frac;
}

float sine_poly(std::uint32_t phase) {
  // Quadrant folding: phases within ¼ turn of ½ turn mirror onto [−¼, ¼] by sin(½ − t) = sin(t).
  // 2^31 − phase (mod 2^32) does it for both the second and the third quadrant.
  if ((phase + 0x40000000u) & 0x80000000u) phase = 0x80000000u - phase;
  const float x = static_cast<float>(static_cast<std::int32_t>(phase)) * (1.0f / 1073741824.0f);  // / 2^30
  const float x2 = x * x;
  return x * (kC1 + x2 * (kC3 + x2 * (kC5 + x2 * kC7)));
}

float sine(SineImpl impl, std::uint32_t phase) {
  switch (impl) {
    case SineImpl::libm: return sine_libm(phase);
    case SineImpl::table: return sine_table(phase);
    case SineImpl::poly: return sine_poly(phase);
  }
  return 0.0f;
}

}  // namespace hmp::synth
