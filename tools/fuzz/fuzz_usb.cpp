// libFuzzer target for the USB device stack (firmware/usb) with the firmware core behind it: the input is
// a program of controller events — SETUP packets, OUT data of any length the controller could deliver,
// IN completions, bus resets, suspends, resumes and ticks, in any order. A simulated controller keeps the
// rules a real one keeps (one packet per armed transfer, never more bytes than armed, completions only
// for armed transfers) and traps when the stack breaks its side of the seam (arming twice, a packet over
// the endpoint's size, a transfer on a closed endpoint). Besides the sanitizers it traps on an output
// sample that is not finite or exceeds the gain, and on a device report that does not decode.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "firmware/core.hpp"
#include "firmware/usb/device.hpp"

namespace {

namespace protocol = hmp::protocol;
namespace usb = hmp::fw::usb;

struct Endpoint {
  bool open = false, armed = false, stalled = false;
  std::uint16_t max_packet = 0;
  std::uint8_t* buffer = nullptr;
  std::uint16_t len = 0;
};

struct Controller {
  Endpoint ep[2][2];  // [number][IN?]
  const hmp::fw::Core* core = nullptr;

  static Controller& self(void* c) { return *static_cast<Controller*>(c); }
  Endpoint& at(std::uint8_t addr) {
    const std::uint8_t n = addr & 0x7F;
    if (n > 1) __builtin_trap();  // the stack only has endpoints 0 and 1
    return ep[n][(addr & 0x80) ? 1 : 0];
  }
  void reset() {
    for (auto& pair : ep) pair[0] = pair[1] = Endpoint{};
    ep[0][0].open = ep[0][1].open = true;
    ep[0][0].max_packet = ep[0][1].max_packet = usb::kEp0Size;
  }
  usb::Dcd dcd() {
    usb::Dcd d;
    d.ctx = this;
    d.connect = [](void*, bool) {};
    d.set_address = [](void*, std::uint8_t a) {
      if (a > 127) __builtin_trap();
    };
    d.ep_open = [](void* c, std::uint8_t a, usb::EpType, std::uint16_t mps) {
      Endpoint& e = self(c).at(a);
      e = Endpoint{};
      e.open = true;
      e.max_packet = mps;
    };
    d.ep_close = [](void* c, std::uint8_t a) { self(c).at(a) = Endpoint{}; };
    d.ep_stall = [](void* c, std::uint8_t a) {
      if ((a & 0x7F) == 0) {  // both directions of endpoint 0, until the next SETUP
        self(c).ep[0][0].stalled = self(c).ep[0][1].stalled = true;
        return;
      }
      Endpoint& e = self(c).at(a);
      e.stalled = true;
      e.armed = false;
    };
    d.ep_clear_stall = [](void* c, std::uint8_t a) {
      Endpoint& e = self(c).at(a);
      e.stalled = false;
      e.armed = false;
    };
    d.ep_xfer = [](void* c, std::uint8_t a, std::uint8_t* buf, std::uint16_t len) {
      Endpoint& e = self(c).at(a);
      if (!e.open) return false;
      if (e.armed || len > e.max_packet || (len > 0 && buf == nullptr)) __builtin_trap();
      e.armed = true;
      e.buffer = buf;
      e.len = len;
      return true;
    };
    return d;
  }
};

void check_output(void* ctx, float value) {
  const auto* c = static_cast<Controller*>(ctx);
  if (!std::isfinite(value) || std::fabs(value) > c->core->settings().gain) __builtin_trap();
}

struct Input {
  const std::uint8_t* data;
  std::size_t size, at = 0;
  bool more() const { return at < size; }
  std::uint8_t byte() { return at < size ? data[at++] : 0; }
};

// The device the core's reports go to (a captureless seam function needs a place to find it).
usb::Device* g_device = nullptr;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Controller ctl;
  ctl.reset();
  hmp::fw::BoardSeam seam;
  seam.ctx = &ctl;
  seam.output = check_output;
  seam.send = [](void*, const protocol::Report& r) {
    protocol::Message m;
    if (protocol::decode(r, m) != protocol::ErrorCode::none || protocol::is_host_to_device(m.type)) __builtin_trap();
    return g_device->queue_report(r);
  };
  hmp::fw::Core wired(seam, 1000);
  ctl.core = &wired;
  usb::Device usb_dev(ctl.dcd(), wired, "FUZZ0001");
  g_device = &usb_dev;
  usb_dev.start();

  Input in{data, size};
  while (in.more()) {
    switch (in.byte() % 9) {
      case 0: {  // SETUP: always accepted, clears the endpoint-0 stall and what was armed there
        std::uint8_t pkt[8];
        for (auto& b : pkt) b = in.byte();
        ctl.ep[0][0].stalled = ctl.ep[0][1].stalled = false;
        ctl.ep[0][0].armed = ctl.ep[0][1].armed = false;
        usb_dev.on_setup(pkt);
        break;
      }
      case 1: {  // endpoint 0 IN packet taken by the host
        Endpoint& e = ctl.ep[0][1];
        if (!e.armed || e.stalled) break;
        e.armed = false;
        usb_dev.on_xfer_complete(0x80, e.len);
        break;
      }
      case 2:    // endpoint 0 OUT data
      case 3: {  // endpoint 1 OUT report (any length the host could send, up to what was armed)
        Endpoint& e = ctl.ep[in.at > 0 && data[in.at - 1] % 9 == 2 ? 0 : 1][0];
        if (!e.armed || e.stalled) break;
        const std::uint16_t n = static_cast<std::uint16_t>(in.byte() % (e.len + 1));
        for (std::uint16_t i = 0; i < n; ++i) e.buffer[i] = in.byte();
        e.armed = false;
        usb_dev.on_xfer_complete(&e == &ctl.ep[0][0] ? 0x00 : 0x01, n);
        break;
      }
      case 4: {  // endpoint 1 IN report read by the host
        Endpoint& e = ctl.ep[1][1];
        if (!e.armed || e.stalled) break;
        protocol::Report r;
        if (e.len != protocol::kReportSize) __builtin_trap();
        std::memcpy(r, e.buffer, sizeof r);
        protocol::Message m;
        if (protocol::decode(r, m) != protocol::ErrorCode::none) __builtin_trap();
        e.armed = false;
        usb_dev.on_xfer_complete(0x81, e.len);
        break;
      }
      case 5:
        ctl.reset();
        usb_dev.on_bus_reset();
        break;
      case 6: usb_dev.on_suspend(); break;
      case 7: usb_dev.on_resume(); break;
      default: {  // ticks, with the main loop's work after each
        const int n = 1 + in.byte() % 32;
        for (int i = 0; i < n; ++i) {
          wired.on_tick();
          while (wired.poll()) {
          }
          usb_dev.poll();
        }
        break;
      }
    }
    if (usb_dev.queued_reports() > usb::Device::kQueueReports) __builtin_trap();
  }
  g_device = nullptr;
  return 0;
}
