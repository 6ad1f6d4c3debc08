// One voice against the double-precision reference of design §6: y[n] = E(nT)·sin(2π f nT) for the
// frequency the device represents, with the envelope written independently in reference_envelope.hpp.
#include "shared/synth/voice.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include "shared/synth/frequency.hpp"
#include "tests/support/reference_envelope.hpp"

namespace {

using namespace hmp;
using synth::SineImpl;

constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kBudget = 2e-5;  // design §7: max |error| over a 10-minute note, in full-scale units

synth::Note make_note(double hz, double amp, std::uint32_t ticks) {
  synth::Note n;
  n.freq_q20 = synth::freq_to_q20(hz);
  n.amp_q16 = synth::amp_to_q16(amp);
  n.duration_ticks = ticks;
  return n;
}

// Plays the whole note and returns the largest distance to the reference.
double max_error(const synth::Note& note, envelope::Preset preset, const synth::SynthConfig& cfg) {
  const envelope::Adsr& adsr = envelope::builtin(preset);
  const double f = synth::q20_to_hz(note.freq_q20);
  const double peak = note.amp_q16 / 65535.0;
  const double tick_ms = 1000.0 / cfg.tick_hz;
  const double d_ms = note.duration_ticks * tick_ms;
  synth::Voice v;
  v.start(note, adsr, cfg, 0);
  double worst = 0.0;
  for (std::uint32_t n = 0; n < note.duration_ticks; ++n) {
    EXPECT_TRUE(v.active());
    const double x_ms = n * tick_ms;
    const double expected = reference::envelope(adsr, peak, d_ms, x_ms, static_cast<double>(cfg.end_fade_ms)) *
                            std::sin(kTwoPi * f * x_ms / 1000.0);
    worst = std::max(worst, std::fabs(static_cast<double>(v.next()) - expected));
  }
  EXPECT_FALSE(v.active());
  return worst;
}

// Every sine implementation, a sustained and a decaying preset, random frequency and full amplitude
// (where the error is largest), 10 minutes at the default 1 kHz.
TEST(Voice, TenMinuteNoteWithinBudgetForEverySine) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> hz(20.0, 450.0);
  for (SineImpl impl : {SineImpl::libm, SineImpl::table, SineImpl::poly}) {
    for (envelope::Preset preset : {envelope::Preset::square, envelope::Preset::violin}) {
      const synth::SynthConfig cfg{1000, 2.0f, impl};
      const double e = max_error(make_note(hz(rng), 1.0, 600000), preset, cfg);
      EXPECT_LT(e, kBudget) << synth::name(impl) << " " << envelope::name(preset);
    }
  }
}

// The default sine with every built-in preset, random amplitudes and frequencies, with and without the end fade.
TEST(Voice, EveryPresetMatchesReference) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> hz(1.0, 450.0), amp(0.05, 1.0);
  std::uniform_int_distribution<std::uint32_t> ticks(1, 3000);
  for (std::uint8_t p = 0; p < envelope::kBuiltinCount; ++p) {
    for (float fade : {0.0f, 2.0f, 50.0f}) {
      for (int trial = 0; trial < 20; ++trial) {
        const synth::SynthConfig cfg{1000, fade, synth::kDefaultSine};
        const synth::Note note = make_note(hz(rng), amp(rng), ticks(rng));
        const auto preset = static_cast<envelope::Preset>(p);
        ASSERT_LT(max_error(note, preset, cfg), kBudget)
            << envelope::name(preset) << " fade " << fade << " N " << note.duration_ticks;
      }
    }
  }
}

// The tick rate is a build setting: 10 kHz, ten minutes, default sine.
TEST(Voice, TenMinuteNoteAtTenKilohertz) {
  const synth::SynthConfig cfg{10000, 2.0f, synth::kDefaultSine};
  EXPECT_LT(max_error(make_note(3999.9, 1.0, 6000000), envelope::Preset::square, cfg), kBudget);
  EXPECT_LT(max_error(make_note(61.3, 0.8, 6000000), envelope::Preset::cello, cfg), kBudget);
}

TEST(Voice, StartsAtPhaseZeroAndStopsAfterNTicks) {
  const synth::SynthConfig cfg{1000, 0.0f, synth::kDefaultSine};
  synth::Voice v;
  v.start(make_note(250.0, 1.0, 5), envelope::builtin(envelope::Preset::square), cfg, 7);
  EXPECT_EQ(v.order(), 7u);
  EXPECT_EQ(v.freq_q20(), 250u << 20);
  // 250 Hz at 1 kHz: quarter turns, so the samples are sin(0), sin(π/2), sin(π), sin(3π/2), sin(2π).
  const float expected[] = {0.0f, 1.0f, 0.0f, -1.0f, 0.0f};
  for (float e : expected) {
    ASSERT_TRUE(v.active());
    EXPECT_NEAR(v.next(), e, 1e-6f);
  }
  EXPECT_FALSE(v.active());
  EXPECT_EQ(v.next(), 0.0f);
  EXPECT_EQ(v.next(), 0.0f);
}

TEST(Voice, DegenerateNotes) {
  const synth::SynthConfig cfg{};
  const envelope::Adsr& square = envelope::builtin(envelope::Preset::square);
  synth::Voice v;
  EXPECT_FALSE(v.active());  // a fresh voice is silent
  EXPECT_EQ(v.next(), 0.0f);

  v.start(make_note(100.0, 1.0, 0), square, cfg, 0);  // N = 0 plays one tick (design: N = max(1, …))
  EXPECT_TRUE(v.active());
  EXPECT_EQ(v.next(), 0.0f);  // phase 0
  EXPECT_FALSE(v.active());

  v.start(make_note(100.0, 0.0, 100), square, cfg, 0);  // amplitude 0: silent but occupies its ticks
  for (int i = 0; i < 100; ++i) ASSERT_EQ(v.next(), 0.0f);
  EXPECT_FALSE(v.active());

  v.start(make_note(0.0, 1.0, 100), square, cfg, 0);  // frequency 0: sin(0) throughout
  for (int i = 0; i < 100; ++i) ASSERT_EQ(v.next(), 0.0f);

  v.start(make_note(300.0, 1.0, 1000), square, cfg, 0);
  v.stop();
  EXPECT_FALSE(v.active());
  EXPECT_EQ(v.next(), 0.0f);
}

// Restarting a voice resets its phase and tick count (a stolen voice must not carry the old note's phase).
TEST(Voice, RestartResetsPhase) {
  const synth::SynthConfig cfg{};
  const envelope::Adsr& square = envelope::builtin(envelope::Preset::square);
  synth::Voice fresh, reused;
  reused.start(make_note(123.4, 1.0, 1000), square, cfg, 0);
  for (int i = 0; i < 333; ++i) reused.next();
  const synth::Note note = make_note(201.7, 0.5, 400);
  reused.start(note, square, cfg, 1);
  fresh.start(note, square, cfg, 1);
  for (int i = 0; i < 400; ++i) ASSERT_EQ(reused.next(), fresh.next());
}

}  // namespace
