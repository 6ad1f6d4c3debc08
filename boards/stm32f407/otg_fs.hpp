#pragma once
// The USB OTG FS device controller driver behind firmware/usb/dcd.hpp (RM0090 §34, device mode, slave
// mode: the core copies every packet through the FIFOs, no DMA). A template over the register access
// (`Io`: read(offset), write(offset, value), delay_ms(n); FIFO words through the FIFO offsets), so that
// the same code runs on the chip (otg_fs.cpp's MMIO) and against a model of the controller in the unit
// tests (tests/boards/stm32f407/otg_fs_test.cpp).
//
// Pitfalls handled (each has a test):
//  - no VBUS sensing: boards that do not wire PA9 still enumerate (GCCFG.NOVBUSSENS);
//  - SET_ADDRESS: DCFG.DAD is written when the request arrives; the core itself answers on the old
//    address until the status stage is over;
//  - an RX FIFO entry with a zero byte count (a ZLP) has no data words: nothing is popped for it;
//  - every RX FIFO entry's data is popped, also of an entry that is dropped (unknown status, endpoint out
//    of range, SETUP not 8 bytes): the FIFO never gets out of step, no endpoint gets another one's data;
//  - EP0 OUT is never enabled (CNAK) before the SETUP-done interrupt has been handled, also after a SETUP
//    entry that is not 8 bytes (no request reaches the stack, but the transfer before it has ended);
//  - every FIFO access is a whole 32-bit word (the last word of a packet padded or discarded);
//  - the RX FIFO and the TX FIFOs fit the 1.25 KB FIFO RAM, each at least what RM0090 asks (fifo_layout);
//  - up to three back-to-back SETUPs (STUPCNT = 3): the last one received is the one handled;
//  - a SETUP or a bus reset takes back an IN packet still queued (the core keeps it): the stack's next
//    packet is never refused for a transfer that has ended, nor an old completion taken for a new one;
//  - every wait on the core is bounded: a core that does not answer makes init() fail, never hang.
#include <cstdint>
#include <cstring>

#include "firmware/usb/dcd.hpp"
#include "firmware/usb/device.hpp"
#include "otg_fs_regs.hpp"

namespace hmp::board::stm32::otg {

// ---- pure parts (constexpr: checked at compile time for the layout in use, and by the tests) ----

// RM0090 §34.11 "FIFO RAM allocation", device mode: the RX FIFO needs room for the SETUP packets of
// each control endpoint (5 words each + 8), one largest packet with its status word, two words per OUT
// endpoint for their transfer-complete status, and one for global OUT NAK.
constexpr std::uint32_t min_rx_fifo_words(std::uint32_t control_eps, std::uint32_t largest_packet,
                                          std::uint32_t out_eps) {
  return (5 * control_eps + 8) + (largest_packet / 4 + 1) + 2 * out_eps + 1;
}

struct FifoLayout {
  std::uint32_t rx_words = 0;
  std::uint32_t tx_start[kEndpoints] = {}, tx_words[kEndpoints] = {};
  std::uint32_t total_words = 0;
};

// RX FIFO at word 0, then TX FIFO 0 … 3 back to back.
constexpr FifoLayout fifo_layout(std::uint32_t rx_words, const std::uint32_t (&tx_words)[kEndpoints]) {
  FifoLayout l;
  l.rx_words = rx_words;
  std::uint32_t at = rx_words;
  for (unsigned i = 0; i < kEndpoints; ++i) {
    l.tx_start[i] = at;
    l.tx_words[i] = tx_words[i];
    at += tx_words[i];
  }
  l.total_words = at;
  return l;
}

// Ours: a generous RX FIFO (several 64-byte packets back to back), two packets for EP0 IN and for the
// HID IN endpoint, the minimum for the two unused endpoints.
inline constexpr FifoLayout kFifoLayout = fifo_layout(128, {32, 32, kMinTxFifoWords, kMinTxFifoWords});
static_assert(kFifoLayout.total_words <= kFifoRamWords, "FIFOs exceed the 1.25 KB FIFO RAM");
static_assert(kFifoLayout.rx_words >= min_rx_fifo_words(1, 64, 2), "RX FIFO below RM0090's minimum");

// One GRXSTSP word (RM0090 §34.16.2, device mode): EPNUM 3:0, BCNT 14:4, DPID 16:15, PKTSTS 20:17.
struct RxStatus {
  std::uint8_t ep = 0;
  std::uint16_t bytes = 0;
  std::uint8_t pid = 0;
  std::uint8_t status = 0;
  static constexpr RxStatus decode(std::uint32_t word) {
    return RxStatus{static_cast<std::uint8_t>(word & 0xFu), static_cast<std::uint16_t>((word >> 4) & 0x7FFu),
                    static_cast<std::uint8_t>((word >> 15) & 0x3u), static_cast<std::uint8_t>((word >> 17) & 0xFu)};
  }
};

// ---- the driver ----

template <typename Io>
class OtgFs {
 public:
  static constexpr std::uint32_t kPolls = 200'000;  // bound of every wait on the core
  static constexpr std::uint32_t kTurnaround = 6;   // GUSBCFG.TRDT for an AHB clock ≥ 32 MHz

