// SerialTransport over a real pty pair (the kind of link QEMU's `-serial pty` gives) and over unix
// sockets: reports round-trip byte-exact both ways, garbage and corrupted frames are dropped and
// counted without costing the next intact report, and a peer that goes away is reported as closed.
// The expected bytes are the reports the test itself generated; corruptions are made here with
// framing::encode plus byte surgery, independently of the transport's writer.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "host/common/error.hpp"
#include "host/transport/serial_transport.hpp"
#include "shared/framing/framing.hpp"

namespace {

using namespace std::chrono_literals;
using hmp::transport::Received;
using hmp::transport::SerialTransport;
using hmp::transport::TransportError;
using Bytes = std::array<std::uint8_t, hmp::protocol::kReportSize>;

const hmp::protocol::Report& as_report(const Bytes& b) {
  return *reinterpret_cast<const hmp::protocol::Report*>(b.data());
}

Bytes random_report(std::mt19937& rng) {
  Bytes r;
  for (auto& b : r) b = static_cast<std::uint8_t>(rng());
  return r;
}

// A fresh pty: the master stays a raw fd the test owns, the slave path is opened by the transport.
struct Pty {
  int master = -1;
  std::string slave;
  Pty() {
    master = ::posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) return;
    slave = ::ptsname(master);
  }
  ~Pty() {
    if (master >= 0) ::close(master);
  }
};

// Both ends of a pty as transports: `host` opens the slave by path (as a user would open QEMU's
// /dev/pts/N); `device` adopts the master.
struct PtyLink {
  Pty pty;
  std::unique_ptr<SerialTransport> host, device;
  PtyLink() {
    host = SerialTransport::open(pty.slave);
    device = SerialTransport::adopt(::dup(pty.master), "pty-master");
  }
};

void write_raw(int fd, const std::vector<std::uint8_t>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    ASSERT_GT(n, 0) << std::strerror(errno);
    done += static_cast<std::size_t>(n);
  }
}

std::vector<std::uint8_t> frame_of(const Bytes& report) {
  std::vector<std::uint8_t> out(hmp::framing::kMaxFrame);
  out.resize(hmp::framing::encode(report.data(), report.size(), out.data(), out.size()));
  return out;
}

Bytes receive_one(hmp::transport::Transport& t, Received expect = Received::report) {
  Bytes got{};
  hmp::protocol::Report r{};
  EXPECT_EQ(t.receive(r, 2s), expect);
  std::memcpy(got.data(), r, got.size());
  return got;
}

TEST(TransportSerial, PtyRoundTripsReportsBothWays) {
  PtyLink link;
  ASSERT_FALSE(link.pty.slave.empty());
  std::mt19937 rng(7);
  std::vector<Bytes> down, up;
  // Every byte value, in particular those a cooked terminal would eat or translate (CR, LF, ^C, ^D,
  // ^S/^Q flow control, DEL) — the transport must have put the line in raw mode.
  for (int block = 0; block < 4; ++block) {
    Bytes r;
    for (std::size_t i = 0; i < r.size(); ++i) r[i] = static_cast<std::uint8_t>(block * 64 + static_cast<int>(i));
    down.push_back(r);
  }
  for (int i = 0; i < 200; ++i) down.push_back(random_report(rng));
  for (int i = 0; i < 200; ++i) up.push_back(random_report(rng));

  for (const Bytes& r : down) ASSERT_TRUE(link.host->send(as_report(r)));
  for (const Bytes& r : up) ASSERT_TRUE(link.device->send(as_report(r)));
  for (const Bytes& r : down) EXPECT_EQ(receive_one(*link.device), r);
  for (const Bytes& r : up) EXPECT_EQ(receive_one(*link.host), r);

  hmp::protocol::Report extra{};
  EXPECT_EQ(link.host->receive(extra, 20ms), Received::timeout);
  EXPECT_EQ(link.host->counters().sent, down.size());
  EXPECT_EQ(link.host->counters().received, up.size());
  EXPECT_EQ(link.device->counters().received, down.size());
  EXPECT_EQ(link.host->frame_counters().dropped(), 0u);
}

