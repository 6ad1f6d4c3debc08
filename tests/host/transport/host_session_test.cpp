// transport::HostSession, the session rules every host follows (docs/protocol.md, "Sequence numbers and
// flow control"), against a brute-force model that numbers reports with a 64-bit counter (no wrap) and
// counts in-flight note reports by scanning everything sent.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "host/transport/host_session.hpp"

namespace {

namespace p = hmp::protocol;
using hmp::transport::HostSession;

p::Message note_report() {
  p::Message m = p::make(p::Type::notes, 0);
  m.notes.count = 1;
  m.notes.notes[0].duration_ticks = 10;
  m.notes.notes[0].freq_q20 = 100u << 20;
  m.notes.notes[0].amp_q16 = 1000;
  return m;
}

p::Status status(std::uint16_t last_seq, std::uint16_t queue_free) {
  p::Status s;
  s.last_seq = last_seq;
  s.queue_free = queue_free;
  return s;
}

TEST(HostSession, NumbersSkipZeroWhenTheyWrap) {
  HostSession session;
  p::Report r;
  std::vector<std::uint16_t> seen;
  for (int i = 0; i < 0xFFFF + 3; ++i) {
    p::Message m = p::make(p::Type::sync, 0);
    seen.push_back(session.number(m, r));
    EXPECT_EQ(m.seq, seen.back());
    EXPECT_EQ(r[1] | r[2] << 8, seen.back()) << "the report carries its number";
  }
  EXPECT_EQ(seen.front(), 1);
  EXPECT_EQ(seen[0xFFFE], 0xFFFF);
  EXPECT_EQ(seen[0xFFFF], 1) << "after 0xFFFF comes 1: 0 never names a report";
  for (std::uint16_t s : seen) EXPECT_NE(s, 0);
}

TEST(HostSession, NoCreditBeforeTheFirstStatusAndNothingProcessed) {
  HostSession session;
  EXPECT_EQ(session.credit(), 0);
  EXPECT_FALSE(session.processed(1));
  session.on_status(status(0, 51));  // the device has processed nothing yet: last_seq 0
  EXPECT_EQ(session.credit(), 51);
  EXPECT_FALSE(session.processed(0));
  EXPECT_FALSE(session.processed(1));
}

TEST(HostSession, AnInvalidMessageIsTheCallersBugAndTakesNoNumber) {
  HostSession session;
  p::Message bad = p::make(p::Type::notes, 0);  // count 0: outside 1–5
  p::Report r;
  EXPECT_THROW(session.number(bad, r), std::logic_error);
  EXPECT_EQ(session.last_sent(), 0);
  EXPECT_EQ(session.in_flight(), 0u);
}

TEST(HostSession, RestartForgetsWhatWasInFlightButKeepsNumbering) {
  HostSession session;
  p::Report r;
  for (int i = 0; i < 5; ++i) {
    p::Message m = note_report();
    session.number(m, r);
  }
  EXPECT_EQ(session.in_flight(), 5u);
  session.restart(status(0, 40));
  EXPECT_EQ(session.in_flight(), 0u);
  EXPECT_EQ(session.credit(), 40);
  EXPECT_EQ(session.next_seq(), 6);
  EXPECT_EQ(session.take_seq(), 6);
  EXPECT_EQ(session.last_sent(), 6);
}

// Random traffic across several wraps: notes, other reports and Statuses that acknowledge some prefix of
// what was sent (in order, as the device processes), compared with a model that never wraps.
TEST(HostSession, CreditAndProcessedMatchABruteForceModelAcrossWraps) {
  std::mt19937_64 rng(20261124);
  HostSession session;
  struct Sent {
    std::uint64_t index;  // 1, 2, … without wrap
    bool note;
  };
  std::vector<Sent> sent;
  std::uint64_t acknowledged = 0;  // the model: every report up to this index was processed
  std::uint16_t queue_free = 0;
  bool have_status = false;
  p::Report r;
  for (int step = 0; step < 500000; ++step) {
    const int what = static_cast<int>(rng() % 10);
    if (what < 5) {
      p::Message m = what < 3 ? note_report() : p::make(p::Type::sync, 0);
      const std::uint16_t seq = session.number(m, r);
      sent.push_back({sent.size() + 1, what < 3});
      ASSERT_EQ(seq, static_cast<std::uint16_t>((sent.back().index - 1) % 0xFFFF + 1));
    } else if (what < 9 && acknowledged < sent.size()) {
      // The device processes 0…(all in flight) more reports; never more than 1000 behind (numbers in
      // flight are close together, as the rule assumes).
      const std::uint64_t behind = sent.size() - acknowledged;
      acknowledged += rng() % (behind + 1);
      if (sent.size() - acknowledged > 1000) acknowledged = sent.size() - 1000;
      queue_free = static_cast<std::uint16_t>(rng() % 60);
      const std::uint16_t last_seq =
          acknowledged == 0 ? 0 : static_cast<std::uint16_t>((acknowledged - 1) % 0xFFFF + 1);
      session.on_status(status(last_seq, queue_free));
      have_status = true;
    }
    std::int64_t notes_after = 0;
    for (auto it = sent.rbegin(); it != sent.rend() && it->index > acknowledged; ++it) notes_after += it->note;
    ASSERT_EQ(session.credit(), have_status ? static_cast<int>(queue_free) - notes_after : 0) << "step " << step;
    if (!sent.empty() && have_status && acknowledged > 0) {
      const std::uint64_t probe = sent.size() - rng() % std::min<std::uint64_t>(sent.size(), 500);
      const auto probe_seq = static_cast<std::uint16_t>((probe - 1) % 0xFFFF + 1);
      ASSERT_EQ(session.processed(probe_seq), probe <= acknowledged) << "step " << step << " probe " << probe;
    }
  }
  EXPECT_GT(sent.size(), 3u * 0xFFFF) << "the run crossed the wrap several times";
}

}  // namespace