  explicit OtgFs(Io& io) : io_(io) {}
  OtgFs(const OtgFs&) = delete;
  OtgFs& operator=(const OtgFs&) = delete;

  void attach(fw::usb::Device& device) { device_ = &device; }

  // Core reset, forced device mode at full speed, no VBUS sensing, soft-disconnected until connect().
  // false: the core did not answer (no clock, or an emulator without the controller).
  bool init() {
    if (!wait(kGrstctl, kGrstctlAhbidl, kGrstctlAhbidl)) return false;
    io_.write(kGrstctl, kGrstctlCsrst);
    if (!wait(kGrstctl, kGrstctlCsrst, 0) || !wait(kGrstctl, kGrstctlAhbidl, kGrstctlAhbidl)) return false;
    io_.write(kGusbcfg, kGusbcfgPhysel | kGusbcfgFdmod | gusbcfg_trdt(kTurnaround));
    io_.delay_ms(25);  // forcing the mode takes effect after 25 ms (RM0090 §34.16.4)
    io_.write(kGccfg, kGccfgPwrdwn | kGccfgNovbussens);
    io_.write(kPcgcctl, 0);
    io_.write(kDcfg, kDcfgDspdFull);
    io_.write(kDctl, kDctlSdis);
    if (!setup_fifos()) return false;
    io_.write(kGintsts, 0xFFFFFFFFu);
    io_.write(kGintmsk, kIntUsbrst | kIntEnumdne | kIntRxflvl | kIntIepint | kIntOepint | kIntUsbsusp | kIntWkupint);
    io_.write(kGahbcfg, kGahbcfgGintmsk);
    return true;
  }

  // The OTG_FS interrupt.
  void on_interrupt() {
    const std::uint32_t pending = io_.read(kGintsts) & io_.read(kGintmsk);
    if (pending & kIntUsbrst) {
      io_.write(kGintsts, kIntUsbrst);
      bus_reset();
    }
    if (pending & kIntEnumdne) {
      io_.write(kGintsts, kIntEnumdne);
      io_.write(diepctl(0), io_.read(diepctl(0)) & ~0x3u);  // MPSIZ 00: 64-byte EP0 at full speed
      io_.write(kDctl, io_.read(kDctl) | kDctlCginak);
    }
    if (pending & kIntRxflvl) drain_rx_fifo();
    if (pending & kIntOepint) out_endpoints();
    if (pending & kIntIepint) in_endpoints();
    if (pending & kIntUsbsusp) {
      io_.write(kGintsts, kIntUsbsusp);
      if (device_) device_->on_suspend();
    }
    if (pending & kIntWkupint) {
      io_.write(kGintsts, kIntWkupint);
      if (device_) device_->on_resume();
    }
  }

  fw::usb::Dcd dcd() {
    fw::usb::Dcd d;
    d.ctx = this;
    d.connect = [](void* c, bool on) { self(c).connect(on); };
    d.set_address = [](void* c, std::uint8_t a) { self(c).set_address(a); };
    d.ep_open = [](void* c, std::uint8_t ep, fw::usb::EpType t, std::uint16_t mps) { self(c).ep_open(ep, t, mps); };
    d.ep_close = [](void* c, std::uint8_t ep) { self(c).ep_close(ep); };
    d.ep_stall = [](void* c, std::uint8_t ep) { self(c).ep_stall(ep); };
    d.ep_clear_stall = [](void* c, std::uint8_t ep) { self(c).ep_clear_stall(ep); };
    d.ep_xfer = [](void* c, std::uint8_t ep, std::uint8_t* b, std::uint16_t n) { return self(c).ep_xfer(ep, b, n); };
    return d;
  }

