// Flow control (design §9): a bounded note queue, Status.queue_free in note reports, a report that does not
// fit is refused whole with Error queue_full and nothing is lost when the host re-sends it; the device's
// reports are numbered without a gap or a 0.
#include <gtest/gtest.h>

#include <deque>
#include <map>
#include <set>

#include "tests/firmware/host_link.hpp"

namespace hmp::test {
namespace {

constexpr std::uint16_t kFreeWhenEmpty = 256 / p::kNotesPerBatch;

// Device reports are numbered by the host's rule (docs/protocol.md): one more each, and after 65535 comes
// 1; 0 never names a report. A Sync a tick for 70,000 ticks: its replies and the Statuses pass 65535.
TEST(FirmwareFlow, DeviceReportsAreNumberedInOrderAndSkipZeroWhenTheyWrap) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.hello();
  std::uint16_t last = 0;
  std::size_t reports = 0;
  bool wrapped = false;
  for (int i = 0; i < 70000; ++i) {
    host.sync(0);
    dev.advance(1);
    p::Report r;
    while (dev.poll_report(r)) {
      p::Message m;
      ASSERT_EQ(p::decode(r, m), p::ErrorCode::none);
      ASSERT_NE(m.seq, 0u) << "report " << reports;
      if (last != 0) {
        ASSERT_EQ(m.seq, last == 0xFFFF ? 1u : last + 1u) << "report " << reports;
      }
      wrapped = wrapped || (last == 0xFFFF && m.seq == 1);
      last = m.seq;
      ++reports;
    }
  }
  EXPECT_TRUE(wrapped) << reports << " reports";
}

TEST(FirmwareFlow, QueueFreeCountsNoteReportsAndABatchThatDoesNotFitIsRefusedWhole) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.hello();  // not playing: nothing leaves the queue
  EXPECT_EQ(host.status().queue_free, kFreeWhenEmpty);
  const std::uint64_t far = dev.tick() + 100000;
  // 51 full reports take 255 slots.
  for (std::uint16_t i = 0; i < kFreeWhenEmpty; ++i) {
    std::vector<TestNote> batch(p::kNotesPerBatch, TestNote{far + i, 10, 80.0, 0.5});
    host.notes(batch);
    if (i % 8 == 7) dev.advance(1);
  }
  p::Status s = host.status();
  EXPECT_EQ(s.queue_free, 0u);
  EXPECT_EQ(s.last_seq, host.seq());
  EXPECT_EQ(dev.core().queued_notes(), 255u);
  host.collect();
  // One slot is left: a one-note report fits (the host was told 0 reports, the device is not stricter
  // than it must be), a two-note report does not, and is not half-taken.
  const std::uint16_t two = host.notes({{far, 10, 80.0, 0.5}, {far, 10, 81.0, 0.5}});
  dev.advance(1);
  Replies r = host.collect();
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].code, p::ErrorCode::queue_full);
  EXPECT_EQ(r.errors[0].seq, two);
  EXPECT_EQ(dev.core().queued_notes(), 255u);
  host.long_note({far + 1, 10, 80.0, 0.5});
  dev.advance(1);
  EXPECT_EQ(dev.core().queued_notes(), 256u);
  const std::uint16_t refused_long = host.long_note({far + 1, 10, 80.0, 0.5});
  dev.advance(1);
  r = host.collect();
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.errors[0].code, p::ErrorCode::queue_full);
  EXPECT_EQ(r.errors[0].seq, refused_long);
  s = host.status();
  EXPECT_EQ(s.rejected, 2u);  // a report sent without credit is refused like any other
  EXPECT_EQ(dev.core().stats().queue_full, 2u);
  EXPECT_NE(s.faults & p::fault_queue_overflow, 0u);
  EXPECT_EQ(s.last_seq, refused_long);  // processed, though refused
  EXPECT_EQ(s.state, p::State::idle);   // the fault is a record, it does not stop anything
}

