// SimTransport: the simulated device behind the Transport interface. The Hello handshake returns what
// the firmware core says about itself (board sim, its tick rate, a Status after the HelloReply); in
// virtual time receive() advances the device clock by exactly the timeout's ticks; in real time the
// device clock follows the host's steady clock (checked with Sync round trips, tolerance for a loaded
// machine).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "firmware/core.hpp"
#include "host/transport/handshake.hpp"
#include "host/transport/sim_transport.hpp"

namespace {

using namespace std::chrono_literals;
using hmp::transport::Received;
using hmp::transport::SimTransport;

SimTransport::Options virtual_time(std::uint32_t hz) {
  SimTransport::Options o;
  o.tick_hz = hz;
  o.pacing = SimTransport::Pacing::virtual_time;
  return o;
}

TEST(TransportSim, HelloHandshakeIdentifiesTheSimulatedBoard) {
  for (const std::uint32_t hz : {1000u, 4000u}) {
    SimTransport sim(virtual_time(hz));
    const auto id = hmp::transport::say_hello(sim, 1, 100ms);
    ASSERT_TRUE(id.has_value());
    EXPECT_TRUE(id->compatible());
    EXPECT_EQ(id->hello.board, hmp::protocol::Board::sim);
    EXPECT_EQ(id->hello.tick_hz, hz);
    EXPECT_EQ(id->hello.fw_major, hmp::fw::kFirmwareMajor);
    EXPECT_EQ(hmp::transport::firmware_version(id->hello), "0.1.0");
    ASSERT_TRUE(id->status.has_value());
    EXPECT_EQ(id->status->state, hmp::protocol::State::idle);
    EXPECT_EQ(id->status->last_seq, 1u);
    EXPECT_STREQ(hmp::transport::board_name(id->hello.board), "sim");
  }
}

TEST(TransportSim, VirtualTimeRunsExactlyTheTimeoutsTicks) {
  SimTransport sim(virtual_time(1000));
  hmp::protocol::Report r;
  // Drain whatever the device says at start-up, then measure a quiet stretch.
  while (sim.receive(r, 0us) == Received::report) {
  }
  const std::uint64_t before = sim.with_device([](hmp::sim::SimDevice& d) { return d.tick(); });
  sim.advance(7);
  EXPECT_EQ(sim.with_device([](hmp::sim::SimDevice& d) { return d.tick(); }), before + 7);
  // Idle status every ≤ 100 ms: a 250 ms wait must see one, after at most 100 ticks.
  ASSERT_EQ(sim.receive(r, 250ms), Received::report);
  const std::uint64_t after = sim.with_device([](hmp::sim::SimDevice& d) { return d.tick(); });
  EXPECT_LE(after - before - 7, 100u);
}

TEST(TransportSim, RealTimeClockFollowsTheHostClock) {
  SimTransport sim;  // real time, default tick rate
  const double hz = sim.tick_hz();
  auto sync_tick = [&](std::uint16_t seq) -> std::optional<std::uint64_t> {
    hmp::protocol::Report r;
    hmp::protocol::encode(hmp::protocol::make(hmp::protocol::Type::sync, seq), r);
    if (!sim.send(r)) return std::nullopt;
    const auto deadline = std::chrono::steady_clock::now() + 2s;
    while (std::chrono::steady_clock::now() < deadline) {
      if (sim.receive(r, 100ms) != Received::report) continue;
      hmp::protocol::Message m;
      if (hmp::protocol::decode(r, m) == hmp::protocol::ErrorCode::none && m.type == hmp::protocol::Type::sync_reply) {
        return m.sync_reply.tick;
      }
    }
    return std::nullopt;
  };
  const auto t0 = std::chrono::steady_clock::now();
  const auto a = sync_tick(1);
  std::this_thread::sleep_for(300ms);
  const auto b = sync_tick(2);
  const double host_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(a && b);
  const double device_s = static_cast<double>(*b - *a) / hz;
  EXPECT_GT(device_s, 0.25);
  EXPECT_LE(device_s, host_s + 0.01);
  sim.close();
  hmp::protocol::Report r;
  // Drain, then the link reports closed.
  Received got;
  while ((got = sim.receive(r, 100ms)) == Received::report) {
  }
  EXPECT_EQ(got, Received::closed);
  EXPECT_FALSE(sim.send(r));
}

TEST(TransportSim, NamesOfStatesAndFaults) {
  EXPECT_STREQ(hmp::transport::state_name(hmp::protocol::State::playing), "playing");
  EXPECT_EQ(hmp::transport::fault_names(0), "none");
  EXPECT_EQ(hmp::transport::fault_names(hmp::protocol::fault_estop | hmp::protocol::fault_string_slack),
            "estop,string_slack");
  EXPECT_EQ(hmp::transport::board_flag_names(0), "none");
  EXPECT_EQ(hmp::transport::board_flag_names(hmp::protocol::board_clock_fallback | hmp::protocol::board_no_usb),
            "clock_fallback,no_usb");
  EXPECT_EQ(hmp::transport::board_flag_names(0x80), "bit7");
}

}  // namespace
