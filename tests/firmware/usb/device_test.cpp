// The USB device stack (firmware/usb) through its controller seam, driven by a scripted host that does
// what the Linux kernel does when a device is plugged in, and the error paths of USB 2.0 chapter 9 and
// HID 1.11. The expected bytes below are written from those specifications (and docs/protocol.md's USB
// identity), not taken from the stack's tables.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "boards/usb-sim/control_transfer.hpp"
#include "firmware/core.hpp"
#include "firmware/usb/device.hpp"
#include "shared/protocol/protocol.hpp"
#include "shared/synth/frequency.hpp"

namespace {

namespace p = hmp::protocol;
namespace usb = hmp::fw::usb;
namespace host = hmp::usb_host;
using Bytes = std::vector<std::uint8_t>;

// A device controller that records what the stack asks of it; the scripted host reads those records.
struct FakeController {
  bool connected = false;
  std::optional<std::uint8_t> address;
  std::map<std::uint8_t, std::uint16_t> open;  // ep → max packet
  std::map<std::uint8_t, bool> stalled;
  std::vector<std::uint8_t> toggle_resets;  // ep_clear_stall calls
  using Pending = host::Packet;             // buffer and room (OUT) or the bytes as handed over (IN)
  std::map<std::uint8_t, Pending> pending;  // armed OUT / queued IN packet per endpoint

  usb::Dcd dcd() {
    usb::Dcd d;
    d.ctx = this;
    d.connect = [](void* c, bool on) { self(c).connected = on; };
    d.set_address = [](void* c, std::uint8_t a) { self(c).address = a; };
    d.ep_open = [](void* c, std::uint8_t ep, usb::EpType t, std::uint16_t mps) {
      EXPECT_EQ(t, usb::EpType::interrupt);
      self(c).open[ep] = mps;
    };
    d.ep_close = [](void* c, std::uint8_t ep) {
      self(c).open.erase(ep);
      self(c).pending.erase(ep);
    };
    d.ep_stall = [](void* c, std::uint8_t ep) {
      self(c).stalled[ep] = true;
      if (ep != 0x00) self(c).pending.erase(ep);
    };
    d.ep_clear_stall = [](void* c, std::uint8_t ep) {
      self(c).stalled[ep] = false;
      self(c).pending.erase(ep);  // the endpoint starts over: what was armed or queued is cancelled
      self(c).toggle_resets.push_back(ep);
    };
    d.ep_xfer = [](void* c, std::uint8_t ep, std::uint8_t* buf, std::uint16_t len) {
      FakeController& f = self(c);
      if ((ep & 0x7F) != 0 && !f.open.count(ep)) return false;
      EXPECT_FALSE(f.pending.count(ep)) << "endpoint " << int(ep) << " armed twice";
      EXPECT_LE(len, (ep & 0x7F) == 0 ? 64 : f.open[ep]) << "more than one packet";
      Pending pk{buf, len, {}};
      if (ep & 0x80) pk.in_data.assign(buf, buf + len);
      f.pending[ep] = pk;
      return true;
    };
    return d;
  }
  static FakeController& self(void* c) { return *static_cast<FakeController*>(c); }
};

// Endpoint 0 of the FakeController as the shared control-transfer model (the one the usbredir rig runs
// too) reads it.
struct FakeEp0 final : host::Ep0 {
  FakeController& ctl;
  explicit FakeEp0(FakeController& c) : ctl(c) {}
  // The controller clears an endpoint-0 stall on every SETUP, as USB requires.
  void accept_setup() override {
    ctl.stalled[0x00] = false;
    ctl.pending.erase(0x80);
    ctl.pending.erase(0x00);
  }
  bool stalled() override { return ctl.stalled[0x00]; }
  host::Packet* packet(std::uint8_t ep) override {
    auto it = ctl.pending.find(ep);
    return it == ctl.pending.end() ? nullptr : &it->second;
  }
  void take(std::uint8_t ep) override { ctl.pending.erase(ep); }
};

struct Rig {
  FakeController ctl;
  FakeEp0 ep0{ctl};
  std::vector<float> outputs;
  hmp::fw::BoardSeam seam;
  std::optional<hmp::fw::Core> core;
  std::optional<usb::Device> dev;

