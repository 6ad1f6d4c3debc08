// usb-e2e's measuring program (tools/bench/usb-e2e.sh), run inside the Linux guest of the USB test on
// /dev/hidraw0 (the kernel's hidraw, the same path hmp's HID transport takes):
//  1. round trip: 2,000 Syncs, each written and its SyncReply read back before the next → median and p99 µs;
//  2. throughput: for 5 s, Notes reports of 5 notes (one tick each, starting 5 per ms from 200 ms ahead)
//     sent as fast as the device's credit allows (queue_free minus reports in flight); then waits for the
//     device's Status to show every note started. Prints notes/s sent and the device's counters.
// Numbering and credit are the host's session rules (host/transport/host_session.hpp), as hmp plays: the
// benchmark measures the link under the same rules, and never sends the reserved sequence number 0.
// Output: `usb-e2e rtt_median_us=… rtt_p99_us=… notes_per_s=… sent=… started=… rejected=… late=…`.
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "host/transport/host_session.hpp"
#include "shared/protocol/protocol.hpp"

namespace {

namespace p = hmp::protocol;
using Clock = std::chrono::steady_clock;

int g_fd = -1;
hmp::transport::HostSession g_session;  // numbers every report; counts note reports in flight for the credit

std::int64_t now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
}

// Numbers `m`, writes it and returns its number. A note report counts in flight from here on (before the
// write: a quick Status must already see it).
std::uint16_t send(p::Message m) {
  std::uint8_t buf[1 + p::kReportSize] = {0};  // report ID 0 first: usbhid drops it for unnumbered reports
  p::Report r;
  try {
    g_session.number(m, r);
  } catch (const std::logic_error&) {
    std::fprintf(stderr, "usb-e2e: cannot encode\n");
    _exit(1);
  }
  std::memcpy(buf + 1, r, sizeof r);
  if (::write(g_fd, buf, sizeof buf) != static_cast<ssize_t>(sizeof buf)) {
    std::perror("usb-e2e: write");
    _exit(1);
  }
  return m.seq;
}

// One device report within `timeout_ms`, decoded; false on timeout.
bool receive(p::Message& m, int timeout_ms) {
  pollfd pf{g_fd, POLLIN, 0};
  if (::poll(&pf, 1, timeout_ms) <= 0) return false;
  p::Report r;
  if (::read(g_fd, r, sizeof r) != static_cast<ssize_t>(sizeof r)) return false;
  return p::decode(r, m) == p::ErrorCode::none;
}

}  // namespace

int main(int argc, char** argv) {
  const char* path = argc > 1 ? argv[1] : "/dev/hidraw0";
  g_fd = ::open(path, O_RDWR);
  if (g_fd < 0) {
    std::perror(path);
    return 1;
  }
  send(p::make(p::Type::hello, 0));
  p::Message m;
  for (int i = 0; i < 100 && !g_session.status(); ++i) {
    if (receive(m, 50) && m.type == p::Type::status) g_session.on_status(m.status);
  }
  if (!g_session.status()) {
    std::fprintf(stderr, "usb-e2e: no Status after Hello\n");
    return 1;
  }
  // The device's newest Status (every Status received goes through the session, which keeps it).
  const auto status = []() -> const p::Status& { return *g_session.status(); };

  // 1. Round trips.
  std::vector<double> rtt;
  for (int i = 0; i < 2000; ++i) {
    p::Message s = p::make(p::Type::sync, 0);
    const std::int64_t t0 = now_us();
    s.sync.host_time_us = static_cast<std::uint64_t>(t0);
    send(s);
    for (;;) {
      if (!receive(m, 100)) {
        std::fprintf(stderr, "usb-e2e: no SyncReply within 100 ms\n");
        return 1;
      }
      if (m.type == p::Type::status) g_session.on_status(m.status);
      if (m.type == p::Type::sync_reply && m.sync_reply.host_time_us == static_cast<std::uint64_t>(t0)) break;
    }
    rtt.push_back(static_cast<double>(now_us() - t0));
  }
  std::sort(rtt.begin(), rtt.end());

  // 2. Throughput under the credit rule.
  p::Message settings = p::make(p::Type::settings, 0);
  settings.settings.watchdog_ms = 2000;
  send(settings);
  p::Message play = p::make(p::Type::transport, 0);
  play.transport.op = p::TransportOp::play;
  send(play);
  const p::Status at_start = status();
  const std::uint32_t started0 = at_start.started, rejected0 = at_start.rejected, late0 = at_start.late;
  const std::uint64_t first = at_start.tick + 200;
  std::uint64_t next_start = first;
  std::uint32_t sent = 0;
  const auto t_start = Clock::now();
  auto last_sync = t_start;
  while (Clock::now() - t_start < std::chrono::seconds(5)) {
    while (receive(m, 0)) {
      if (m.type == p::Type::status) g_session.on_status(m.status);
    }
    if (g_session.credit() > 0) {
      p::Message n = p::make(p::Type::notes, 0);
      n.notes.count = 5;
      n.notes.base_tick = static_cast<std::uint32_t>(next_start);
      for (std::uint8_t k = 0; k < 5; ++k) {
        n.notes.notes[k].offset = 0;
        n.notes.notes[k].duration_ticks = 1;
        n.notes.notes[k].freq_q20 = 100u << 20;
        n.notes.notes[k].amp_q16 = 1000;
      }
      send(n);
      next_start += 1;  // five notes a tick: the protocol's ceiling at one report per ms
      sent += 5;
    } else {
      if (receive(m, 1) && m.type == p::Type::status) g_session.on_status(m.status);
    }
    if (Clock::now() - last_sync > std::chrono::milliseconds(100)) {
      send(p::make(p::Type::sync, 0));
      last_sync = Clock::now();
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  // Wait until the device has started every note sent (or 3 s).
  const auto deadline = Clock::now() + std::chrono::seconds(3);
  while (Clock::now() < deadline && (status().started - started0) + (status().rejected - rejected0) < sent) {
    if (receive(m, 20) && m.type == p::Type::status) g_session.on_status(m.status);
  }
  const p::Status end = status();
  std::printf("usb-e2e rtt_median_us=%.0f rtt_p99_us=%.0f notes_per_s=%.0f sent=%u started=%u rejected=%u late=%u\n",
              rtt[rtt.size() / 2], rtt[rtt.size() * 99 / 100], sent / seconds, sent, end.started - started0,
              end.rejected - rejected0, end.late - late0);
  return 0;
}
