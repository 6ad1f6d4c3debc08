// Voices prepared ahead of their tick by the core's background context (docs/firmware.md, "Note
// starts"): the output, the start ticks and the counters must be exactly those of notes set up on their
// tick — with the background keeping up, with no background at all, for chords larger than the slots,
// notes arriving too late to prepare, and a preset replaced after a note was handed over. The reference
// is the shared Engine driven directly.
#include <gtest/gtest.h>

#include <random>

#include "tests/firmware/host_link.hpp"

namespace hmp::test {
namespace {

class PreparedNotes : public ::testing::TestWithParam<std::uint32_t> {};

// A random passage: chords of up to 8 notes 10–50 ms apart (the tick hands one note a tick to the
// background, so such a passage can be prepared whole), several presets, voices stolen often.
std::vector<TestNote> passage(std::uint64_t t0, std::uint32_t hz, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> gap(hz / 100, hz / 20), length(1, hz / 2), chord(1, 8);
  std::uniform_int_distribution<int> preset(0, 7);
  std::uniform_real_distribution<double> freq(30.0, 300.0), amp(0.05, 0.3);
  std::vector<TestNote> notes;
  std::uint64_t t = t0;
  while (notes.size() < 60) {
    t += gap(rng);
    const std::uint32_t n = chord(rng);
    for (std::uint32_t i = 0; i < n; ++i) {
      notes.push_back({t, length(rng), freq(rng), amp(rng), static_cast<std::uint8_t>(preset(rng))});
    }
  }
  return notes;
}

// Sends every note (start order), then plays until all have ended; checks the output against the engine
// and every Started entry against its schedule.
void play_and_check(sim::SimDevice& dev, HostLink& host, const std::vector<TestNote>& notes, std::uint32_t hz) {
  // Reports of up to 5 notes within 255 ticks of the first (the wire's offsets); sending may run ticks
  // while the inbox is full, long before the first note.
  std::vector<TestNote> batch;
  for (const TestNote& n : notes) {
    if (!batch.empty() && (batch.size() == 5 || n.start - batch.front().start > 255)) {
      host.notes(batch);
      batch.clear();
    }
    batch.push_back(n);
  }
  host.notes(batch);
  const std::uint64_t first = dev.tick() + 1;
  ASSERT_LT(first + 10, notes.front().start);
  std::uint64_t end = 0;
  for (const TestNote& n : notes) end = std::max(end, n.start + n.duration);
  const auto span = static_cast<std::size_t>(end + 10 - first);
  const std::vector<float> got = host.run(span);
  ASSERT_TRUE(same_output(got, reference_output(notes, first, span, hz), first));
  const Replies r = host.collect();
  ASSERT_EQ(r.started.size(), notes.size());
  for (const p::StartedEntry& e : r.started) EXPECT_EQ(e.actual_tick, e.scheduled_tick);
}

TEST_P(PreparedNotes, BackgroundPreparedStartsEqualTheEngineAndCostTheTickNoSetUp) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.open_exact();
  dev.advance(5);
  host.collect();
  const std::vector<TestNote> notes = passage(dev.tick() + hz / 2, hz, 7);
  play_and_check(dev, host, notes, hz);
  const fw::Stats s = dev.core().stats();
  EXPECT_EQ(s.started, notes.size());
  EXPECT_EQ(s.late, 0u);
  EXPECT_EQ(s.prepare_requests, notes.size());
  EXPECT_EQ(s.started_in_tick, 0u) << "every voice was prepared by the background in time";
}

TEST_P(PreparedNotes, WithoutBackgroundTheTickSetsUpEveryNoteOnItsTick) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  dev.set_prepare_voices(false);
  HostLink host(dev);
  host.open_exact();
  dev.advance(5);
  host.collect();
  const std::vector<TestNote> notes = passage(dev.tick() + hz / 2, hz, 11);
  play_and_check(dev, host, notes, hz);
  const fw::Stats s = dev.core().stats();
  EXPECT_EQ(s.started, notes.size());
  EXPECT_EQ(s.late, 0u);
  EXPECT_EQ(s.started_in_tick, notes.size());
}

// 20 notes on one tick, more than the 16 slots and the 16 starts a tick allows: the first 16 (in arrival
// order) on the tick, the other 4 one tick late, exactly as an engine started that way.
TEST_P(PreparedNotes, ChordLargerThanTheSlotsStartsSixteenOnTimeAndTheRestNextTick) {
  const std::uint32_t hz = GetParam();
  for (const bool background : {true, false}) {
    SCOPED_TRACE(background ? "background on" : "background off");
    sim::SimDevice dev(hz);
    dev.set_prepare_voices(background);
    HostLink host(dev);
    host.hello();
    host.settings(exact_settings());
    host.play();
    dev.advance(5);
    host.collect();
    const std::uint64_t t = dev.tick() + hz / 10;
    std::vector<TestNote> notes;
    for (int i = 0; i < 20; ++i) notes.push_back({t, hz / 5, 40.0 + 7.0 * i, 0.04});
    for (std::size_t i = 0; i < notes.size(); i += 5) {
      host.notes(std::vector<TestNote>(notes.begin() + static_cast<std::ptrdiff_t>(i),
                                       notes.begin() + static_cast<std::ptrdiff_t>(i + 5)));
    }
    std::vector<TestNote> as_started = notes;
    for (std::size_t i = 16; i < as_started.size(); ++i) as_started[i].start = t + 1;
    const std::uint64_t first = dev.tick() + 1;
    const auto span = static_cast<std::size_t>(t + hz / 5 + 10 - first);
    const std::vector<float> got = host.run(span);
    ASSERT_TRUE(same_output(got, reference_output(as_started, first, span, hz), first));
    const Replies r = host.collect();
    ASSERT_EQ(r.started.size(), 20u);
    for (std::size_t i = 0; i < 20; ++i) {
      EXPECT_EQ(r.started[i].actual_tick, static_cast<std::uint32_t>(i < 16 ? t : t + 1)) << "note " << i;
    }
    EXPECT_EQ(dev.core().stats().late, 4u);
    EXPECT_EQ(dev.core().engine().counters().stolen, 4u);
  }
}