  explicit Rig(const char* serial = "0123456789AB") {
    seam.ctx = this;
    seam.output = [](void* c, float v) { static_cast<Rig*>(c)->outputs.push_back(v); };
    seam.send = [](void* c, const p::Report& r) { return static_cast<Rig*>(c)->dev->queue_report(r); };
    core.emplace(seam);
    dev.emplace(ctl.dcd(), *core, serial);
    dev->start();
  }

  // A SETUP alone (the transfer's other stages are left to the test).
  void setup(std::uint8_t type, std::uint8_t req, std::uint16_t value, std::uint16_t index, std::uint16_t length) {
    host::send_setup(*dev, ep0, usb::Setup{type, req, value, index, length});
  }

  struct Result {
    bool stalled = false;
    Bytes data;
    std::vector<std::uint16_t> packets;  // sizes of the IN data packets (a ZLP shows as 0)
  };

  // A control read as a host controller does it: IN packets until a short one or wLength bytes, then the
  // status stage (a ZLP OUT).
  Result control_in(std::uint8_t type, std::uint8_t req, std::uint16_t value, std::uint16_t index,
                    std::uint16_t length) {
    const host::ControlResult c = host::control_transfer(*dev, ep0, usb::Setup{type, req, value, index, length});
    if (c.outcome == host::ControlOutcome::no_data_packet) ADD_FAILURE() << "no IN packet";
    EXPECT_NE(c.outcome, host::ControlOutcome::no_status_stage) << "status stage not armed";
    return Result{c.outcome == host::ControlOutcome::stalled, c.data, c.packets};
  }

  // A control write without data: the device answers the status stage with a ZLP IN, or stalls.
  bool control_out(std::uint8_t type, std::uint8_t req, std::uint16_t value, std::uint16_t index) {
    const host::ControlResult c = host::control_transfer(*dev, ep0, usb::Setup{type, req, value, index, 0});
    EXPECT_NE(c.outcome, host::ControlOutcome::no_status_stage) << "no status ZLP";
    return c.outcome == host::ControlOutcome::done;
  }

  // A control write with a data stage (SET_REPORT), in 64-byte packets each into the buffer the device
  // armed; false when the device stalls or leaves the host waiting.
  bool control_out_data(std::uint8_t type, std::uint8_t req, std::uint16_t value, std::uint16_t index,
                        const Bytes& data) {
    const usb::Setup s{type, req, value, index, static_cast<std::uint16_t>(data.size())};
    const host::ControlResult c = host::control_transfer(*dev, ep0, s, data.data());
    EXPECT_EQ(c.cut_packets, 0u) << "the device armed less room than a packet of the data stage";
    return c.outcome == host::ControlOutcome::done;
  }

  // The host writes one report on the interrupt OUT endpoint; false when the endpoint is NAKing.
  bool interrupt_out(const Bytes& report) {
    auto it = ctl.pending.find(0x01);
    if (it == ctl.pending.end()) return false;
    std::copy(report.begin(), report.end(), it->second.buffer);
    ctl.pending.erase(it);
    dev->on_xfer_complete(0x01, static_cast<std::uint16_t>(report.size()));
    return true;
  }

  // The host reads one report from the interrupt IN endpoint, if one is there.
  std::optional<Bytes> interrupt_in() {
    auto it = ctl.pending.find(0x81);
    if (it == ctl.pending.end()) return std::nullopt;
    Bytes d = it->second.in_data;
    ctl.pending.erase(it);
    dev->on_xfer_complete(0x81, static_cast<std::uint16_t>(d.size()));
    return d;
  }

  // The usual enumeration up to a configured device (the steps are checked in EnumerationAsLinuxDoesIt).
  void enumerate() {
    dev->on_bus_reset();
    control_in(0x80, 6, 0x0100, 0, 64);
    dev->on_bus_reset();
    control_out(0x00, 5, 7, 0);
    ASSERT_TRUE(control_out(0x00, 9, 1, 0));
  }