  // ---- Dcd commands ----
  void connect(bool on) {
    const std::uint32_t dctl = io_.read(kDctl);
    io_.write(kDctl, on ? dctl & ~kDctlSdis : dctl | kDctlSdis);
  }
  void set_address(std::uint8_t address) { io_.write(kDcfg, (io_.read(kDcfg) & ~kDcfgDadMask) | dcfg_dad(address)); }
  void ep_open(std::uint8_t ep_addr, fw::usb::EpType type, std::uint16_t max_packet) {
    const unsigned n = ep_addr & 0x7Fu;
    if (n == 0 || n >= kEndpoints) return;
    const std::uint32_t common = (max_packet & 0x7FFu) | kEpctlUsbaep | epctl_eptyp(static_cast<std::uint32_t>(type)) |
                                 kEpctlSd0pid | kEpctlSnak;
    if (ep_addr & fw::usb::kDirIn) {
      io_.write(diepctl(n), common | diepctl_txfnum(n));
      io_.write(kDaintmsk, io_.read(kDaintmsk) | 1u << n);
    } else {
      io_.write(doepctl(n), common);
      io_.write(kDaintmsk, io_.read(kDaintmsk) | 1u << (16 + n));
    }
  }
  void ep_close(std::uint8_t ep_addr) {
    const unsigned n = ep_addr & 0x7Fu;
    if (n == 0 || n >= kEndpoints) return;
    cancel(ep_addr);
    if (ep_addr & fw::usb::kDirIn) {
      io_.write(diepctl(n), io_.read(diepctl(n)) & ~kEpctlUsbaep);
      io_.write(kDaintmsk, io_.read(kDaintmsk) & ~(1u << n));
    } else {
      io_.write(doepctl(n), io_.read(doepctl(n)) & ~kEpctlUsbaep);
      io_.write(kDaintmsk, io_.read(kDaintmsk) & ~(1u << (16 + n)));
    }
  }
  void ep_stall(std::uint8_t ep_addr) {
    const unsigned n = ep_addr & 0x7Fu;
    if (n >= kEndpoints) return;
    if (n == 0) {  // both directions, until the next SETUP (the core clears it then)
      io_.write(diepctl(0), io_.read(diepctl(0)) | kEpctlStall);
      io_.write(doepctl(0), io_.read(doepctl(0)) | kEpctlStall);
      return;
    }
    cancel(ep_addr);
    const std::uint32_t reg = ep_addr & fw::usb::kDirIn ? diepctl(n) : doepctl(n);
    io_.write(reg, io_.read(reg) | kEpctlStall);
  }
  void ep_clear_stall(std::uint8_t ep_addr) {
    const unsigned n = ep_addr & 0x7Fu;
    if (n == 0 || n >= kEndpoints) return;
    cancel(ep_addr);
    const std::uint32_t reg = ep_addr & fw::usb::kDirIn ? diepctl(n) : doepctl(n);
    io_.write(reg, (io_.read(reg) & ~kEpctlStall) | kEpctlSd0pid);  // and the next packet is DATA0
  }
  bool ep_xfer(std::uint8_t ep_addr, std::uint8_t* buffer, std::uint16_t len) {
    const unsigned n = ep_addr & 0x7Fu;
    if (n >= kEndpoints || len > 64) return false;
    if (ep_addr & fw::usb::kDirIn) {
      if (io_.read(diepctl(n)) & kEpctlEpena) return false;  // the last packet is still waiting
      const std::uint32_t words = (len + 3u) / 4u;
      if ((io_.read(dtxfsts(n)) & 0xFFFFu) < words) return false;
      in_len_[n] = len;
      io_.write(dieptsiz(n), eptsiz(1, len));
      io_.write(diepctl(n), io_.read(diepctl(n)) | kEpctlEpena | kEpctlCnak);
      for (std::uint32_t w = 0; w < words; ++w) {
        std::uint32_t word = 0;
        const std::uint32_t take = len - w * 4u < 4u ? len - w * 4u : 4u;
        std::memcpy(&word, buffer + w * 4u, take);
        io_.write(fifo(n), word);
      }
      return true;
    }
    Out& o = out_[n];
    o.buffer = buffer;
    o.capacity = len;
    o.received = 0;
    const std::uint32_t size = n == 0 ? eptsiz(1, 64) | doeptsiz0_stupcnt(3) : eptsiz(1, len);
    io_.write(doeptsiz(n), size);
    io_.write(doepctl(n), io_.read(doepctl(n)) | kEpctlEpena | kEpctlCnak);
    return true;
  }