// A note that arrives for the very next tick cannot be prepared ahead: the tick sets it up itself, on time.
TEST_P(PreparedNotes, NoteForTheNextTickStartsOnItWithoutPreparation) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.open_exact();
  dev.advance(50);
  const TestNote note{dev.tick() + 1, 100, 77.0, 0.6, static_cast<std::uint8_t>(envelope::Preset::cello)};
  host.notes({note});
  const std::vector<float> got = host.run(120);
  ASSERT_TRUE(same_output(got, reference_output({note}, note.start, 120, hz), note.start));
  const fw::Stats s = dev.core().stats();
  EXPECT_EQ(s.started, 1u);
  EXPECT_EQ(s.late, 0u);
  EXPECT_EQ(s.started_in_tick, 1u);
}

// A preset replaced after the note's voice was prepared with the old one: the note plays the new one.
TEST_P(PreparedNotes, PresetReplacedAfterPreparationIsTheOneHeard) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.hello();
  host.settings(exact_settings());
  envelope::Adsr old_adsr{10, 20, 30, 0.5f, 0.1f, envelope::Shape::adsr};
  envelope::Adsr new_adsr{40, 0, 60, 1.0f, 0.01f, envelope::Shape::adsr};
  constexpr std::uint8_t kSlot = envelope::kFirstUserSlot;
  host.preset(kSlot, old_adsr);
  host.play();
  dev.advance(5);
  const TestNote note{dev.tick() + hz / 100 + 5, hz / 4, 90.0, 0.7, kSlot};  // within the 20 ms horizon
  static_assert(fw::Core::kPrepareAheadMs >= 15);
  host.notes({note});
  dev.advance(3);
  ASSERT_EQ(dev.core().prepared_pending(), 1u) << "the note should have been handed to the background";
  host.preset(kSlot, new_adsr);
  const std::uint64_t first = dev.tick() + 1;
  const std::vector<float> got = host.run(static_cast<std::size_t>(note.start + note.duration + 5 - first));

  synth::SynthConfig cfg;
  cfg.tick_hz = hz;
  synth::Engine engine(cfg);
  ASSERT_TRUE(engine.set_preset(kSlot, new_adsr));
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (first + i == note.start) {
      ASSERT_TRUE(engine.start(to_synth(note)));
    }
    ASSERT_EQ(got[i], engine.tick()) << "tick " << first + i;
  }
  EXPECT_EQ(dev.core().stats().started_in_tick, 1u);
  EXPECT_EQ(dev.core().stats().late, 0u);
}

// Notes handed to the background still count as queued (credit, Status.queue_free), and a seek drops
// them with the rest of the schedule.
TEST_P(PreparedNotes, HandedOverNotesCountAsQueuedAndSeekDropsThem) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.open_exact();
  dev.advance(5);
  const std::uint16_t free_before = host.status().queue_free;
  const std::uint32_t horizon = hz * fw::Core::kPrepareAheadMs / 1000;
  const std::uint64_t t = dev.tick() + horizon + 30;
  host.notes({{t, 50, 60.0, 0.2},
              {t, 50, 70.0, 0.2},
              {t + 1, 50, 80.0, 0.2},
              {t + 2, 50, 90.0, 0.2},
              {t + 3, 50, 100.0, 0.2}});
  dev.advance(36);  // handed over one per tick from t − horizon on; the status below stays short of t
  EXPECT_EQ(dev.core().prepared_pending(), 5u);
  EXPECT_EQ(dev.core().queued_notes(), 5u);
  EXPECT_EQ(host.status().queue_free, free_before - 1);
  host.transport(p::TransportOp::seek, 0);
  dev.advance(40);
  EXPECT_EQ(dev.core().queued_notes(), 0u);
  EXPECT_EQ(dev.core().stats().started, 0u);
  EXPECT_EQ(host.status().queue_free, free_before);
}

INSTANTIATE_TEST_SUITE_P(TickRates, PreparedNotes, ::testing::Values(1000u, 10000u),
                         [](const ::testing::TestParamInfo<std::uint32_t>& i) {
                           return std::to_string(i.param / 1000) + "kHz";
                         });

}  // namespace
}  // namespace hmp::test