// A song longer than the queue, sent by a greedy host that ignores queue_free and simply re-sends what
// the device refused. Every note must start exactly once, on its tick.
TEST(FirmwareFlow, GreedyHostThatResendsRefusedReportsLosesNothing) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.open_exact();
  dev.advance(1);
  const std::uint64_t t0 = dev.tick() + 200;
  std::deque<std::vector<TestNote>> to_send;
  std::set<std::uint64_t> expected_starts;
  for (int b = 0; b < 600; ++b) {  // 3000 notes, 2 ticks apart: 6 s, far more than 256 notes of queue
    std::vector<TestNote> batch;
    for (int k = 0; k < 5; ++k) {
      const std::uint64_t start = t0 + static_cast<std::uint64_t>(b * 5 + k) * 2;
      batch.push_back({start, 3, 100.0, 0.2});
      expected_starts.insert(start);
    }
    to_send.push_back(batch);
  }
  std::map<std::uint16_t, std::vector<TestNote>> in_flight;  // seq → batch, until accepted or refused
  std::map<std::uint64_t, int> starts;                       // scheduled tick → times started
  std::uint32_t refused = 0;
  while (dev.tick() < t0 + 6200) {
    if (!to_send.empty()) {
      in_flight[host.notes(to_send.front())] = to_send.front();
      to_send.pop_front();
    }
    dev.advance(1);
    if (dev.tick() % 50 == 0) host.sync(0);
    const Replies r = host.collect();
    for (const p::Error& e : r.errors) {
      ASSERT_EQ(e.code, p::ErrorCode::queue_full);
      ++refused;
      to_send.push_front(in_flight.at(e.seq));  // re-send it first (it is the earliest outstanding)
    }
    for (const p::StartedEntry& e : r.started) {
      ASSERT_EQ(e.actual_tick, e.scheduled_tick);
      ++starts[e.scheduled_tick];
    }
  }
  EXPECT_GT(refused, 100u) << "the test must actually overflow the queue";
  ASSERT_EQ(starts.size(), expected_starts.size());
  for (const auto& [tick, times] : starts) {
    EXPECT_EQ(times, 1) << "tick " << tick;
    EXPECT_TRUE(expected_starts.count(static_cast<std::uint64_t>(tick) | (t0 & ~0xFFFFFFFFull)));
  }
  const p::Status s = host.status();
  EXPECT_EQ(s.started, expected_starts.size());
  EXPECT_EQ(s.late, 0u);
  EXPECT_EQ(s.rejected, refused);
  EXPECT_EQ(dev.core().stats().queue_full, refused);
}

// A host that follows the credit rule (transport::HostSession: queue_free minus the note reports in flight)
// is never refused: it never sees queue_full, and its credit runs out before the device's queue does.
TEST(FirmwareFlow, HostThatFollowsQueueFreeIsNeverRefused) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.open_exact();
  dev.advance(1);
  const std::uint64_t t0 = dev.tick() + 100;
  std::size_t next = 0, started = 0;
  const std::size_t batches = 400;
  bool credit_ran_out = false;
  while (dev.tick() < t0 + batches * 10 + 100) {
    while (host.credit() > 0 && next < batches) {
      std::vector<TestNote> batch;
      for (std::uint64_t k = 0; k < 5; ++k) batch.push_back({t0 + next * 10 + k * 2, 2, 120.0, 0.3});
      host.notes(batch);
      ++next;
    }
    credit_ran_out = credit_ran_out || (next > 0 && next < batches && host.credit() <= 0);
    dev.advance(1);
    if (dev.tick() % 50 == 0) host.sync(0);
    const Replies r = host.collect();
    ASSERT_TRUE(r.errors.empty());
    started += r.started.size();
  }
  EXPECT_TRUE(credit_ran_out) << "the test never filled the device's queue";
  EXPECT_EQ(next, batches);
  EXPECT_EQ(started, batches * 5);
  EXPECT_EQ(dev.core().stats().queue_full, 0u);
  EXPECT_EQ(dev.core().faults(), 0u);
}

}  // namespace
}  // namespace hmp::test
