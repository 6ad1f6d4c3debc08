// EtherTransport over real unix datagram sockets, the peer played by a plain socket of the test (as
// QEMU's `-netdev dgram` back-end is): reports go out as frames whose bytes the test checks with
// shared/framing's layout, frames coming in are delivered whole, datagrams that are not ours are
// dropped and counted, a peer that goes away closes the link, and close() wakes a blocked receive().
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <thread>

#include "host/transport/ether_transport.hpp"
#include "shared/framing/ether_frame.hpp"

namespace {

using namespace std::chrono_literals;
namespace ether = hmp::framing::ether;
using hmp::transport::EtherTransport;
using hmp::transport::Received;
using Bytes = std::array<std::uint8_t, hmp::protocol::kReportSize>;

const hmp::protocol::Report& as_report(const Bytes& b) {
  return *reinterpret_cast<const hmp::protocol::Report*>(b.data());
}

// A private folder with the transport bound at host.sock and the test's socket (the "NIC") at nic.sock.
struct Link {
  std::filesystem::path dir;
  std::unique_ptr<EtherTransport> host;
  int nic = -1;
  sockaddr_un host_addr{};

  Link() {
    char tmpl[] = "/tmp/hmp-ether-test-XXXXXX";
    dir = ::mkdtemp(tmpl);
    host = EtherTransport::bind((dir / "host.sock").string(), "qemu:net");
    nic = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un nic_addr{};
    nic_addr.sun_family = AF_UNIX;
    std::strcpy(nic_addr.sun_path, (dir / "nic.sock").c_str());
    EXPECT_EQ(::bind(nic, reinterpret_cast<const sockaddr*>(&nic_addr), sizeof nic_addr), 0);
    host_addr.sun_family = AF_UNIX;
    std::strcpy(host_addr.sun_path, (dir / "host.sock").c_str());
    host->connect((dir / "nic.sock").string());
  }
  ~Link() {
    if (nic >= 0) ::close(nic);
    host.reset();
    std::filesystem::remove_all(dir);
  }
  void nic_send(const std::uint8_t* data, std::size_t size) const {
    ASSERT_EQ(::sendto(nic, data, size, 0, reinterpret_cast<const sockaddr*>(&host_addr), sizeof host_addr),
              static_cast<ssize_t>(size));
  }
};

TEST(EtherTransport, ReportsTravelWholeAsOneFrameEachWay) {
  Link link;
  std::mt19937 rng(5);
  for (int i = 0; i < 200; ++i) {
    Bytes out;
    for (auto& b : out) b = static_cast<std::uint8_t>(rng());
    ASSERT_TRUE(link.host->send(as_report(out)));
    std::uint8_t frame[256];
    const ssize_t n = ::recv(link.nic, frame, sizeof frame, 0);
    ASSERT_EQ(n, 78);
    EXPECT_EQ(frame[12], 0x88);
    EXPECT_EQ(frame[13], 0xB5);
    EXPECT_EQ(std::memcmp(frame + 6, ether::kHostMac, 6), 0);
    EXPECT_EQ(std::memcmp(frame + 14, out.data(), out.size()), 0);

    Bytes in;
    for (auto& b : in) b = static_cast<std::uint8_t>(rng());
    std::uint8_t reply[ether::kFrameBytes];
    ether::build(in.data(), ether::kDeviceMac, ether::kHostMac, reply);
    link.nic_send(reply, sizeof reply);
    Bytes got{};
    ASSERT_EQ(link.host->receive(*reinterpret_cast<hmp::protocol::Report*>(got.data()), 1s), Received::report);
    EXPECT_EQ(got, in);
  }
  EXPECT_EQ(link.host->counters().sent, 200u);
  EXPECT_EQ(link.host->counters().received, 200u);
  EXPECT_EQ(link.host->counters().dropped, 0u);
}

TEST(EtherTransport, ForeignDatagramsAreDroppedAndCountedWithoutCostingTheNextReport) {
  Link link;
  Bytes in{};
  in[0] = 0x83;
  std::uint8_t frame[ether::kFrameBytes + 1];
  ether::build(in.data(), ether::kDeviceMac, ether::kHostMac, frame);
  link.nic_send(frame, ether::kFrameBytes - 1);  // cut short
  link.nic_send(frame, ether::kFrameBytes + 1);  // one byte more
  frame[13] = 0x00;                              // another EtherType
  link.nic_send(frame, ether::kFrameBytes);
  frame[13] = 0xB5;
  link.nic_send(frame, ether::kFrameBytes);
  Bytes got{};
  ASSERT_EQ(link.host->receive(*reinterpret_cast<hmp::protocol::Report*>(got.data()), 1s), Received::report);
  EXPECT_EQ(got, in);
  EXPECT_EQ(link.host->counters().dropped, 3u);
  EXPECT_EQ(link.host->receive(*reinterpret_cast<hmp::protocol::Report*>(got.data()), 20ms), Received::timeout);
}

TEST(EtherTransport, APeerThatIsGoneClosesTheLinkOnTheNextSend) {
  Link link;
  ::close(link.nic);
  link.nic = -1;
  std::filesystem::remove(link.dir / "nic.sock");
  Bytes out{};
  EXPECT_FALSE(link.host->send(as_report(out)));
  EXPECT_FALSE(link.host->is_open());
  EXPECT_NE(link.host->closed_reason().find("peer closed qemu:net"), std::string::npos) << link.host->closed_reason();
  Bytes got{};
  EXPECT_EQ(link.host->receive(*reinterpret_cast<hmp::protocol::Report*>(got.data()), 0ms), Received::closed);
}

TEST(EtherTransport, CloseWakesABlockedReceive) {
  Link link;
  Received r = Received::report;
  const auto start = std::chrono::steady_clock::now();
  std::thread reader([&] {
    Bytes got{};
    r = link.host->receive(*reinterpret_cast<hmp::protocol::Report*>(got.data()), 10s);
  });
  std::this_thread::sleep_for(50ms);
  link.host->close();
  reader.join();
  EXPECT_EQ(r, Received::closed);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
  EXPECT_EQ(link.host->closed_reason(), "closed by the host");
}

TEST(EtherTransport, BindingWherePathCannotBeIsOneLine) {
  try {
    EtherTransport::bind("/nonexistent-dir/host.sock", "x");
    ADD_FAILURE() << "bound";
  } catch (const hmp::transport::TransportError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot bind /nonexistent-dir/host.sock"), std::string::npos) << e.what();
  }
}

}  // namespace
