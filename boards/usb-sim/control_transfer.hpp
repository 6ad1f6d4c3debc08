#pragma once
// The host controller's half of a control transfer on endpoint 0, written once for the two native
// controllers behind the USB stack's seam (firmware/usb/dcd.hpp): the usbredir rig (usb_sim.cpp), which
// turns QEMU's control packets into these stages, and the scripted host of the stack's unit tests
// (tests/firmware/usb/device_test.cpp). Native host code only (vectors): the firmware never includes it.
//
// A transfer (USB 2.0 §8.5.3):
//  - SETUP: always accepted (§8.5.3.4): it ends an endpoint-0 stall and drops whatever the stack had armed
//    or queued there (the controller does that: Ep0::accept_setup), then the stack sees the 8 bytes.
//  - Data stage IN (bmRequestType bit 7): the host takes the packets the stack queues, one at a time, until
//    a short packet (a ZLP included) or wLength bytes; then the status stage is the host's ZLP OUT, into
//    the buffer the stack armed for it.
//  - Data stage OUT: the host writes wLength bytes in max-packet pieces, each into the buffer the stack
//    armed (cut to its room); then the status stage is the stack's ZLP IN.
//  - A stall on endpoint 0, looked for before each packet of the data stage and before the status stage
//    of a write, ends the transfer as stalled. A packet the host comes for that the stack never armed or
//    queued (the host would see NAK for ever) ends it too, reported as such (the rig answers an I/O error,
//    the tests fail).
// The controller keeps endpoint 0's state the way it keeps every endpoint's (the rig and the tests keep
// theirs differently); the model reads and takes packets through Ep0.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "firmware/usb/dcd.hpp"
#include "firmware/usb/device.hpp"

namespace hmp::usb_host {

// One packet the stack handed to the controller (ep_xfer): the buffer it armed and its room (OUT), or the
// bytes it queued (IN, copied at ep_xfer: the stack's buffer may be reused once the packet completes).
struct Packet {
  std::uint8_t* buffer = nullptr;
  std::uint16_t len = 0;
  std::vector<std::uint8_t> in_data;
};

// What the model needs of the controller's endpoint 0.
class Ep0 {
 public:
  // A SETUP is coming: end the stall and forget the packets armed or queued on either direction.
  virtual void accept_setup() = 0;
  // The stack stalled endpoint 0 (ep_stall(0x00): both directions, until the next SETUP).
  virtual bool stalled() = 0;
  // The packet armed (0x00) or queued (0x80) on endpoint 0, or nullptr: none (the host would see NAK).
  virtual Packet* packet(std::uint8_t ep) = 0;
  // The host has moved that packet: the controller forgets it (before the stack hears of it, since the
  // stack may arm the next one from its completion).
  virtual void take(std::uint8_t ep) = 0;

  virtual ~Ep0() = default;
};

enum class ControlOutcome : std::uint8_t {
  done,             // every stage completed
  stalled,          // the stack refused the request (a STALL)
  no_data_packet,   // data stage: nothing queued (IN) or armed (OUT) when the host came for it
  no_status_stage,  // status stage: no OUT buffer armed (after IN) or no ZLP queued (after OUT)
};

struct ControlResult {
  ControlOutcome outcome = ControlOutcome::done;
  std::vector<std::uint8_t> data;      // IN: the data stage's bytes
  std::vector<std::uint16_t> packets;  // IN: the size of each data packet (a ZLP shows as 0)
  std::uint32_t cut_packets = 0;       // OUT: data packets larger than the room the stack armed (cut to it)
};

// The SETUP stage alone (tests also use it to start a transfer they then leave unfinished).
inline void send_setup(fw::usb::Device& dev, Ep0& ep0, const fw::usb::Setup& s) {
  ep0.accept_setup();
  const std::uint8_t pkt[8] = {s.request_type,
                               s.request,
                               static_cast<std::uint8_t>(s.value),
                               static_cast<std::uint8_t>(s.value >> 8),
                               static_cast<std::uint8_t>(s.index),
                               static_cast<std::uint8_t>(s.index >> 8),
                               static_cast<std::uint8_t>(s.length),
                               static_cast<std::uint8_t>(s.length >> 8)};
  dev.on_setup(pkt);
}

// A whole control transfer: its direction is bmRequestType's bit 7; an OUT transfer writes s.length bytes
// of `out_data` (which may be null when s.length is 0).
inline ControlResult control_transfer(fw::usb::Device& dev, Ep0& ep0, const fw::usb::Setup& s,
                                      const std::uint8_t* out_data = nullptr) {
  using fw::usb::kDirIn;
  using fw::usb::kEp0Size;
  ControlResult r;
  send_setup(dev, ep0, s);
  if (s.request_type & kDirIn) {
    // Ends: a packet is either short (which ends the stage) or at least a whole one, and wLength bytes
    // end it too.
    for (;;) {
      if (ep0.stalled()) {
        r.outcome = ControlOutcome::stalled;
        return r;
      }
      const Packet* in = ep0.packet(kDirIn);
      if (in == nullptr) {
        r.outcome = ControlOutcome::no_data_packet;
        return r;
      }
      const std::vector<std::uint8_t> d = in->in_data;
      ep0.take(kDirIn);
      r.packets.push_back(static_cast<std::uint16_t>(d.size()));
      r.data.insert(r.data.end(), d.begin(), d.end());
      dev.on_xfer_complete(kDirIn, static_cast<std::uint16_t>(d.size()));
      if (d.size() < kEp0Size || r.data.size() >= s.length) break;
    }
    if (ep0.packet(0x00) == nullptr) {
      r.outcome = ControlOutcome::no_status_stage;
      return r;
    }
    ep0.take(0x00);
    dev.on_xfer_complete(0x00, 0);
    return r;
  }
  for (std::size_t done = 0; done < s.length;) {
    if (ep0.stalled()) {
      r.outcome = ControlOutcome::stalled;
      return r;
    }
    Packet* out = ep0.packet(0x00);
    if (out == nullptr) {
      r.outcome = ControlOutcome::no_data_packet;
      return r;
    }
    std::size_t n = s.length - done < kEp0Size ? s.length - done : kEp0Size;
    if (n > out->len) {
      ++r.cut_packets;
      n = out->len;
    }
    std::copy(out_data + done, out_data + done + n, out->buffer);
    ep0.take(0x00);
    done += n;
    dev.on_xfer_complete(0x00, static_cast<std::uint16_t>(n));
  }
  if (ep0.stalled()) {
    r.outcome = ControlOutcome::stalled;
    return r;
  }
  const Packet* zlp = ep0.packet(kDirIn);
  if (zlp == nullptr || zlp->len != 0) {
    r.outcome = ControlOutcome::no_status_stage;
    return r;
  }
  ep0.take(kDirIn);
  dev.on_xfer_complete(kDirIn, 0);
  return r;
}

}  // namespace hmp::usb_host