 private:
  struct Out {
    std::uint8_t* buffer = nullptr;
    std::uint16_t capacity = 0, received = 0;
  };

  static OtgFs& self(void* c) { return *static_cast<OtgFs*>(c); }

  bool wait(std::uint32_t reg, std::uint32_t mask, std::uint32_t value) {
    for (std::uint32_t i = 0; i < kPolls; ++i) {
      if ((io_.read(reg) & mask) == value) return true;
    }
    return false;
  }

  bool setup_fifos() {
    io_.write(kGrxfsiz, kFifoLayout.rx_words);
    io_.write(kDieptxf0, kFifoLayout.tx_words[0] << 16 | kFifoLayout.tx_start[0]);
    for (unsigned i = 1; i < kEndpoints; ++i)
      io_.write(dieptxf(i), kFifoLayout.tx_words[i] << 16 | kFifoLayout.tx_start[i]);
    io_.write(kGrstctl, kGrstctlTxfflsh | grstctl_txfnum(0x10));
    if (!wait(kGrstctl, kGrstctlTxfflsh, 0)) return false;
    io_.write(kGrstctl, kGrstctlRxfflsh);
    return wait(kGrstctl, kGrstctlRxfflsh, 0);
  }

  void bus_reset() {
    for (unsigned n = 0; n < kEndpoints; ++n) {
      cancel(static_cast<std::uint8_t>(n | fw::usb::kDirIn));  // the old session's IN packets are not sent
      io_.write(doepctl(n), io_.read(doepctl(n)) | kEpctlSnak);
      io_.write(diepint(n), 0xFFu);
      io_.write(doepint(n), 0xFFu);
      out_[n] = Out{};
    }
    setup_pending_ = false;  // its STUP flag was just cleared, its entries flushed below
    io_.write(kDaintmsk, 1u << 0 | 1u << 16);
    io_.write(kDoepmsk, kDoepintStup | kEpintXfrc);
    io_.write(kDiepmsk, kEpintXfrc);
    io_.write(kDcfg, io_.read(kDcfg) & ~kDcfgDadMask);
    static_cast<void>(setup_fifos());
    // Ready for up to three back-to-back SETUPs; EP0 OUT itself stays NAKing (no CNAK here).
    io_.write(doeptsiz(0), eptsiz(1, 24) | doeptsiz0_stupcnt(3));
    if (device_) device_->on_bus_reset();
  }

  // Pops every entry of the RX FIFO (RXFLVL stays set while there is one).
  void drain_rx_fifo() {
    for (std::uint32_t guard = 0; guard < 64 && (io_.read(kGintsts) & kIntRxflvl) != 0; ++guard) {
      const RxStatus s = RxStatus::decode(io_.read(kGrxstsp));
      if (s.status == kPktstsSetupData && s.ep == 0) {
        // Any SETUP entry opens the setup phase (EP0 OUT stays off until its STUP is handled); only one of
        // 8 bytes is a request the stack is given.
        setup_whole_ = s.bytes == sizeof setup_;
        read_fifo(setup_whole_ ? setup_ : nullptr, sizeof setup_, s.bytes);
        setup_pending_ = true;
      } else if (s.status == kPktstsOutData && s.ep < kEndpoints) {
        Out& o = out_[s.ep];
        const std::uint16_t room = o.buffer ? static_cast<std::uint16_t>(o.capacity - o.received) : 0;
        read_fifo(o.buffer ? o.buffer + o.received : nullptr, room, s.bytes);
        o.received = static_cast<std::uint16_t>(o.received + (s.bytes < room ? s.bytes : room));
      } else {
        // A status word only (OUT/SETUP done, global OUT NAK), or an entry no endpoint can take (an unknown
        // status, an endpoint the core does not have, a SETUP that is not 8 bytes): its data is popped and
        // dropped all the same, so that the next status word is read where it is.
        read_fifo(nullptr, 0, s.bytes);
      }
    }
  }

