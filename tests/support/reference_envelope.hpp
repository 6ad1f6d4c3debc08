#pragma once
// Independent double-precision reference of design §6 envelopes, written from the spec text (not from
// shared/envelope/envelope.cpp) so tests and benchmarks can check the float implementation against it.
// Times are in ms: x from the note's start, D the note's duration (N·T), fade F (0 = none).
#include <algorithm>
#include <cmath>

#include "shared/envelope/envelope.hpp"

namespace hmp::reference {

// E(x) in [0, peak]; 0 outside [0, D).
inline double envelope(const envelope::Adsr& p, double peak, double d_ms, double x_ms, double fade_ms) {
  if (!(x_ms >= 0.0) || !(x_ms < d_ms)) return 0.0;
  const auto d = [](float v) { return static_cast<double>(v); };
  double e = peak;
  switch (p.shape) {
    case envelope::Shape::triangle:  // peak at the start, linearly to S at D
      e = peak + (d(p.sustain) * peak - peak) * x_ms / d_ms;
      break;
    case envelope::Shape::damped: {  // peak · (end/peak)^(x/D), end an absolute level ≤ peak
      const double end = std::min(d(p.final_ratio), peak);
      e = end <= 0.0 ? (x_ms == 0.0 ? peak : 0.0) : peak * std::pow(end / peak, x_ms / d_ms);
      break;
    }
    case envelope::Shape::adsr: {
      double a = d(p.attack_ms), dc = d(p.decay_ms), r = d(p.release_ms);
      const double total = a + dc + r;
      if (total > d_ms) {  // short note: squeeze the three phases into D, no sustain
        a *= d_ms / total;
        dc *= d_ms / total;
        r *= d_ms / total;
      }
      const double s = d(p.sustain) * peak;
      if (x_ms < a) {
        e = peak * x_ms / a;
      } else if (x_ms < a + dc) {
        e = peak + (s - peak) * (x_ms - a) / dc;
      } else if (x_ms < d_ms - r) {
        e = s;
      } else {                                     // exponential release from the sustain level to r·s at D
        const double u = (x_ms - (d_ms - r)) / r;  // in [0, 1)
        e = p.final_ratio <= 0.0f ? (u == 0.0 ? s : 0.0) : s * std::pow(d(p.final_ratio), u);
      }
      break;
    }
  }
  if (fade_ms > 0.0) e *= std::min(1.0, (d_ms - x_ms) / fade_ms);
  return e;
}

}  // namespace hmp::reference
