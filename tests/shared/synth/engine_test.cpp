// The synthesis engine (design §7): voice pool and stealing, preset slots, note validation, polyphony
// policies and the limiter. Expected outputs come from independently driven Voice objects or from the
// double-precision reference, never from the engine itself.
#include "shared/synth/engine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "shared/synth/frequency.hpp"

namespace {

using namespace hmp;
using synth::Engine;
using synth::Note;
using synth::Polyphony;

constexpr auto kSquare = static_cast<std::uint8_t>(envelope::Preset::square);
constexpr auto kViolin = static_cast<std::uint8_t>(envelope::Preset::violin);
constexpr double kTwoPi = 2 * std::numbers::pi;

Note note(double hz, double amp, std::uint32_t ticks, std::uint8_t preset = kSquare, std::uint8_t track = 0) {
  Note n;
  n.freq_q20 = synth::freq_to_q20(hz);
  n.amp_q16 = synth::amp_to_q16(amp);
  n.duration_ticks = ticks;
  n.preset = preset;
  n.track = track;
  return n;
}

// The same notes played by free-standing voices, started in the same order.
struct Shadow {
  std::vector<synth::Voice> voices;
  void start(const Note& n, const synth::SynthConfig& cfg) {
    voices.emplace_back();
    voices.back().start(n, envelope::builtin(static_cast<envelope::Preset>(n.preset)), cfg,
                        static_cast<std::uint32_t>(voices.size()));
  }
};

bool contains_track(const Engine& e, std::uint8_t track) {
  for (std::uint8_t i = 0; i < synth::kVoiceCount; ++i)
    if (e.voice(i).active() && e.voice(i).note().track == track) return true;
  return false;
}

TEST(Engine, BuiltinPresetsPreloadedUserSlotsEmpty) {
  Engine e;
  for (std::uint8_t s = 0; s < envelope::kBuiltinCount; ++s) {
    const envelope::Adsr* p = e.preset(s);
    ASSERT_NE(p, nullptr) << int(s);
    const envelope::Adsr& b = envelope::builtin(static_cast<envelope::Preset>(s));
    EXPECT_EQ(p->attack_ms, b.attack_ms);
    EXPECT_EQ(p->release_ms, b.release_ms);
    EXPECT_EQ(p->sustain, b.sustain);
    EXPECT_EQ(p->shape, b.shape);
  }
  for (unsigned s = envelope::kBuiltinCount; s < 256; ++s)
    EXPECT_EQ(e.preset(static_cast<std::uint8_t>(s)), nullptr) << s;
}

TEST(Engine, UserPresetsValidated) {
  Engine e;
  const envelope::Adsr good{10, 20, 30, 0.5f, 0.1f, envelope::Shape::adsr};
  EXPECT_TRUE(e.set_preset(envelope::kFirstUserSlot, good));
  EXPECT_TRUE(e.set_preset(envelope::kSlotCount - 1, good));
  ASSERT_NE(e.preset(envelope::kFirstUserSlot), nullptr);
  EXPECT_EQ(e.preset(envelope::kFirstUserSlot)->decay_ms, 20.0f);

  EXPECT_FALSE(e.set_preset(0, good));  // built-ins are fixed
  EXPECT_FALSE(e.set_preset(envelope::kSlotCount, good));
  EXPECT_FALSE(e.set_preset(255, good));
  envelope::Adsr bad = good;
  bad.attack_ms = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(e.set_preset(envelope::kFirstUserSlot + 1, bad));
  bad = good;
  bad.sustain = 1.5f;
  EXPECT_FALSE(e.set_preset(envelope::kFirstUserSlot + 1, bad));
  bad = good;
  bad.release_ms = -1.0f;
  EXPECT_FALSE(e.set_preset(envelope::kFirstUserSlot + 1, bad));
  EXPECT_EQ(e.preset(envelope::kFirstUserSlot + 1), nullptr);

  // A note on the uploaded slot plays.
  Note n = note(100.0, 1.0, 50);
  n.preset = envelope::kFirstUserSlot;
  EXPECT_TRUE(e.start(n));
}

TEST(Engine, RejectsMalformedNotes) {
  Engine e;  // 1 kHz
  const Note ok = note(100.0, 0.5, 100);
  std::vector<Note> bad;
  Note n = ok;
  n.preset = envelope::kBuiltinCount;  // gap between built-in and user slots
  bad.push_back(n);
  n.preset = envelope::kFirstUserSlot;  // user slot never uploaded
  bad.push_back(n);
  n.preset = 255;
  bad.push_back(n);
  n = ok;
  n.freq_q20 = 0;
  bad.push_back(n);
  n = ok;
  n.duration_ticks = 0;
  bad.push_back(n);
  n = ok;
  n.freq_q20 = synth::freq_to_q20(500.0);  // Nyquist at 1 kHz
  bad.push_back(n);
  n.freq_q20 = 0xFFFFFFFFu;
  bad.push_back(n);
  for (const Note& b : bad) EXPECT_FALSE(e.start(b));
  EXPECT_EQ(e.counters().rejected, bad.size());
  EXPECT_EQ(e.counters().started, 0u);
  EXPECT_EQ(e.active_voices(), 0);
  EXPECT_EQ(e.tick(), 0.0f);

  Note silent = ok;
  silent.amp_q16 = 0;  // amplitude 0 is a valid (silent) note
  EXPECT_TRUE(e.start(silent));
  n = ok;
  n.freq_q20 = synth::freq_to_q20(499.9);
  EXPECT_TRUE(e.start(n));
  EXPECT_EQ(e.counters().started, 2u);
  EXPECT_EQ(e.counters().rejected, bad.size());
}

TEST(Engine, RandomGarbageNeverBreaksTheOutput) {
  Engine e;
  std::mt19937_64 rng(21);
  for (int i = 0; i < 20000; ++i) {
    Note n;
    n.start_tick = rng();
    n.duration_ticks = static_cast<std::uint32_t>(rng() % 5000);
    n.freq_q20 = static_cast<std::uint32_t>(rng());
    n.amp_q16 = static_cast<std::uint16_t>(rng());
    n.preset = static_cast<std::uint8_t>(rng());
    n.track = static_cast<std::uint8_t>(rng());
    e.start(n);
    const float y = e.tick();
    ASSERT_TRUE(std::isfinite(y));
    ASSERT_LE(std::fabs(y), 1.0f);
  }
  EXPECT_EQ(e.counters().started + e.counters().rejected, 20000u);
  EXPECT_GT(e.counters().rejected, 0u);
  EXPECT_GT(e.counters().started, 0u);
}

// 16 voices whose amplitudes add up to at most 1: the output is the plain sum, checked against the
// voices played separately and against the double reference of each note.
TEST(Engine, SixteenVoiceChordSumsExactly) {
  const synth::SynthConfig cfg{};
  Engine e(cfg);
  Shadow shadow;
  std::vector<double> freqs;
  for (int i = 0; i < synth::kVoiceCount; ++i) {
    const Note n = note(50.0 + 12.5 * i, 1.0 / 16, 3000);
    ASSERT_TRUE(e.start(n));
    shadow.start(n, cfg);
    freqs.push_back(synth::q20_to_hz(n.freq_q20));
  }
  EXPECT_EQ(e.active_voices(), synth::kVoiceCount);
  const double amp = synth::amp_to_q16(1.0 / 16) / 65535.0;
  for (int t = 0; t < 3000; ++t) {
    double sum = 0.0, reference = 0.0;
    for (std::size_t i = 0; i < shadow.voices.size(); ++i) {
      sum += static_cast<double>(shadow.voices[i].next());
      const double fade = std::min(1.0, (3000.0 - t) / 2.0);  // default 2 ms end fade
      reference += amp * fade * std::sin(kTwoPi * freqs[i] * t / 1000.0);
    }
    const double y = static_cast<double>(e.tick());
    ASSERT_NEAR(y, sum, 1e-6) << t;
    ASSERT_NEAR(y, reference, 16 * 2e-5) << t;
  }
  EXPECT_EQ(e.active_voices(), 0);
  EXPECT_EQ(e.counters().stolen, 0u);
}

TEST(Engine, SeventeenthNoteStealsTheOldest) {
  Engine e;
  for (std::uint8_t i = 0; i < synth::kVoiceCount; ++i) {
    ASSERT_TRUE(e.start(note(100.0 + i, 0.01, 10000, kSquare, i)));
    e.tick();
  }
  EXPECT_EQ(e.counters().stolen, 0u);
  ASSERT_TRUE(e.start(note(300.0, 0.01, 10000, kSquare, 100)));
  EXPECT_EQ(e.counters().stolen, 1u);
  EXPECT_EQ(e.active_voices(), synth::kVoiceCount);
  EXPECT_FALSE(contains_track(e, 0));  // the first note went
  EXPECT_TRUE(contains_track(e, 1));
  EXPECT_TRUE(contains_track(e, 100));
  ASSERT_TRUE(e.start(note(301.0, 0.01, 10000, kSquare, 101)));
  EXPECT_EQ(e.counters().stolen, 2u);
  EXPECT_FALSE(contains_track(e, 1));  // then the second
  EXPECT_TRUE(contains_track(e, 2));
  EXPECT_TRUE(contains_track(e, 100));  // the newest are kept
  EXPECT_EQ(e.counters().started, synth::kVoiceCount + 2u);
}

TEST(Engine, FinishedVoicesAreReusedWithoutStealing) {
  Engine e;
  for (std::uint8_t i = 0; i < synth::kVoiceCount; ++i)
    ASSERT_TRUE(e.start(note(100.0 + i, 0.01, i < 4 ? 5 : 1000, kSquare, i)));
  for (int t = 0; t < 5; ++t) e.tick();
  EXPECT_EQ(e.active_voices(), synth::kVoiceCount - 4);
  for (std::uint8_t i = 0; i < 4; ++i) ASSERT_TRUE(e.start(note(200.0 + i, 0.01, 1000, kSquare, 50 + i)));
  EXPECT_EQ(e.counters().stolen, 0u);
  for (std::uint8_t i = 4; i < synth::kVoiceCount; ++i) EXPECT_TRUE(contains_track(e, i));
}

// The highest (by frequency: monotonic in key for every mapping) sounding note is heard; the others
// keep advancing silently, so switching back to sum gives every voice at its own right tick.
TEST(Engine, HighestPolicy) {
  const synth::SynthConfig cfg{};
  Engine e(cfg);
  e.set_polyphony(Polyphony::highest);
  Shadow s;
  const Note low = note(80.0, 0.3, 400, kViolin), high = note(220.0, 0.2, 200, kViolin),
             mid = note(150.0, 0.4, 600, kViolin);
  for (const Note& n : {low, high, mid}) {
    e.start(n);
    s.start(n, cfg);
  }
  for (int t = 0; t < 700; ++t) {
    float y[3];
    for (int i = 0; i < 3; ++i) y[i] = s.voices[i].next();
    const float expected = t < 200 ? y[1] : (t < 600 ? y[2] : 0.0f);  // high, then mid, then none
    if (t == 650) e.set_polyphony(Polyphony::sum);
    const float got = e.tick();
    if (t < 650) {
      ASSERT_EQ(got, expected) << t;
    } else {
      ASSERT_NEAR(got, y[0] + y[1] + y[2], 1e-7f) << t;
    }
  }
}

TEST(Engine, HighestPolicyTieGoesToTheNewest) {
  const synth::SynthConfig cfg{};
  Engine e(cfg);
  e.set_polyphony(Polyphony::highest);
  Shadow s;
  const Note older = note(200.0, 0.9, 100), newer = note(200.0, 0.1, 50);
  for (const Note& n : {older, newer}) {
    e.start(n);
    s.start(n, cfg);
  }
  for (int t = 0; t < 100; ++t) {
    const float a = s.voices[0].next(), b = s.voices[1].next();
    ASSERT_EQ(e.tick(), t < 50 ? b : a) << t;
  }
}

TEST(Engine, LatestPolicy) {
  const synth::SynthConfig cfg{};
  Engine e(cfg);
  e.set_polyphony(Polyphony::latest);
  Shadow s;
  std::vector<float> y(3);
  // A long low note, then a short high one at t = 10, then a medium one at t = 20 that ends first.
  for (int t = 0; t < 300; ++t) {
    const auto start = [&](const Note& n) {
      e.start(n);
      s.start(n, cfg);
    };
    if (t == 0) start(note(70.0, 0.5, 300));
    if (t == 10) start(note(240.0, 0.5, 100));
    if (t == 20) start(note(120.0, 0.5, 30));
    for (std::size_t i = 0; i < s.voices.size(); ++i) y[i] = s.voices[i].next();
    const float expected = t < 10 ? y[0] : (t < 20 ? y[1] : (t < 50 ? y[2] : (t < 110 ? y[1] : y[0])));
    ASSERT_EQ(e.tick(), expected) << t;
  }
}

TEST(Engine, PolicyNames) {
  Polyphony p = Polyphony::sum;
  for (Polyphony q : {Polyphony::sum, Polyphony::highest, Polyphony::latest}) {
    ASSERT_TRUE(synth::find_polyphony(synth::name(q), p));
    EXPECT_EQ(p, q);
  }
  EXPECT_TRUE(synth::find_polyphony("HIGHEST", p));
  EXPECT_EQ(p, Polyphony::highest);
  EXPECT_FALSE(synth::find_polyphony("loudest", p));
  EXPECT_FALSE(synth::find_polyphony("", p));
  EXPECT_FALSE(synth::find_polyphony(nullptr, p));
  EXPECT_STREQ(synth::name(Polyphony::latest), "latest");
}

TEST(Engine, StopAllSilences) {
  Engine e;
  for (int i = 0; i < 5; ++i) e.start(note(100.0 + 10 * i, 0.5, 1000));
  e.tick();
  e.stop_all();
  EXPECT_EQ(e.active_voices(), 0);
  EXPECT_EQ(e.tick(), 0.0f);
}

// 16 in-phase full-scale voices peak at 16× full scale: the limiter keeps |y| ≤ 1 and only scales (the
// output keeps the sum's sign and shape: y = g·sum with 0 < g ≤ 1).
TEST(Engine, LimiterTamesSixteenFullScaleVoices) {
  const synth::SynthConfig cfg{};
  Engine e(cfg);
  Shadow s;
  for (int i = 0; i < synth::kVoiceCount; ++i) {
    const Note n = note(i < 8 ? 100.0 : 100.0 + 3 * i, 1.0, 2000, kViolin);
    e.start(n);
    s.start(n, cfg);
  }
  float peak = 0.0f;
  for (int t = 0; t < 2000; ++t) {
    float sum = 0.0f;
    for (auto& v : s.voices) sum += v.next();
    const float y = e.tick();
    peak = std::max(peak, std::fabs(sum));
    ASSERT_LE(std::fabs(y), 1.0f) << t;
    ASSERT_FALSE(std::signbit(y) != std::signbit(sum) && y != 0.0f && sum != 0.0f) << t;
    ASSERT_LE(std::fabs(y), std::fabs(sum) + 1e-6f) << t;
  }
  EXPECT_GT(peak, 8.0f);  // the test really drove the limiter hard
}

TEST(Limiter, PassesInScaleSignalsBitForBit) {
  synth::Limiter l;
  l.configure(50.0f, 1000);
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> x(-1.0f, 1.0f);
  for (int i = 0; i < 100000; ++i) {
    const float v = x(rng);
    ASSERT_EQ(l.process(v), v);
  }
  for (float v : {1.0f, -1.0f, 0.0f, -0.0f, 1e-38f}) EXPECT_EQ(l.process(v), v);
  EXPECT_EQ(l.gain(), 1.0f);
}

TEST(Limiter, NeverPassesNaNOrInfinity) {
  synth::Limiter l;
  l.configure(50.0f, 1000);
  EXPECT_EQ(l.process(std::numeric_limits<float>::quiet_NaN()), 0.0f);
  EXPECT_EQ(l.process(std::numeric_limits<float>::infinity()), 0.0f);
  EXPECT_EQ(l.process(-std::numeric_limits<float>::infinity()), 0.0f);
  EXPECT_EQ(l.gain(), 1.0f);  // garbage does not disturb the gain either
  EXPECT_EQ(l.process(0.5f), 0.5f);
  const float huge = l.process(3e38f);
  EXPECT_LE(std::fabs(huge), 1.0f);
  EXPECT_GT(huge, 0.99f);
}

// A spike of 2× full scale: gain 1/2 at once, then the gap to unity decays with the release time
// constant (checked against exp(−t/τ) in double), and after a while the limiter is transparent again.
TEST(Limiter, AttackAtOnceReleaseWithTimeConstant) {
  for (std::uint32_t tick_hz : {1000u, 10000u}) {
    const float release_ms = 50.0f;
    synth::Limiter l;
    l.configure(release_ms, tick_hz);
    EXPECT_EQ(l.process(2.0f), 1.0f);
    EXPECT_EQ(l.gain(), 0.5f);
    EXPECT_EQ(l.process(-4.0f), -1.0f);
    EXPECT_EQ(l.gain(), 0.25f);
    const double tau_ticks = 50.0 * tick_hz / 1000.0;
    for (std::uint32_t t = 1; t <= 2 * tau_ticks; ++t) {
      const float y = l.process(0.1f);
      const double expected_gain = 1.0 - 0.75 * std::exp(-static_cast<double>(t) / tau_ticks);
      ASSERT_NEAR(static_cast<double>(l.gain()), expected_gain, 1e-4) << t;
      ASSERT_FLOAT_EQ(y, 0.1f * l.gain());
    }
    for (std::uint32_t t = 0; t < 20 * tau_ticks; ++t) l.process(0.0f);
    EXPECT_EQ(l.gain(), 1.0f);
    EXPECT_EQ(l.process(0.987654f), 0.987654f);
  }
}

TEST(Limiter, ZeroReleaseRecoversAtOnce) {
  synth::Limiter l;
  l.configure(0.0f, 1000);
  EXPECT_EQ(l.process(5.0f), 1.0f);
  EXPECT_EQ(l.process(0.3f), 0.3f);
  l.configure(std::numeric_limits<float>::quiet_NaN(), 1000);
  EXPECT_EQ(l.process(5.0f), 1.0f);
  EXPECT_EQ(l.process(0.3f), 0.3f);
}

}  // namespace
