// Held notes in the engine (live input): start_held, release, bend. Expected samples come from a
// double-precision sine with the phase carried over a bend, and from a free-standing Envelope, never from
// the engine itself.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "shared/synth/engine.hpp"
#include "shared/synth/frequency.hpp"

namespace {

using namespace hmp;
using synth::Engine;
using synth::Note;

constexpr auto kSquare = static_cast<std::uint8_t>(envelope::Preset::square);
constexpr auto kOrgan = static_cast<std::uint8_t>(envelope::Preset::organ);
constexpr double kTwoPi = 2 * std::numbers::pi;

Note held(double hz, std::uint8_t key, std::uint8_t track = 0, std::uint8_t preset = kSquare) {
  Note n;
  n.freq_q20 = synth::freq_to_q20(hz);
  n.amp_q16 = synth::amp_to_q16(0.5);
  n.preset = preset;
  n.track = track;
  n.key = key;
  n.duration_ticks = 0;  // a held note has none
  return n;
}

synth::SynthConfig no_fade() {
  synth::SynthConfig cfg;
  cfg.end_fade_ms = 0;
  return cfg;
}

TEST(HeldNotes, SoundUntilReleasedThenFollowTheRelease) {
  Engine e(no_fade());
  ASSERT_TRUE(e.start_held(held(100, 60, 0, kOrgan)));
  // Far past any scheduled length: still sounding.
  for (int n = 0; n < 5000; ++n) e.tick();
  EXPECT_EQ(e.active_voices(), 1);
  EXPECT_TRUE(e.voice(0).held());
  EXPECT_FALSE(e.release(1, 60)) << "another track's key";
  EXPECT_FALSE(e.release(0, 61)) << "another key";
  EXPECT_TRUE(e.release(0, 60));
  EXPECT_FALSE(e.voice(0).held());
  EXPECT_FALSE(e.release(0, 60)) << "released already";
  // The organ's release is 25 ms: its samples follow a free-standing envelope released at the same tick.
  envelope::Envelope ref;
  ref.start_held(envelope::builtin(envelope::Preset::organ), 0.5f, 1000, 0);
  ref.release_at(5000);
  int sounding = 0;
  for (std::uint32_t n = 5000; n < 5030; ++n) {
    const double phase = kTwoPi * 100.0 * n / 1000.0;
    sounding += e.active_voices();  // before the tick: the ticks the note sounds in
    EXPECT_NEAR(e.tick(), static_cast<double>(ref.at(n)) * std::sin(phase), 2e-4) << n;
  }
  EXPECT_EQ(sounding, 25);
  EXPECT_EQ(e.active_voices(), 0);
}

TEST(HeldNotes, ABendKeepsThePhaseGoing) {
  Engine e(no_fade());
  ASSERT_TRUE(e.start_held(held(50, 7)));
  double phase = 0;
  for (int n = 0; n < 333; ++n) {
    EXPECT_NEAR(e.tick(), 0.5 * std::sin(phase), 2e-4) << n;
    phase += kTwoPi * synth::q20_to_hz(synth::freq_to_q20(50)) / 1000.0;
  }
  ASSERT_TRUE(e.bend(0, 7, synth::freq_to_q20(75.5)));
  EXPECT_EQ(e.voice(0).freq_q20(), synth::freq_to_q20(75.5));
  for (int n = 0; n < 1000; ++n) {
    EXPECT_NEAR(e.tick(), 0.5 * std::sin(phase), 2e-4) << "after the bend, " << n;
    phase += kTwoPi * synth::q20_to_hz(synth::freq_to_q20(75.5)) / 1000.0;
  }
  // Nothing changes for a frequency the tick rate cannot carry, or a key that is not sounding.
  EXPECT_FALSE(e.bend(0, 7, 0));
  EXPECT_FALSE(e.bend(0, 7, synth::freq_to_q20(500)));
  EXPECT_FALSE(e.bend(0, 8, synth::freq_to_q20(60)));
  EXPECT_EQ(e.voice(0).freq_q20(), synth::freq_to_q20(75.5));
}

TEST(HeldNotes, AKeyStruckAgainReleasesItsFormerNote) {
  Engine e(no_fade());
  ASSERT_TRUE(e.start_held(held(100, 60, 3, kOrgan)));
  for (int n = 0; n < 10; ++n) e.tick();
  ASSERT_TRUE(e.start_held(held(100, 60, 3, kOrgan)));
  int held_voices = 0;
  for (std::uint8_t i = 0; i < synth::kVoiceCount; ++i) held_voices += e.voice(i).held() ? 1 : 0;
  EXPECT_EQ(held_voices, 1);
  EXPECT_EQ(e.active_voices(), 2) << "the first one in its release";
  // A bend reaches both: the releasing one is the same key.
  EXPECT_TRUE(e.bend(3, 60, synth::freq_to_q20(110)));
  for (std::uint8_t i = 0; i < synth::kVoiceCount; ++i) {
    if (e.voice(i).active()) {
      EXPECT_EQ(e.voice(i).freq_q20(), synth::freq_to_q20(110));
    }
  }
  for (int n = 0; n < 30; ++n) e.tick();
  EXPECT_EQ(e.active_voices(), 1);
}

TEST(HeldNotes, OverTheVoiceLimitTheOldestGivesWay) {
  Engine e(no_fade());
  for (std::uint8_t k = 0; k < synth::kVoiceCount + 4; ++k) ASSERT_TRUE(e.start_held(held(40 + k, k)));
  EXPECT_EQ(e.active_voices(), synth::kVoiceCount);
  EXPECT_EQ(e.counters().stolen, 4u);
  for (std::uint8_t k = 0; k < 4; ++k) EXPECT_FALSE(e.release(0, k)) << "stolen: " << int(k);
  for (std::uint8_t k = 4; k < synth::kVoiceCount + 4; ++k) EXPECT_TRUE(e.release(0, k)) << int(k);
}

TEST(HeldNotes, UnplayableHeldNotesAreRefused) {
  Engine e;
  Note n = held(100, 1);
  n.preset = envelope::kFirstUserSlot;  // empty
  EXPECT_FALSE(e.start_held(n));
  n = held(0, 1);
  EXPECT_FALSE(e.start_held(n));
  n = held(600, 1);  // above Nyquist at 1 kHz
  EXPECT_FALSE(e.start_held(n));
  EXPECT_EQ(e.counters().rejected, 3u);
  EXPECT_EQ(e.active_voices(), 0);
  // A scheduled note is never a held one: release and bend leave it alone.
  Note scheduled = held(100, 9);
  scheduled.duration_ticks = 100;
  ASSERT_TRUE(e.start(scheduled));
  EXPECT_FALSE(e.release(0, 9));
  EXPECT_FALSE(e.bend(0, 9, synth::freq_to_q20(120)));
}

}  // namespace
