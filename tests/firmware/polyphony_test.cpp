// Voices through the device (design §7): 16-voice chords, oldest-first stealing counted in Status, and the
// three polyphony policies chosen by a Settings report.
#include <gtest/gtest.h>

#include "tests/firmware/host_link.hpp"

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

// A single-voice engine playing only the chosen note: what `highest` and `latest` must output.
std::vector<float> solo(const TestNote& n, std::uint64_t first, std::size_t ticks) {
  return reference_output({n}, first, ticks, 1000);
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
    const float want = t >= abs_notes[2].start && t < abs_notes[2].start + 100   ? hi[i]
                       : t >= abs_notes[1].start && t < abs_notes[1].start + 300 ? mid[i]
                                                                                 : lo[i];
    ASSERT_EQ(got.output[i], want) << "tick " << t;
  }
  EXPECT_EQ(got.output, reference_output(abs_notes, first, 700, 1000, synth::Polyphony::highest));
}

TEST(FirmwarePolyphony, LatestPolicyOutputsOnlyTheNewestNote) {
  const std::vector<TestNote> notes = {{0, 600, 200.0, 0.5}, {100, 300, 60.0, 0.3}, {150, 100, 90.0, 0.2}};
  const Played got = play(notes, p::PolicyCode::latest, 700);
  const auto abs_notes = shifted(notes, got.t0);
  const std::uint64_t first = got.first;
  const auto a = solo(abs_notes[0], first, 700), b = solo(abs_notes[1], first, 700),
             c = solo(abs_notes[2], first, 700);
  for (std::size_t i = 0; i < 700; ++i) {
    const std::uint64_t t = first + i;
    const float want = t >= abs_notes[2].start && t < abs_notes[2].start + 100   ? c[i]
                       : t >= abs_notes[1].start && t < abs_notes[1].start + 300 ? b[i]
                                                                                 : a[i];
    ASSERT_EQ(got.output[i], want) << "tick " << t;
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
