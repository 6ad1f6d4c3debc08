// LoopbackTransport: order-preserving in both directions, timeouts that really wait, close from either
// end seen by the other after what was queued, counters that match what the test sent.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <thread>

#include "host/transport/loopback_transport.hpp"

namespace {

using namespace std::chrono_literals;
using hmp::protocol::Report;
using hmp::transport::LoopbackTransport;
using hmp::transport::Received;

void fill(Report& r, std::uint32_t n) {
  for (std::size_t i = 0; i < hmp::protocol::kReportSize; ++i)
    r[i] = static_cast<std::uint8_t>((n * 31 + i * 7) & 0xFF);
}

TEST(TransportLoopback, DeliversInOrderBothWays) {
  auto [host, device] = LoopbackTransport::make_pair("test");
  for (std::uint32_t n = 0; n < 100; ++n) {
    Report r;
    fill(r, n);
    ASSERT_TRUE(host->send(r));
    fill(r, 1000 + n);
    ASSERT_TRUE(device->send(r));
  }
  for (std::uint32_t n = 0; n < 100; ++n) {
    Report got, want;
    ASSERT_EQ(device->receive(got, 0us), Received::report);
    fill(want, n);
    EXPECT_EQ(0, std::memcmp(got, want, sizeof(got)));
    ASSERT_EQ(host->receive(got, 0us), Received::report);
    fill(want, 1000 + n);
    EXPECT_EQ(0, std::memcmp(got, want, sizeof(got)));
  }
  EXPECT_EQ(host->counters().sent, 100u);
  EXPECT_EQ(host->counters().received, 100u);
  EXPECT_EQ(host->name(), "test:host");
  EXPECT_EQ(device->name(), "test:device");
}

TEST(TransportLoopback, TimeoutWaitsAndAReportWakesTheReceiver) {
  auto [host, device] = LoopbackTransport::make_pair();
  Report r{};
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(host->receive(r, 30ms), Received::timeout);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 30ms);

  std::thread sender([&, d = device.get()] {
    std::this_thread::sleep_for(20ms);
    Report s;
    fill(s, 5);
    d->send(s);
  });
  t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(host->receive(r, 5s), Received::report);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 2s);
  sender.join();
  Report want;
  fill(want, 5);
  EXPECT_EQ(0, std::memcmp(r, want, sizeof(r)));
}

TEST(TransportLoopback, ClosingOneEndClosesTheLinkAfterQueuedReports) {
  auto [host, device] = LoopbackTransport::make_pair();
  Report r;
  fill(r, 1);
  ASSERT_TRUE(device->send(r));
  device.reset();  // the device end goes away
  EXPECT_FALSE(host->is_open());
  EXPECT_EQ(host->receive(r, 1s), Received::report);
  EXPECT_EQ(host->receive(r, 1s), Received::closed);
  EXPECT_FALSE(host->send(r));
  EXPECT_EQ(host->closed_reason(), "closed by loopback:device");
}

TEST(TransportLoopback, CloseWakesABlockedReceiver) {
  auto [host, device] = LoopbackTransport::make_pair();
  Received got = Received::report;
  std::thread reader([&, h = host.get()] {
    Report r;
    got = h->receive(r, 10s);
  });
  std::this_thread::sleep_for(20ms);
  host->close();
  reader.join();
  EXPECT_EQ(got, Received::closed);
}

}  // namespace
