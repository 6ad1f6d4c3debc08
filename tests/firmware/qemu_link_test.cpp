// The qemu-an386 firmware's UART link under load (boards/cortex-m/serial_link.hpp): at a tick rate of
// 5 Hz the core takes only 4 reports per 200 ms, so a burst of 40 reports must fill its 16-report inbox.
// The board must then hold the line back (stop reading the UART until a tick makes room) rather than lose
// reports: every report is answered, in order, and the core never counts a report it had to turn away.
// Needs qemu-system-arm and the image (HMP_QEMU_ELF); skipped when either is missing.
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "host/player/device_link.hpp"
#include "host/transport/handshake.hpp"
#include "tests/firmware/qemu_runner.hpp"

namespace hmp::test {
namespace {

namespace p = hmp::protocol;
using namespace std::chrono_literals;

TEST(QemuLink, ABurstBeyondTheInboxWaitsInTheLineInsteadOfBeingLost) {
  if (const std::string why = qemu_missing(); !why.empty()) GTEST_SKIP() << why;
  QemuFirmware qemu(qemu_image_path(), "hz=5 exit-idle-ms=2000");
  transport::SerialTransport& link = qemu.link();
  std::uint16_t seq = 1;
  const auto id = transport::say_hello(link, seq, 10s);
  ASSERT_TRUE(id.has_value()) << qemu.log_text();
  ASSERT_EQ(id->hello.tick_hz, 5u);

  constexpr std::uint64_t kBurst = 40;  // 2.5 inboxes
  for (std::uint64_t i = 0; i < kBurst; ++i) {
    p::Message m = p::make(p::Type::sync, ++seq);
    m.sync.host_time_us = 1000 + i;
    p::Report r;
    ASSERT_TRUE(p::encode(m, r));
    ASSERT_TRUE(link.send(r));
  }
  std::vector<std::uint64_t> echoed;
  std::vector<double> arrival;  // tick + sub-tick of each Sync's arrival, as the device stamped it
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (echoed.size() < kBurst && std::chrono::steady_clock::now() < deadline) {
    p::Report r;
    if (link.receive(r, 100ms) != transport::Received::report) continue;
    p::Message m;
    if (p::decode(r, m) != p::ErrorCode::none || m.type != p::Type::sync_reply) continue;
    echoed.push_back(m.sync_reply.host_time_us);
    arrival.push_back(static_cast<double>(m.sync_reply.tick) + m.sync_reply.subtick / 4294967296.0);
  }
  ASSERT_EQ(echoed.size(), kBurst);
  for (std::uint64_t i = 0; i < kBurst; ++i) EXPECT_EQ(echoed[i], 1000 + i) << "reply " << i;
  // The board's sub-tick (SysTick's position in the tick) never lets an arrival time step back, and the
  // held-back burst spreads over several ticks.
  for (std::size_t i = 1; i < arrival.size(); ++i) EXPECT_GE(arrival[i], arrival[i - 1]) << "reply " << i;
  EXPECT_GE(arrival.back() - arrival.front(), 3.0);

  // Quiet now: the image exits 2 s after its last input byte (the inbox drains in 0.8 s); keep reading so its UART
  // never stalls.
  std::optional<int> code;
  const auto exit_deadline = std::chrono::steady_clock::now() + 20s;
  while (!(code = qemu.wait(0ms)) && std::chrono::steady_clock::now() < exit_deadline) {
    p::Report r;
    link.receive(r, 20ms);
  }
  ASSERT_EQ(code, 0);
  const FirmwareRun run = parse_firmware_log(qemu.log_text());
  // At 5 Hz the first answer takes up to a tick (200 ms): say_hello may have sent its Hello more than once.
  const auto hellos = static_cast<std::uint64_t>(id->hellos_sent);
  EXPECT_EQ(run.counters.at("link.frames"), kBurst + hellos);
  EXPECT_GE(run.counters.at("link.rx_held"), 1u) << "the burst never filled the inbox: the test proves nothing";
  EXPECT_EQ(run.counters.at("link.inbox_refused"), 0u);
  EXPECT_EQ(run.counters.at("core.inbox_full"), 0u);
  EXPECT_EQ(run.counters.at("core.packets"), kBurst + hellos);
  EXPECT_EQ(run.counters.at("core.faults"), 0u);
}

// The host is up before the board: the emulated UART drops everything for the board's first 500 ms (as the
// USART of a board still starting does), so the first Hellos are lost. The player's own greeting (its
// default 1 s deadline) must still connect, by sending the Hello again.
TEST(QemuLink, AHostThatStartsBeforeTheBoardConnectsWithinTheDeadline) {
  if (const std::string why = qemu_missing(); !why.empty()) GTEST_SKIP() << why;
  QemuFirmware qemu(qemu_image_path(), "listen-after-ms=500 exit-idle-ms=1000");
  const auto t0 = std::chrono::steady_clock::now();
  {
    player::DeviceLink device(qemu.link());
    ASSERT_EQ(device.connect().protocol_version, p::kProtocolVersion) << qemu.log_text();
  }
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 400ms) << "the board answered while it should be deaf";
  std::optional<int> code;
  const auto exit_deadline = std::chrono::steady_clock::now() + 20s;
  while (!(code = qemu.wait(0ms)) && std::chrono::steady_clock::now() < exit_deadline) {
    p::Report r;
    qemu.link().receive(r, 20ms);
  }
  ASSERT_EQ(code, 0) << qemu.log_text();
  const FirmwareRun run = parse_firmware_log(qemu.log_text());
  EXPECT_GE(run.counters.at("link.rx_lost"), 1u) << "no Hello was lost: the test proves nothing";
  EXPECT_GE(run.counters.at("link.frames"), 1u);
  EXPECT_EQ(run.counters.at("core.faults"), 0u);
}

}  // namespace
}  // namespace hmp::test