  // `bytes` from the RX FIFO in whole words; up to `room` of them kept, the rest (and padding) dropped.
  // A zero byte count pops nothing.
  void read_fifo(std::uint8_t* into, std::uint16_t room, std::uint16_t bytes) {
    for (std::uint32_t at = 0; at < bytes; at += 4) {
      const std::uint32_t word = io_.read(fifo(0));
      for (std::uint32_t k = 0; k < 4 && at + k < bytes; ++k) {
        if (into != nullptr && at + k < room) into[at + k] = static_cast<std::uint8_t>(word >> (8 * k));
      }
    }
  }

  void out_endpoints() {
    const std::uint32_t daint = io_.read(kDaint) & io_.read(kDaintmsk);
    for (unsigned n = 0; n < kEndpoints; ++n) {
      if ((daint & 1u << (16 + n)) == 0) continue;
      const std::uint32_t flags = io_.read(doepint(n));
      io_.write(doepint(n), flags);
      if (flags & kEpintXfrc) {
        const std::uint16_t got = out_[n].received;
        out_[n] = Out{};
        if (device_) device_->on_xfer_complete(static_cast<std::uint8_t>(n), got);
      }
      if (n == 0 && (flags & kDoepintStup) != 0 && setup_pending_) {
        // SETUP done: only now may EP0 OUT be enabled again (by the stack's data or status stage).
        setup_pending_ = false;
        io_.write(doeptsiz(0), eptsiz(1, 24) | doeptsiz0_stupcnt(3));
        // A SETUP ends the control transfer before it: an EP0 IN packet of that one still queued (the
        // core keeps it), or its completion not handled yet, would be taken for the new transfer's.
        cancel(fw::usb::kDirIn);
        io_.write(diepint(0), kEpintXfrc);
        if (device_ && setup_whole_) device_->on_setup(setup_);
      }
    }
  }

  void in_endpoints() {
    const std::uint32_t daint = io_.read(kDaint) & io_.read(kDaintmsk);
    for (unsigned n = 0; n < kEndpoints; ++n) {
      if ((daint & 1u << n) == 0) continue;
      const std::uint32_t flags = io_.read(diepint(n));
      io_.write(diepint(n), flags);
      // A SETUP read but not handled yet ends the transfer this EP0 IN packet belonged to: reported now,
      // the stack would go on with that transfer (even enable EP0 OUT) before the SETUP is done.
      if (n == 0 && setup_pending_) continue;
      if ((flags & kEpintXfrc) && device_) {
        device_->on_xfer_complete(static_cast<std::uint8_t>(n | fw::usb::kDirIn), in_len_[n]);
      }
    }
  }

  // Takes back what was armed or queued on an endpoint (EP0 IN too: a SETUP or a bus reset ends its packet).
  void cancel(std::uint8_t ep_addr) {
    const unsigned n = ep_addr & 0x7Fu;
    if (ep_addr & fw::usb::kDirIn) {
      if (io_.read(diepctl(n)) & kEpctlEpena) {
        io_.write(diepctl(n), io_.read(diepctl(n)) | kEpctlSnak | kEpctlEpdis);
        static_cast<void>(wait(diepint(n), kEpintEpdisd, kEpintEpdisd));
        io_.write(diepint(n), kEpintEpdisd);
        io_.write(kGrstctl, kGrstctlTxfflsh | grstctl_txfnum(n));
        static_cast<void>(wait(kGrstctl, kGrstctlTxfflsh, 0));
      }
    } else {
      out_[n] = Out{};  // a packet that still lands is dropped (no buffer); the stack arms again
      io_.write(doepctl(n), io_.read(doepctl(n)) | kEpctlSnak);
    }
  }

  Io& io_;
  fw::usb::Device* device_ = nullptr;
  std::uint8_t setup_[8] = {};
  bool setup_pending_ = false;  // a SETUP entry popped, its STUP not handled yet
  bool setup_whole_ = false;    // that SETUP had 8 bytes (in setup_)
  Out out_[kEndpoints];
  std::uint16_t in_len_[kEndpoints] = {};
};

}  // namespace hmp::board::stm32::otg