TEST(TransportSerial, GarbageAndCorruptFramesAreDroppedAndCounted) {
  Pty pty;
  auto host = SerialTransport::open(pty.slave);
  std::mt19937 rng(11);
  const Bytes a = random_report(rng), b = random_report(rng), c = random_report(rng), d = random_report(rng);

  // 1. A boot banner (no 0x00 in it) and then a frame with the leading delimiter a sender puts first.
  std::vector<std::uint8_t> stream = {'b', 'o', 'o', 't', ' ', 'v', '0', '.', '1', '\r', '\n', 0x00};
  for (auto x : frame_of(a)) stream.push_back(x);
  // 2. A frame with one byte flipped in the middle (never to 0x00, which would split it instead).
  std::vector<std::uint8_t> bad = frame_of(b);
  bad[30] = static_cast<std::uint8_t>(bad[30] ^ 0x5A);
  if (bad[30] == 0) bad[30] = 0x01;
  stream.insert(stream.end(), bad.begin(), bad.end());
  // 3. A frame cut in half (a reset mid-transfer), ended by a delimiter.
  std::vector<std::uint8_t> cut = frame_of(c);
  cut.resize(cut.size() / 2);
  cut.push_back(0x00);
  stream.insert(stream.end(), cut.begin(), cut.end());
  // 4. Random noise, zeros included, then a delimiter and an intact frame.
  for (int i = 0; i < 1000; ++i) stream.push_back(static_cast<std::uint8_t>(rng()));
  stream.push_back(0x00);
  for (auto x : frame_of(d)) stream.push_back(x);
  write_raw(pty.master, stream);

  EXPECT_EQ(receive_one(*host), a);
  EXPECT_EQ(receive_one(*host), d);  // b was corrupted, c cut: neither may come out
  hmp::protocol::Report extra{};
  EXPECT_EQ(host->receive(extra, 50ms), Received::timeout);

  const auto fc = host->frame_counters();
  EXPECT_EQ(fc.packets, 2u);
  // At least: banner, corrupted frame, cut frame (noise adds more, its count depends on its zeros).
  EXPECT_GE(fc.dropped(), 3u);
  EXPECT_EQ(host->counters().dropped, fc.dropped());
  EXPECT_TRUE(host->is_open());
}

TEST(TransportSerial, DetectsTheMasterSideClosing) {
  PtyLink link;
  std::mt19937 rng(3);
  const Bytes r = random_report(rng);
  ASSERT_TRUE(link.device->send(as_report(r)));
  EXPECT_EQ(receive_one(*link.host), r);
  // Everything referring to the master goes away, as when QEMU exits.
  link.device.reset();
  ::close(link.pty.master);
  link.pty.master = -1;
  const auto t0 = std::chrono::steady_clock::now();
  receive_one(*link.host, Received::closed);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
  EXPECT_FALSE(link.host->is_open());
  EXPECT_FALSE(link.host->closed_reason().empty());
  EXPECT_FALSE(link.host->send(as_report(r)));
}

TEST(TransportSerial, DetectsTheSlaveSideClosing) {
  PtyLink link;
  link.host.reset();
  receive_one(*link.device, Received::closed);
}

TEST(TransportSerial, CloseFromAnotherThreadWakesABlockedReceive) {
  PtyLink link;
  Received got = Received::report;
  const auto t0 = std::chrono::steady_clock::now();
  std::thread reader([&] {
    hmp::protocol::Report r{};
    got = link.host->receive(r, 10s);
  });
  std::this_thread::sleep_for(50ms);
  link.host->close();
  reader.join();
  EXPECT_EQ(got, Received::closed);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 2s);
  EXPECT_EQ(link.host->closed_reason(), "closed by the host");
}

