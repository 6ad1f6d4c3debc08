// `hmp tone` end to end: the CSV it prints matches the independent double-precision formula of design §6
// (reference_envelope.hpp) times sin(2π f x) to 1e-4 of full scale, for every built-in preset and for
// random --adsr values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "tests/support/reference_envelope.hpp"
#include "shared/envelope/envelope.hpp"

namespace {

struct Row {
  double t, v;
};

std::vector<Row> run_tone(const std::string& args, int* exit_code) {
  const std::string cmd = std::string(HMP_BIN_DIR) + "/hmp tone " + args + " --out - 2>/dev/null";
  std::FILE* p = popen(cmd.c_str(), "r");
  std::vector<Row> rows;
  if (!p) return rows;
  char line[256];
  bool header = true;
  while (std::fgets(line, sizeof line, p)) {
    if (header) {
      header = false;
      continue;
    }
    Row r{};
    if (std::sscanf(line, "%lf,%lf", &r.t, &r.v) == 2) rows.push_back(r);
  }
  const int status = pclose(p);
  *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return rows;
}

// Max |tone − reference| over the note; also checks the row count N = max(1, round(D/T)).
double max_error(const std::string& envelope_args, const hmp::envelope::Adsr& preset, double freq, double amp,
                 double ms, int tick_hz, double fade_ms) {
  int rc = -1;
  char args[512];
  std::snprintf(args, sizeof args, "--freq %.9g --amp %.9g --ms %.9g --tick-hz %d --end-fade-ms %.9g %s", freq, amp, ms,
                tick_hz, fade_ms, envelope_args.c_str());
  const auto rows = run_tone(args, &rc);
  EXPECT_EQ(rc, 0) << args;
  const double n_ticks = std::max(1.0, std::round(ms * tick_hz / 1000.0));
  EXPECT_EQ(rows.size(), static_cast<std::size_t>(n_ticks)) << args;
  const double d_ms = n_ticks * 1000.0 / tick_hz;
  double worst = 0;
  for (std::size_t n = 0; n < rows.size(); ++n) {
    const double x_ms = static_cast<double>(n) * 1000.0 / tick_hz;
    EXPECT_NEAR(rows[n].t, x_ms / 1000.0, 1e-9);
    const double ref = hmp::reference::envelope(preset, amp, d_ms, x_ms, fade_ms) *
                       std::sin(2 * std::numbers::pi * freq * x_ms / 1000.0);
    worst = std::max(worst, std::abs(rows[n].v - ref));
  }
  return worst;
}

TEST(ToneCli, EveryPresetMatchesSpecFormula) {
  for (std::uint8_t i = 0; i < hmp::envelope::kBuiltinCount; ++i) {
    const auto id = static_cast<hmp::envelope::Preset>(i);
    const std::string name = hmp::envelope::name(id);
    for (double ms : {0.4, 1.0, 7.0, 50.0, 333.0, 1500.0}) {
      for (int tick_hz : {1000, 10000}) {
        const double err = max_error("--instrument " + name, hmp::envelope::builtin(id), 173.3, 0.8, ms, tick_hz, 2.0);
        EXPECT_LE(err, 1e-4) << name << " " << ms << " ms at " << tick_hz << " Hz";
      }
    }
  }
}

TEST(ToneCli, PaperExactWithoutFade) {
  const double err = max_error("--instrument harpsichord", hmp::envelope::builtin(hmp::envelope::Preset::harpsichord),
                               250, 1.0, 400, 1000, 0.0);
  EXPECT_LE(err, 1e-4);
}

TEST(ToneCli, RandomAdsrMatchesSpecFormula) {
  std::mt19937 rng(20261121);
  std::uniform_real_distribution<double> ms(0, 400), pct(0, 100), u(0, 1);
  for (int k = 0; k < 60; ++k) {
    hmp::envelope::Adsr a;
    // Zeros are common in real presets: give each field a chance to be exactly 0 (or 100 %).
    a.attack_ms = static_cast<float>(u(rng) < 0.2 ? 0 : ms(rng));
    a.decay_ms = static_cast<float>(u(rng) < 0.2 ? 0 : ms(rng));
    a.release_ms = static_cast<float>(u(rng) < 0.2 ? 0 : ms(rng));
    const double s = u(rng) < 0.15 ? 0 : u(rng) < 0.15 ? 100 : pct(rng);
    const double r = u(rng) < 0.15 ? 0 : u(rng) < 0.15 ? 100 : pct(rng);
    char spec[256];
    std::snprintf(spec, sizeof spec, "--adsr attack=%.9g,decay=%.9g,sustain=%.9g,release=%.9g,final=%.9g",
                  static_cast<double>(a.attack_ms), static_cast<double>(a.decay_ms), s,
                  static_cast<double>(a.release_ms), r);
    a.sustain = static_cast<float>(s / 100);
    a.final_ratio = static_cast<float>(r / 100);
    const double duration = u(rng) < 0.3 ? 5 * u(rng) : 1500 * u(rng);
    const double freq = 20 + 400 * u(rng);
    const double amp = 0.01 + 0.99 * u(rng);
    const double err = max_error(spec, a, freq, amp, duration, 1000, u(rng) < 0.5 ? 0.0 : 2.0);
    EXPECT_LE(err, 1e-4) << spec << " D=" << duration << " f=" << freq << " a=" << amp;
  }
}

}  // namespace
