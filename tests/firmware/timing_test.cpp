// Notes start on their exact tick (design §8, §10): Started reports, output sample for sample against the
// shared Engine driven directly, late notes, the 32-bit base tick across the 2^32 wrap, both tick rates.
#include <gtest/gtest.h>

#include "tests/firmware/host_link.hpp"

namespace hmp::test {
namespace {

class FirmwareTiming : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(FirmwareTiming, NotesStartOnTheirExactTickAndOutputMatchesTheEngine) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.open_exact();
  dev.advance(5);
  host.collect();

  const std::uint64_t t0 = dev.tick() + 20;
  // Offsets across the whole 8-bit range of a batch, two notes on one tick, a second batch later.
  const std::vector<TestNote> notes = {
      {t0, 300, 80.0, 0.4},
      {t0 + 1, 50, 123.4, 0.3},
      {t0 + 1, 70, 210.0, 0.2},
      {t0 + 255, 40, 60.0, 0.5},
      {t0 + 400, hz / 4, 150.0, 0.25, static_cast<std::uint8_t>(envelope::Preset::violin)}};
  const std::vector<std::uint16_t> seqs = {host.notes({notes[0], notes[1], notes[2], notes[3]}),
                                           host.notes({notes[4]})};
  const std::uint64_t first = dev.tick() + 1;
  const std::size_t span = static_cast<std::size_t>(t0 + 400 + hz / 4 + 50 - first);
  const std::vector<float> got = host.run(span);
  ASSERT_TRUE(same_output(got, reference_output(notes, first, span, hz), first));

  const Replies r = host.collect();
  ASSERT_EQ(r.started.size(), notes.size());
  for (std::size_t i = 0; i < notes.size(); ++i) {
    const p::StartedEntry& e = r.started[i];
    EXPECT_EQ(e.seq, i < 4 ? seqs[0] : seqs[1]);
    EXPECT_EQ(e.index, i < 4 ? i : 0u);
    EXPECT_EQ(e.scheduled_tick, static_cast<std::uint32_t>(notes[i].start));
    EXPECT_EQ(e.actual_tick, e.scheduled_tick) << "note " << i;
  }
  const p::Status s = host.status();
  EXPECT_EQ(s.late, 0u);
  EXPECT_EQ(s.started, notes.size());
  EXPECT_EQ(s.rejected, 0u);
  EXPECT_EQ(s.faults, 0u);
}

TEST_P(FirmwareTiming, LateNoteStartsAtOnceAndIsCounted) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.open_exact();
  dev.advance(100);
  const std::uint64_t now = dev.tick();
  const TestNote late{now - 30, 200, 90.0, 0.5};
  host.notes({late});
  // It arrived during tick `now`; the next tick is the earliest it can start.
  TestNote actual = late;
  actual.start = now + 1;
  const std::vector<float> got = host.run(300);
  ASSERT_TRUE(same_output(got, reference_output({actual}, now + 1, 300, hz), now + 1));
  const Replies r = host.collect();
  ASSERT_EQ(r.started.size(), 1u);
  EXPECT_EQ(r.started[0].scheduled_tick, static_cast<std::uint32_t>(now - 30));
  EXPECT_EQ(r.started[0].actual_tick, static_cast<std::uint32_t>(now + 1));
  EXPECT_EQ(host.status().late, 1u);
}

TEST_P(FirmwareTiming, StatusComesAtLeastFiftyTimesASecondWhilePlaying) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.hello();
  host.play();
  dev.advance(10);
  host.collect();
  for (int second = 0; second < 2; ++second) {
    for (int k = 0; k < 10; ++k) {  // keep the watchdog fed
      host.sync(0);
      dev.advance(hz / 10);
    }
    const Replies r = host.collect();
    EXPECT_GE(r.statuses.size(), 50u);
    for (const p::Status& s : r.statuses) EXPECT_EQ(s.state, p::State::playing);
    // And never more than one per ten ticks at 1 kHz (the link has other traffic too).
    EXPECT_LE(r.statuses.size(), static_cast<std::size_t>(hz / 10 + 1));
  }
}

TEST_P(FirmwareTiming, HelloReplyAndSyncReportTheTickRateAndClock) {
  const std::uint32_t hz = GetParam();
  sim::SimDevice dev(hz);
  HostLink host(dev);
  host.hello();
  dev.advance(1);
  Replies r = host.collect();
  ASSERT_EQ(r.hellos.size(), 1u);
  EXPECT_EQ(r.hellos[0].tick_hz, hz);
  EXPECT_EQ(r.hellos[0].board, p::Board::sim);
  EXPECT_EQ(r.hellos[0].voices, synth::kVoiceCount);
  EXPECT_EQ(r.hellos[0].protocol_version, p::kProtocolVersion);
  EXPECT_EQ(r.hellos[0].preset_slots, envelope::kSlotCount);
  EXPECT_EQ(r.hellos[0].queue_capacity, 256u / p::kNotesPerBatch);

  dev.advance(1234);
  const std::uint64_t during = dev.tick();
  dev.set_subtick(0x40000000u);  // a quarter of the way to the next tick
  host.sync(987654321);
  dev.advance(3);
  r = host.collect();
  ASSERT_EQ(r.syncs.size(), 1u);
  EXPECT_EQ(r.syncs[0].host_time_us, 987654321u);
  EXPECT_EQ(r.syncs[0].tick, during);
  EXPECT_EQ(r.syncs[0].subtick, 0x40000000u);
}

INSTANTIATE_TEST_SUITE_P(TickRates, FirmwareTiming, ::testing::Values(1000u, 10000u),
                         [](const auto& p) { return std::to_string(p.param) + "Hz"; });

// The batch carries only the low 32 bits of its base tick; the device picks the 64-bit tick nearest its
// own clock, so notes right after the 2^32 wrap (and before it) land where the host meant them.
TEST(FirmwareTiming, BaseTickIsExtendedAcrossThe32BitWrap) {
  const std::uint64_t wrap = std::uint64_t{1} << 32;
  sim::SimDevice dev(1000, wrap - 100);
  HostLink host(dev);
  host.open_exact();
  dev.advance(2);
  const std::vector<TestNote> notes = {
      {wrap - 20, 60, 70.0, 0.5}, {wrap + 50, 60, 90.0, 0.5}, {wrap + 300, 60, 110.0, 0.5}};
  host.notes({notes[0]});
  host.notes({notes[1]});
  host.long_note(notes[2]);
  const std::uint64_t first = dev.tick() + 1;
  const std::size_t span = static_cast<std::size_t>(wrap + 400 - first);
  const std::vector<float> got = host.run(span);
  ASSERT_TRUE(same_output(got, reference_output(notes, first, span, 1000), first));
  const Replies r = host.collect();
  ASSERT_EQ(r.started.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.started[i].scheduled_tick, static_cast<std::uint32_t>(notes[i].start));
    EXPECT_EQ(r.started[i].actual_tick, static_cast<std::uint32_t>(notes[i].start));
  }
  EXPECT_GT(dev.tick(), wrap);
  EXPECT_EQ(host.status().late, 0u);
}

}  // namespace
}  // namespace hmp::test