TEST(TransportSerial, ReportsQueuedBeforeThePeerClosedAreStillDelivered) {
  int sv[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
  auto a = SerialTransport::adopt(sv[0], "a");
  auto b = SerialTransport::adopt(sv[1], "b");
  std::mt19937 rng(5);
  std::vector<Bytes> sent;
  for (int i = 0; i < 10; ++i) {
    sent.push_back(random_report(rng));
    ASSERT_TRUE(a->send(as_report(sent.back())));
  }
  a.reset();
  for (const Bytes& r : sent) EXPECT_EQ(receive_one(*b), r);
  receive_one(*b, Received::closed);
  EXPECT_FALSE(b->send(as_report(sent.front())));
}

TEST(TransportSerial, OpensAUnixSocketPathAsQemuChardevSocketGives) {
  const auto dir = std::filesystem::temp_directory_path() / ("hmp-serial-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "uart.sock").string();
  const int listener = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof(addr.sun_path) - 1);
  ASSERT_EQ(::bind(listener, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)), 0);
  ASSERT_EQ(::listen(listener, 1), 0);

  auto host = SerialTransport::open(path);
  auto device = SerialTransport::adopt(::accept(listener, nullptr, nullptr), "qemu-side");
  std::mt19937 rng(9);
  const Bytes down = random_report(rng), up = random_report(rng);
  ASSERT_TRUE(host->send(as_report(down)));
  ASSERT_TRUE(device->send(as_report(up)));
  EXPECT_EQ(receive_one(*device), down);
  EXPECT_EQ(receive_one(*host), up);
  EXPECT_EQ(host->name(), "serial:" + path);
  ::close(listener);
  std::filesystem::remove_all(dir);
}

// A path that is neither a tty, a pipe nor a socket is refused, and a file there is left as it was: the
// protocol's frames must not be written into a user's file given by mistake.
TEST(TransportSerial, ARegularFileOrAFolderIsRefusedAndLeftAlone) {
  const auto dir = std::filesystem::temp_directory_path() / ("hmp-serial-file-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "song.mid").string();
  std::ofstream(file) << "MThd precious";
  EXPECT_THROW(SerialTransport::open(file), hmp::BadInput);
  EXPECT_THROW(SerialTransport::open(dir.string()), hmp::BadInput);
  std::ifstream in(file);
  const std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept, "MThd precious");
  std::filesystem::remove_all(dir);
}

TEST(TransportSerial, AStalledPeerTimesOutInsteadOfBlockingForever) {
  int sv[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, sv), 0);
  const int small = 4096;
  ::setsockopt(sv[0], SOL_SOCKET, SO_SNDBUF, &small, sizeof(small));
  ::setsockopt(sv[1], SOL_SOCKET, SO_RCVBUF, &small, sizeof(small));
  SerialTransport::Options options;
  options.write_timeout = 100ms;
  auto a = SerialTransport::adopt(sv[0], "a", options);
  hmp::protocol::Report r{};
  int sent = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (a->send(r) && sent < 100000) ++sent;  // nobody reads sv[1]
  EXPECT_LT(sent, 100000);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 5s);
  EXPECT_NE(a->closed_reason().find("stalled"), std::string::npos) << a->closed_reason();
  ::close(sv[1]);
}

TEST(TransportSerial, OpenErrorsNameThePath) {
  try {
    SerialTransport::open("/nonexistent/ttyHMP0");
    FAIL() << "no exception";
  } catch (const TransportError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/ttyHMP0"), std::string::npos) << e.what();
  }
  // A pty slave path with a speed: ptys take any standard speed; a non-standard one is refused.
  Pty pty;
  SerialTransport::Options options;
  options.baud = 921600;
  EXPECT_NO_THROW(SerialTransport::open(pty.slave, options));
  options.baud = 12345;
  EXPECT_THROW(SerialTransport::open(pty.slave, options), TransportError);
}

}  // namespace
