// Hello is what a host resends until a board that is still starting answers (transport::say_hello: the
// same report, the same sequence number, every 100 ms). The device answers every copy, and a copy that
// arrives after the first changes nothing: the session each opens is the same one (notes flushed, voices
// silenced, faults acknowledged, settings and presets kept), and the host's next report is played.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/firmware/host_link.hpp"

namespace hmp::test {
namespace {

float peak(const std::vector<float>& v) {
  float m = 0.0f;
  for (float x : v) m = std::max(m, std::abs(x));
  return m;
}

TEST(FirmwareHello, TwentyHellosInARowAreEachAnsweredAndOpenOneIdleSession) {
  sim::SimDevice dev;
  HostLink host(dev);
  host.open_exact();
  dev.advance(1);
  // A session in full swing: a long note sounding, one queued for later, then a fault latched.
  host.long_note({dev.tick() + 2, 5000, 80.0, 0.8});
  host.notes({{dev.tick() + 3000, 100, 120.0, 0.5}});
  EXPECT_GT(peak(host.run(100)), 0.3f);
  host.estop();
  dev.advance(2);
  host.collect();
  ASSERT_NE(host.status().faults & p::fault_estop, 0u) << "the test must start from a latched fault";

  constexpr int kHellos = 20;
  const std::uint16_t seq = host.repeated_hello(kHellos, 5);
  dev.advance(5);
  const Replies r = host.collect();
  EXPECT_TRUE(r.errors.empty()) << "first error code " << static_cast<int>(r.errors.front().code);
  ASSERT_EQ(r.hellos.size(), static_cast<std::size_t>(kHellos)) << "every Hello is answered";
  for (const p::HelloReply& h : r.hellos) {
    EXPECT_EQ(h.protocol_version, p::kProtocolVersion);
    EXPECT_EQ(h.tick_hz, dev.core().tick_hz());
  }
  // Each HelloReply is followed by a Status; every Status from the first answer on shows the same idle,
  // empty, fault-free session that processed the Hello.
  ASSERT_GE(r.statuses.size(), static_cast<std::size_t>(kHellos));
  const p::Status& first = r.statuses.front();
  for (const p::Status& s : r.statuses) {
    EXPECT_EQ(s.last_seq, seq);
    EXPECT_EQ(s.state, p::State::idle);
    EXPECT_EQ(s.faults, 0u);
    EXPECT_EQ(s.active_voices, 0u);
    EXPECT_EQ(s.queue_free, first.queue_free);
    EXPECT_EQ(s.started, first.started);
    EXPECT_EQ(s.rejected, first.rejected);
  }
  // The queued note of the old session is gone: nothing sounds, even past its start.
  EXPECT_EQ(peak(host.run(3200)), 0.0f);
  EXPECT_TRUE(host.collect().started.empty());

  // The next report of the host is the session's first: played on its tick.
  host.play();
  dev.advance(1);
  const std::uint64_t start = dev.tick() + 10;
  const std::uint16_t note_seq = host.notes({{start, 200, 100.0, 0.6}});
  EXPECT_GT(peak(host.run(300)), 0.1f);
  const Replies after = host.collect();
  ASSERT_EQ(after.started.size(), 1u);
  EXPECT_EQ(after.started[0].seq, note_seq);
  EXPECT_EQ(after.started[0].actual_tick, static_cast<std::uint32_t>(start));
  EXPECT_TRUE(after.errors.empty());
}

}  // namespace
}  // namespace hmp::test