  // Ticks the core as a board's main loop would; the host reads every IN report the device offers
  // (kept in `read`).
  std::vector<Bytes> read;
  void tick(int n = 1) {
    for (int i = 0; i < n; ++i) {
      core->on_tick();
      while (core->poll()) {
      }
      dev->poll();
      while (auto d = interrupt_in()) read.push_back(*d);
    }
  }
};

Bytes report_of(p::Message m, std::uint16_t seq) {
  m.seq = seq;
  p::Report r;
  EXPECT_TRUE(p::encode(m, r));
  return Bytes(r, r + p::kReportSize);
}

std::string utf16_string(const Bytes& d) {
  std::string s;
  for (std::size_t i = 2; i + 1 < d.size(); i += 2) {
    EXPECT_EQ(d[i + 1], 0);
    s += static_cast<char>(d[i]);
  }
  return s;
}

// The vendor report descriptor docs/protocol.md describes: usage page 0xFF00, usage 1, one 64-byte input
// and one 64-byte output report of 8-bit fields, no report ID (HID 1.11 §6.2.2 item encodings).
const Bytes kExpectedReportDescriptor = {0x06, 0x00, 0xFF, 0x09, 0x01, 0xA1, 0x01, 0x15, 0x00, 0x26, 0xFF, 0x00, 0x75,
                                         0x08, 0x95, 0x40, 0x09, 0x01, 0x81, 0x02, 0x09, 0x01, 0x91, 0x02, 0xC0};

TEST(UsbDevice, EnumerationAsLinuxDoesIt) {
  Rig rig;
  EXPECT_TRUE(rig.ctl.connected);
  rig.dev->on_bus_reset();
  // 1. The first 8 bytes of the device descriptor at address 0 (bMaxPacketSize0 is byte 7).
  auto r = rig.control_in(0x80, 6, 0x0100, 0, 64);
  ASSERT_FALSE(r.stalled);
  ASSERT_GE(r.data.size(), 8u);
  EXPECT_EQ(Bytes(r.data.begin(), r.data.begin() + 8), (Bytes{18, 1, 0x00, 0x02, 0, 0, 0, 64}));
  // 2. Reset, SET_ADDRESS: the controller is told before the status stage completes.
  rig.dev->on_bus_reset();
  rig.setup(0x00, 5, 23, 0, 0);
  EXPECT_EQ(rig.ctl.address, 23);
  ASSERT_TRUE(rig.ctl.pending.count(0x80));
  EXPECT_EQ(rig.ctl.pending[0x80].len, 0);
  rig.ctl.pending.erase(0x80);
  rig.dev->on_xfer_complete(0x80, 0);
  EXPECT_EQ(rig.dev->address(), 23);
  // 3. The whole device descriptor.
  r = rig.control_in(0x80, 6, 0x0100, 0, 18);
  // bcdDevice is the project's version in binary-coded decimal, JJ.M.N (0.1.0: 0x0010).
  const auto bcd_low = static_cast<std::uint8_t>(HMP_VERSION_MINOR << 4 | HMP_VERSION_PATCH);
  const auto bcd_high = static_cast<std::uint8_t>((HMP_VERSION_MAJOR / 10) << 4 | HMP_VERSION_MAJOR % 10);
  EXPECT_EQ(r.data, (Bytes{18, 1, 0x00, 0x02, 0, 0, 0, 64, 0x09, 0x12, 0x01, 0x00, bcd_low, bcd_high, 1, 2, 3, 1}));
  // 4. Configuration: 9 bytes, then wTotalLength.
  r = rig.control_in(0x80, 6, 0x0200, 0, 9);
  ASSERT_EQ(r.data.size(), 9u);
  const std::uint16_t total = static_cast<std::uint16_t>(r.data[2] | r.data[3] << 8);
  EXPECT_EQ(total, 9 + 9 + 9 + 7 + 7);
  r = rig.control_in(0x80, 6, 0x0200, 0, total);
  const Bytes expected_config = {9,  2,    41,   0,    1,  1, 0,    0x80,
                                 50,  // one configuration, 100 mA
                                 9,  4,    0,    0,    2,  3, 0,    0,
                                 0,  // interface 0: HID, 2 endpoints
                                 9,  0x21, 0x11, 0x01, 0,  1, 0x22, std::uint8_t(kExpectedReportDescriptor.size()),
                                 0,                                // HID 1.11
                                 7,  5,    0x81, 3,    64, 0, 1,   // interrupt IN, 64 B, 1 ms
                                 7,  5,    0x01, 3,    64, 0, 1};  // interrupt OUT, 64 B, 1 ms
  EXPECT_EQ(r.data, expected_config);
  // 5. Strings: the language list, then each string in US English.
  r = rig.control_in(0x80, 6, 0x0300, 0, 255);
  EXPECT_EQ(r.data, (Bytes{4, 3, 0x09, 0x04}));
  for (int i : {1, 2, 3}) {
    r = rig.control_in(0x80, 6, static_cast<std::uint16_t>(0x0300 + i), 0x0409, 255);
    ASSERT_FALSE(r.stalled) << "string " << int(i);
    ASSERT_GE(r.data.size(), 2u);
    EXPECT_EQ(r.data[0], r.data.size());
    EXPECT_EQ(r.data[1], 3);
    EXPECT_FALSE(utf16_string(r.data).empty());
  }
  r = rig.control_in(0x80, 6, 0x0303, 0x0409, 255);
  EXPECT_EQ(utf16_string(r.data), "0123456789AB") << "the serial number the board handed in";
  // 6. SET_CONFIGURATION 1: both interrupt endpoints open, the OUT one armed.
  EXPECT_TRUE(rig.control_out(0x00, 9, 1, 0));
  EXPECT_EQ(rig.dev->configuration(), 1);
  EXPECT_EQ(rig.ctl.open, (std::map<std::uint8_t, std::uint16_t>{{0x01, 64}, {0x81, 64}}));
  EXPECT_TRUE(rig.ctl.pending.count(0x01));
  r = rig.control_in(0x80, 8, 0, 0, 1);
  EXPECT_EQ(r.data, Bytes{1});
  // 7. usbhid: SET_IDLE 0, then the report descriptor from the interface.
  EXPECT_TRUE(rig.control_out(0x21, 0x0A, 0, 0));
  r = rig.control_in(0x81, 6, 0x2200, 0, 255);
  EXPECT_EQ(r.data, kExpectedReportDescriptor);
  r = rig.control_in(0x81, 6, 0x2100, 0, 9);
  EXPECT_EQ(r.data, Bytes(expected_config.begin() + 18, expected_config.begin() + 27));
  EXPECT_EQ(rig.dev->stats().stalls, 0u);
}

TEST(UsbDevice, RepliesFollowWLengthAndEndWithAZlpWhenTheyFillTheirLastPacket) {
  // A 31-character serial number makes a 64-byte string descriptor: exactly one full packet.
  Rig rig("ABCDEFGHIJKLMNOPQRSTUVWXYZ01234");
  rig.enumerate();
  auto r = rig.control_in(0x80, 6, 0x0303, 0x0409, 255);
  EXPECT_EQ(r.packets, (std::vector<std::uint16_t>{64, 0})) << "shorter than wLength and a multiple of 64: ZLP";
  r = rig.control_in(0x80, 6, 0x0303, 0x0409, 64);
  EXPECT_EQ(r.packets, (std::vector<std::uint16_t>{64})) << "exactly wLength: no ZLP";
  r = rig.control_in(0x80, 6, 0x0100, 0, 8);
  EXPECT_EQ(r.data.size(), 8u) << "wLength shorter than the descriptor: truncated";
  r = rig.control_in(0x80, 6, 0x0100, 0, 0xFFFF);
  EXPECT_EQ(r.packets, (std::vector<std::uint16_t>{18})) << "wLength longer: the descriptor, a short packet";
  // The product string is longer than one packet: two packets, the second short.
  r = rig.control_in(0x80, 6, 0x0302, 0x0409, 255);
  ASSERT_EQ(r.packets.size(), 2u);
  EXPECT_EQ(r.packets[0], 64);
  EXPECT_LT(r.packets[1], 64);
  EXPECT_EQ(r.data[0], r.data.size());
}

TEST(UsbDevice, ANewSetupAbortsAnUnfinishedTransfer) {
  Rig rig;
  rig.enumerate();
  rig.setup(0x80, 6, 0x0302, 0x0409, 255);  // two packets; the host takes none
  ASSERT_TRUE(rig.ctl.pending.count(0x80));
  auto r = rig.control_in(0x80, 6, 0x0100, 0, 18);
  EXPECT_EQ(r.data.size(), 18u);
  EXPECT_EQ(r.data[1], 1);
  EXPECT_EQ(rig.dev->stats().aborted, 1u);
  // Up to three SETUPs back to back (a host retrying): only the last one is answered.
  rig.setup(0x80, 6, 0x0200, 0, 9);
  rig.setup(0x80, 6, 0x0200, 0, 9);
  r = rig.control_in(0x80, 8, 0, 0, 1);
  EXPECT_EQ(r.data, Bytes{1});
}

TEST(UsbDevice, UnsupportedRequestsStallUntilTheNextSetup) {
  Rig rig;
  rig.enumerate();
  const auto stalls_of = [&](std::uint8_t type, std::uint8_t req, std::uint16_t value, std::uint16_t index,
                             std::uint16_t length = 0) {
    const auto before = rig.dev->stats().stalls;
    const bool in = type & 0x80;
    const bool stalled =
        in ? rig.control_in(type, req, value, index, length).stalled : !rig.control_out(type, req, value, index);
    EXPECT_EQ(rig.dev->stats().stalls, before + (stalled ? 1 : 0));
    return stalled;
  };
  EXPECT_TRUE(stalls_of(0x80, 6, 0x0600, 0, 10)) << "DEVICE_QUALIFIER: full speed only";
  EXPECT_TRUE(stalls_of(0x80, 6, 0x0700, 0, 9)) << "OTHER_SPEED_CONFIGURATION";
  EXPECT_TRUE(stalls_of(0x80, 6, 0x0201, 0, 9)) << "a second configuration";
  EXPECT_TRUE(stalls_of(0x80, 6, 0x0304, 0x0409, 255)) << "string 4";
  EXPECT_TRUE(stalls_of(0xC0, 0x42, 0, 0, 4)) << "vendor request";
  EXPECT_TRUE(stalls_of(0x00, 9, 2, 0)) << "SET_CONFIGURATION 2";
  EXPECT_TRUE(stalls_of(0x00, 3, 1, 0)) << "SET_FEATURE remote wake-up: not supported";
  EXPECT_TRUE(stalls_of(0x02, 3, 0, 0x82)) << "halt on an endpoint that does not exist";
  EXPECT_TRUE(stalls_of(0x01, 11, 1, 0)) << "SET_INTERFACE alternate 1";
  EXPECT_TRUE(stalls_of(0x81, 10, 0, 1, 1)) << "GET_INTERFACE of interface 1";
  EXPECT_TRUE(stalls_of(0xA1, 0x03, 0, 0, 1)) << "GET_PROTOCOL: no boot interface";
  // After every stall the next SETUP is served.
  auto r = rig.control_in(0x80, 6, 0x0100, 0, 18);
  EXPECT_FALSE(r.stalled);
  EXPECT_EQ(r.data.size(), 18u);
}

TEST(UsbDevice, StatusConfigurationAndInterfaceRequests) {
  Rig rig;
  rig.dev->on_bus_reset();
  EXPECT_TRUE(rig.control_in(0x80, 8, 0, 0, 1).data == Bytes{0}) << "GET_CONFIGURATION before: 0";
  rig.enumerate();
  EXPECT_EQ(rig.control_in(0x80, 0, 0, 0, 2).data, (Bytes{0, 0})) << "bus powered, no remote wake-up";
  EXPECT_EQ(rig.control_in(0x81, 0, 0, 0, 2).data, (Bytes{0, 0}));
  EXPECT_EQ(rig.control_in(0x82, 0, 0, 0x81, 2).data, (Bytes{0, 0}));
  EXPECT_EQ(rig.control_in(0x81, 10, 0, 0, 1).data, Bytes{0}) << "GET_INTERFACE: alternate 0";
  EXPECT_TRUE(rig.control_out(0x01, 11, 0, 0)) << "SET_INTERFACE alternate 0";
  // SET_CONFIGURATION 0 closes the endpoints; 1 opens them again.
  EXPECT_TRUE(rig.control_out(0x00, 9, 0, 0));
  EXPECT_TRUE(rig.ctl.open.empty());
  EXPECT_TRUE(rig.control_in(0x82, 0, 0, 0x81, 2).stalled) << "no data endpoints while unconfigured";
  EXPECT_TRUE(rig.control_out(0x00, 9, 1, 0));
  EXPECT_EQ(rig.ctl.open.size(), 2u);
}

TEST(UsbDevice, EndpointHaltAndItsClearingResetTheToggle) {
  Rig rig;
  rig.enumerate();
  EXPECT_TRUE(rig.control_out(0x02, 3, 0, 0x81));  // SET_FEATURE(ENDPOINT_HALT) on IN
  EXPECT_TRUE(rig.ctl.stalled[0x81]);
  EXPECT_EQ(rig.control_in(0x82, 0, 0, 0x81, 2).data, (Bytes{1, 0}));
  EXPECT_TRUE(rig.control_out(0x02, 1, 0, 0x81));  // CLEAR_FEATURE
  EXPECT_FALSE(rig.ctl.stalled[0x81]);
  EXPECT_EQ(rig.control_in(0x82, 0, 0, 0x81, 2).data, (Bytes{0, 0}));
  // Clearing a halt that was not set still resets the data toggle (USB 2.0 §9.4.5).
  rig.ctl.toggle_resets.clear();
  EXPECT_TRUE(rig.control_out(0x02, 1, 0, 0x01));
  EXPECT_EQ(rig.ctl.toggle_resets, std::vector<std::uint8_t>{0x01});
  EXPECT_TRUE(rig.ctl.pending.count(0x01)) << "the OUT endpoint is armed again";
  // A halted OUT endpoint takes nothing.
  EXPECT_TRUE(rig.control_out(0x02, 3, 0, 0x01));
  rig.tick();
  EXPECT_FALSE(rig.ctl.pending.count(0x01));
}

TEST(UsbDevice, HelloOverTheInterruptPipeIsAnsweredOnTheInPipe) {
  Rig rig;
  rig.enumerate();
  ASSERT_TRUE(rig.interrupt_out(report_of(p::make(p::Type::hello, 0), 1)));
  rig.tick(5);
  std::vector<p::Message> got;
  for (const Bytes& d : rig.read) {
    p::Report r;
    std::copy(d.begin(), d.end(), r);
    p::Message m;
    ASSERT_EQ(p::decode(r, m), p::ErrorCode::none);
    got.push_back(m);
  }
  ASSERT_GE(got.size(), 2u);
  EXPECT_EQ(got[0].type, p::Type::hello_reply);
  EXPECT_EQ(got[0].hello_reply.protocol_version, p::kProtocolVersion);
  EXPECT_EQ(got[1].type, p::Type::status);
}

TEST(UsbDevice, ControlPipeReportsAreHidapisFallback) {
  Rig rig;
  rig.enumerate();
  rig.ctl.pending.erase(0x01);  // as if the interrupt OUT pipe were unused
  EXPECT_TRUE(rig.control_out_data(0x21, 0x09, 0x0200, 0, report_of(p::make(p::Type::hello, 0), 1)));  // SET_REPORT
  EXPECT_EQ(rig.dev->stats().out_reports, 1u);
  rig.core->on_tick();
  while (rig.core->poll()) {
  }
  rig.ctl.pending.erase(0x81);  // the IN pipe's copy is not read: GET_REPORT takes the queue's head
  // The head went to the IN endpoint already; once that packet is "lost" the report stays queued, so
  // GET_REPORT is refused while an IN transfer holds the head.
  auto r = rig.control_in(0xA1, 0x01, 0x0100, 0, 64);
  EXPECT_TRUE(r.stalled);
  EXPECT_TRUE(rig.control_in(0xA1, 0x01, 0x0300, 0, 64).stalled) << "feature reports: none";
  EXPECT_FALSE(rig.control_out_data(0x21, 0x09, 0x0200, 0, Bytes(10, 0))) << "SET_REPORT of 10 bytes";
}

TEST(UsbDevice, GetReportReadsTheQueueWhenTheInPipeIsIdle) {
  Rig rig;
  rig.dev->on_bus_reset();
  rig.control_in(0x80, 6, 0x0100, 0, 64);
  rig.control_out(0x00, 5, 9, 0);
  // Not configured: reports queue but nothing starts on the IN endpoint.
  p::Report status;
  p::encode(p::make(p::Type::sync_reply, 5), status);
  ASSERT_TRUE(rig.dev->queue_report(status));
  auto r = rig.control_in(0xA1, 0x01, 0x0100, 0, 64);
  ASSERT_FALSE(r.stalled);
  EXPECT_EQ(r.data, Bytes(status, status + 64));
  EXPECT_EQ(rig.dev->queued_reports(), 0u);
  EXPECT_TRUE(rig.control_in(0xA1, 0x01, 0x0100, 0, 64).stalled) << "nothing left to read";
}

// The host writes far faster than the core drains its inbox (4 reports a tick, 16 in the inbox): the OUT
// endpoint NAKs while the inbox is full, and every report reaches the core in order.
TEST(UsbDevice, OutReportsFasterThanTheCoreDrainsAreHeldNotLost) {
  Rig rig;
  rig.enumerate();
  const int total = 500;
  int sent = 0, naks = 0;
  std::vector<std::uint16_t> acked;
  while (sent < total) {
    while (sent < total &&
           rig.interrupt_out(report_of(p::make(p::Type::sync, 0), static_cast<std::uint16_t>(sent + 1))))
      ++sent;
    if (sent < total) ++naks;
    rig.tick();
  }
  rig.tick(200);
  EXPECT_GT(naks, 0) << "the test never filled the inbox";
  EXPECT_GT(rig.dev->stats().out_held, 0u);
  EXPECT_EQ(rig.dev->stats().out_reports, static_cast<std::uint32_t>(total));
  EXPECT_EQ(rig.dev->stats().out_lost, 0u);
  EXPECT_EQ(rig.core->stats().packets, static_cast<std::uint32_t>(total));
  EXPECT_EQ(rig.core->stats().inbox_full, 0u);
  EXPECT_EQ(rig.core->status().last_seq, total);
}

// Both OUT paths at once, the inbox one slot short of full with the OUT endpoint armed: a SET_REPORT is
// refused (STALL: the host may retry) rather than taking the slot the armed endpoint may fill, so the
// report that comes on the endpoint is taken, and none the host was told arrived is lost.
TEST(UsbDevice, SetReportAndTheOutEndpointNeverCountOnOneLastSlot) {
  Rig rig;
  rig.enumerate();
  ASSERT_TRUE(rig.ctl.pending.count(0x01)) << "the OUT endpoint is armed";
  std::uint16_t seq = 1;
  int taken = 0;
  while (rig.control_out_data(0x21, 0x09, 0x0200, 0, report_of(p::make(p::Type::sync, 0), seq))) {
    ++seq;
    ++taken;
    ASSERT_LT(taken, 100) << "SET_REPORT never refused";
  }
  EXPECT_EQ(taken, static_cast<int>(hmp::fw::Core::kInboxCapacity) - 1) << "one slot kept for the armed endpoint";
  EXPECT_TRUE(rig.interrupt_out(report_of(p::make(p::Type::sync, 0), seq)));
  EXPECT_EQ(rig.dev->stats().out_lost, 0u);
  EXPECT_EQ(rig.dev->stats().out_reports, static_cast<std::uint32_t>(taken + 1));
  EXPECT_EQ(rig.core->faults() & p::fault_queue_overflow, 0u);
  rig.tick(10);
  EXPECT_EQ(rig.core->status().last_seq, seq) << "every report taken reached the core";
}

// Device reports wait for the host: none is dropped while the host keeps reading, however late.
TEST(UsbDevice, InReportsWaitForTheHostInOrder) {
  Rig rig;
  rig.enumerate();
  for (std::uint16_t i = 0; i < usb::Device::kQueueReports; ++i) {
    p::Report r;
    p::encode(p::make(p::Type::sync_reply, i), r);
    ASSERT_TRUE(rig.dev->queue_report(r));
  }
  p::Report extra;
  p::encode(p::make(p::Type::sync_reply, 99), extra);
  EXPECT_FALSE(rig.dev->queue_report(extra)) << "a full queue refuses (the core counts it)";
  for (std::uint16_t i = 0; i < usb::Device::kQueueReports; ++i) {
    auto d = rig.interrupt_in();
    ASSERT_TRUE(d);
    EXPECT_EQ((*d)[1] | (*d)[2] << 8, i);
  }
  EXPECT_FALSE(rig.interrupt_in());
}

// Suspend while a note sounds: the outputs fade to zero within 20 ms (like the host watchdog, at once).
TEST(UsbDevice, SuspendMidNoteFadesTheOutputWithin20ms) {
  Rig rig;
  rig.enumerate();
  std::uint16_t seq = 0;
  auto write = [&](p::Message m) {
    ASSERT_TRUE(rig.interrupt_out(report_of(m, ++seq)));
    rig.tick();
  };
  write(p::make(p::Type::hello, 0));
  p::Message settings = p::make(p::Type::settings, 0);
  settings.settings.ramp_in_ms = 0;
  write(settings);
  p::Message play = p::make(p::Type::transport, 0);
  play.transport.op = p::TransportOp::play;
  write(play);
  p::Message note = p::make(p::Type::long_note, 0);
  note.long_note.start_tick = rig.core->tick() + 5;
  note.long_note.duration_ticks = 5000;
  note.long_note.freq_q20 = hmp::synth::freq_to_q20(100.0);
  note.long_note.amp_q16 = 60000;
  note.long_note.preset = static_cast<std::uint8_t>(hmp::envelope::Preset::square);
  write(note);
  rig.tick(100);
  float peak = 0;
  for (std::size_t i = rig.outputs.size() - 20; i < rig.outputs.size(); ++i)
    peak = std::max(peak, std::abs(rig.outputs[i]));
  ASSERT_GT(peak, 0.5f) << "the note sounds before the suspend";
  rig.dev->on_suspend();
  const std::size_t at = rig.outputs.size();
  rig.tick(40);
  for (std::size_t i = at + 20; i < rig.outputs.size(); ++i) EXPECT_EQ(rig.outputs[i], 0.0f) << "tick " << i - at;
  EXPECT_EQ(rig.core->state(), p::State::paused);
  EXPECT_EQ(rig.core->faults(), 0u) << "a suspend is not a fault";
  EXPECT_FALSE(rig.interrupt_in()) << "nothing is sent while suspended";
  rig.dev->on_resume();
  EXPECT_TRUE(rig.interrupt_in()) << "the waiting Status goes out after resume";
}

TEST(UsbDevice, BusResetForgetsAddressConfigurationAndStaleReports) {
  Rig rig;
  rig.enumerate();
  p::Report r;
  p::encode(p::make(p::Type::sync_reply, 1), r);
  rig.dev->queue_report(r);
  rig.dev->on_bus_reset();
  EXPECT_EQ(rig.dev->address(), 0);
  EXPECT_EQ(rig.dev->configuration(), 0);
  EXPECT_EQ(rig.dev->queued_reports(), 0u);
  EXPECT_TRUE(rig.ctl.open.empty());
  EXPECT_TRUE(rig.control_out(0x00, 9, 1, 0) == false) << "SET_CONFIGURATION before an address: refused";
}

}  // namespace
