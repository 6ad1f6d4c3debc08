// Voices through the device (design §7): 16-voice chords, oldest-first stealing counted in Status, and the
// three polyphony policies chosen by a Settings report. Expectations come from an independent
// double-precision evaluation of design §6 (tests/support/reference_envelope.hpp and sin()), not from the
// synth::Engine the device runs; where the limiter or stealing decides the output, the engine's own
// reference is compared as well.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/firmware/host_link.hpp"
#include "tests/support/reference_envelope.hpp"

namespace hmp::test {
namespace {

struct Played {
  std::uint64_t t0 = 0;     // the notes' starts are relative to this tick
  std::uint64_t first = 0;  // tick of output[0]
  std::vector<float> output;
  Replies replies;
  p::Status status;
};

// Plays `notes` (starts relative to a tick shortly after play) with the given policy.
Played play(std::vector<TestNote> notes, p::PolicyCode policy, std::size_t ticks) {
  sim::SimDevice dev(1000);
  HostLink host(dev);
  host.hello();
  host.settings(exact_settings(policy));
  host.play();
  dev.advance(3);
  host.collect();
  const std::uint64_t t0 = dev.tick() + 10;
  for (TestNote& n : notes) n.start += t0;
  host.all_notes(notes);
  Played out;
  out.t0 = t0;
  out.first = dev.tick() + 1;
  out.output = host.run(ticks);
  out.replies = host.collect();
  out.status = host.status();
  return out;
}

// One note as design §6 and §7 define it, in double precision: the preset's envelope times a sine of the
// frequency the wire carries, phase 0 at the note's start; 0 outside the note. At 1 kHz.
double independent_sample(const TestNote& n, std::uint64_t tick) {
  if (tick < n.start || tick >= n.start + n.duration) return 0.0;
  const synth::Note s = to_synth(n);
  const double f = synth::q20_to_hz(s.freq_q20);
  const double peak = s.amp_q16 / 65535.0;
  const double x_ms = static_cast<double>(tick - n.start);
  const double fade_ms = static_cast<double>(exact_settings().end_fade_ms);
  return reference::envelope(envelope::builtin(static_cast<envelope::Preset>(n.preset)), peak,
                             static_cast<double>(n.duration), x_ms, fade_ms) *
         std::sin(2.0 * M_PI * f * x_ms / 1000.0);
}

// Design §7's accuracy for one voice (2·10⁻⁵ of full scale), plus float rounding of the mix per voice.
constexpr double kPerVoiceTolerance = 3e-5;

std::vector<TestNote> shifted(std::vector<TestNote> notes, std::uint64_t by) {
  for (TestNote& n : notes) n.start += by;
  return notes;
}

std::vector<TestNote> chord(std::size_t voices, std::uint64_t at) {
  std::vector<TestNote> notes;
  for (std::size_t i = 0; i < voices; ++i)
    notes.push_back({at, 400, 50.0 + 12.5 * static_cast<double>(i), 0.05 + 0.01 * static_cast<double>(i)});
  return notes;
}

TEST(FirmwarePolyphony, SixteenVoiceChordSoundsWholeWithoutStealing) {
  const std::vector<TestNote> notes = chord(synth::kVoiceCount, 0);
  const Played got = play(notes, p::PolicyCode::sum, 600);
  const std::vector<float> want = reference_output(shifted(notes, got.t0), got.first, 600, 1000);
  ASSERT_EQ(got.output, want);
  ASSERT_EQ(got.replies.started.size(), synth::kVoiceCount);
  for (const p::StartedEntry& e : got.replies.started) EXPECT_EQ(e.actual_tick, e.scheduled_tick);
  EXPECT_EQ(got.status.stolen, 0u);
  // While the chord sounded, every status counted 16 voices.
  bool saw_full = false;
  for (const p::Status& s : got.replies.statuses) saw_full = saw_full || s.active_voices == synth::kVoiceCount;
  EXPECT_TRUE(saw_full);
}

TEST(FirmwarePolyphony, SeventeenthNoteStealsTheOldestAndIsCounted) {
  std::vector<TestNote> notes;
  for (std::size_t i = 0; i < synth::kVoiceCount + 3; ++i)
    notes.push_back({i * 2, 500, 60.0 + 7.0 * static_cast<double>(i), 0.04});
  const Played got = play(notes, p::PolicyCode::sum, 700);
  const std::vector<float> want = reference_output(shifted(notes, got.t0), got.first, 700, 1000);
  ASSERT_EQ(got.output, want);
  EXPECT_EQ(got.status.stolen, 3u);
  EXPECT_EQ(got.status.started, synth::kVoiceCount + 3);
}

// The chosen note alone, independently evaluated: what `highest` and `latest` must output.
std::vector<double> solo(const TestNote& n, std::uint64_t first, std::size_t ticks) {
  std::vector<double> out(ticks);
  for (std::size_t i = 0; i < ticks; ++i) out[i] = independent_sample(n, first + i);
  return out;
}

// A chord that stays within full scale: the limiter must leave it alone, so the device's output is the
// plain sum of the sixteen notes.
TEST(FirmwarePolyphony, QuietSixteenVoiceChordIsThePlainSumOfItsNotes) {
  std::vector<TestNote> notes;
  for (std::size_t i = 0; i < synth::kVoiceCount; ++i)
    notes.push_back({i * 3, 400, 50.0 + 12.5 * static_cast<double>(i), 0.04});  // |sum| ≤ 0.64
  const Played got = play(notes, p::PolicyCode::sum, 500);
  const auto abs_notes = shifted(notes, got.t0);
  double worst = 0.0;
  for (std::size_t i = 0; i < got.output.size(); ++i) {
    double want = 0.0;
    for (const TestNote& n : abs_notes) want += independent_sample(n, got.first + i);
    worst = std::max(worst, std::fabs(static_cast<double>(got.output[i]) - want));
  }
  EXPECT_LT(worst, synth::kVoiceCount * kPerVoiceTolerance);
  EXPECT_EQ(got.status.stolen, 0u);
}

TEST(FirmwarePolyphony, HighestPolicyOutputsOnlyTheHighestNote) {
  // Low note first and longest, a higher one on top, then a higher still that ends first.
  const std::vector<TestNote> notes = {{0, 600, 60.0, 0.5}, {100, 300, 120.0, 0.3}, {150, 100, 200.0, 0.2}};
  const Played got = play(notes, p::PolicyCode::highest, 700);
  const auto abs_notes = shifted(notes, got.t0);
  const std::uint64_t first = got.first;
  const auto lo = solo(abs_notes[0], first, 700), mid = solo(abs_notes[1], first, 700),
             hi = solo(abs_notes[2], first, 700);
  for (std::size_t i = 0; i < 700; ++i) {
    const std::uint64_t t = first + i;
    const double want = t >= abs_notes[2].start && t < abs_notes[2].start + 100   ? hi[i]
                        : t >= abs_notes[1].start && t < abs_notes[1].start + 300 ? mid[i]
                                                                                  : lo[i];
    ASSERT_NEAR(got.output[i], want, kPerVoiceTolerance) << "tick " << t;
  }
  EXPECT_EQ(got.output, reference_output(abs_notes, first, 700, 1000, synth::Polyphony::highest));
}

TEST(FirmwarePolyphony, LatestPolicyOutputsOnlyTheNewestNote) {
  const std::vector<TestNote> notes = {{0, 600, 200.0, 0.5}, {100, 300, 60.0, 0.3}, {150, 100, 90.0, 0.2}};
  const Played got = play(notes, p::PolicyCode::latest, 700);
  const auto abs_notes = shifted(notes, got.t0);
  const std::uint64_t first = got.first;
  const auto a = solo(abs_notes[0], first, 700), b = solo(abs_notes[1], first, 700), c = solo(abs_notes[2], first, 700);
  for (std::size_t i = 0; i < 700; ++i) {
    const std::uint64_t t = first + i;
    const double want = t >= abs_notes[2].start && t < abs_notes[2].start + 100   ? c[i]
                        : t >= abs_notes[1].start && t < abs_notes[1].start + 300 ? b[i]
                                                                                  : a[i];
    ASSERT_NEAR(got.output[i], want, kPerVoiceTolerance) << "tick " << t;
  }
}

TEST(FirmwarePolyphony, SumPolicyLimitsALoudChordSmoothly) {
  // 16 full-scale notes add far beyond full scale: the limiter must keep |y| ≤ 1 (and the device
  // matches the engine sample for sample).
  std::vector<TestNote> notes;
  for (std::size_t i = 0; i < synth::kVoiceCount; ++i) notes.push_back({0, 300, 100.0, 1.0});
  const Played got = play(notes, p::PolicyCode::sum, 400);
  float peak = 0.0f;
  for (const float y : got.output) peak = std::max(peak, std::abs(y));
  EXPECT_LE(peak, 1.0f);
  EXPECT_GT(peak, 0.9f);  // scaled, not flattened to nothing
  EXPECT_EQ(got.output, reference_output(shifted(notes, got.t0), got.first, 400, 1000));
  EXPECT_EQ(got.status.faults, 0u);
}

// More notes due on one tick than there are voices: the first 16 start on time, the rest on the next
// tick (counted late), stealing the oldest.
TEST(FirmwarePolyphony, MoreNotesOnOneTickThanVoicesSpillToTheNextTick) {
  const std::vector<TestNote> notes = chord(synth::kVoiceCount + 4, 0);
  const Played got = play(notes, p::PolicyCode::sum, 500);
  ASSERT_EQ(got.replies.started.size(), notes.size());
  for (std::size_t i = 0; i < notes.size(); ++i) {
    const auto& e = got.replies.started[i];
    EXPECT_EQ(e.actual_tick, e.scheduled_tick + (i < synth::kVoiceCount ? 0u : 1u)) << i;
  }
  EXPECT_EQ(got.status.late, 4u);
  EXPECT_EQ(got.status.stolen, 4u);
}

}  // namespace
}  // namespace hmp::test
