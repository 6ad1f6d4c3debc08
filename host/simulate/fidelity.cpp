// fidelity: the RMS ratio and delay of a recorded force against the commanded one (fidelity.hpp).
#include "host/simulate/fidelity.hpp"

#include <algorithm>
#include <cmath>

namespace hmp::simulate {

Fidelity measure_fidelity(const std::vector<ForceSample>& s, std::uint32_t tick_hz, double peak) {
  Fidelity f;
  constexpr int kMaxLag = 3;  // the device delays by ~1.3 ticks; a vibration period can be as short as 4
  double corr[kMaxLag + 1] = {};
  int best = 0;
  for (int lag = 0; lag <= kMaxLag; ++lag) {
    for (std::size_t i = 0; i + static_cast<std::size_t>(lag) < s.size(); ++i) {
      corr[lag] +=
          static_cast<double>(s[i + static_cast<std::size_t>(lag)].actual) * static_cast<double>(s[i].commanded);
    }
    if (corr[lag] > corr[best]) best = lag;
  }
  f.lag_ticks = best;
  if (best > 0 && best < kMaxLag) {
    const double l = corr[best - 1], m = corr[best], r = corr[best + 1];
    const double d = l - 2 * m + r;
    if (d < 0) f.lag_ticks += 0.5 * (l - r) / d;
  }
  // Windows of the actual force taken that many whole ticks later, so that note onsets line up.
  const auto shift = static_cast<std::size_t>(std::lround(f.lag_ticks));
  const std::size_t w = std::max<std::size_t>(1, tick_hz / 50);
  for (std::size_t a = 0; a + w + shift <= s.size(); a += w) {
    double c = 0, x = 0;
    for (std::size_t i = a; i < a + w; ++i) {
      c += static_cast<double>(s[i].commanded) * static_cast<double>(s[i].commanded);
      x += static_cast<double>(s[i + shift].actual) * static_cast<double>(s[i + shift].actual);
    }
    c = std::sqrt(c / static_cast<double>(w));
    x = std::sqrt(x / static_cast<double>(w));
    if (c < 0.05 * peak) continue;
    const double e = std::fabs(x / c - 1.0);
    ++f.windows;
    f.mean_ratio_error += e;
    f.worst_ratio_error = std::max(f.worst_ratio_error, e);
  }
  if (f.windows > 0) f.mean_ratio_error /= static_cast<double>(f.windows);
  return f;
}

}  // namespace hmp::simulate
