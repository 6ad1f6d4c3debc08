// The STM32F407's USB OTG FS device driver (boards/stm32f407/otg_fs.hpp) on a PC, against a model of the
// controller written from RM0090 §34 (device mode, slave mode): registers that keep what is written,
// write-1-to-clear interrupt flags, an RX FIFO that presents a status word (GRXSTSP) and then that
// entry's data words, TX FIFOs that collect the words written, SETUP packets always accepted (STUPCNT),
// EP0's STALL cleared by the next SETUP, a packet taken only from an enabled endpoint. The driver runs
// with the real USB stack (firmware/usb) and core above it; expected bytes come from USB 2.0 ch. 9 and
// docs/usb.md's identity (1209:0001), not from the code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "boards/stm32f407/otg_fs.hpp"
#include "firmware/core.hpp"
#include "firmware/usb/device.hpp"

namespace {

namespace otg = hmp::board::stm32::otg;
namespace usb = hmp::fw::usb;
using Bytes = std::vector<std::uint8_t>;

struct FakeOtg {
  struct Entry {
    std::uint32_t status;
    std::vector<std::uint32_t> words;
  };
  std::map<std::uint32_t, std::uint32_t> regs;
  std::deque<Entry> rx;                  // entries not yet popped
  std::deque<std::uint32_t> rx_data;     // data words of the entry popped last
  std::map<unsigned, std::deque<std::uint32_t>> tx;
  bool core_answers = true;
  int empty_pops = 0;                    // FIFO reads with no data word to give (a driver bug)
  std::uint64_t reads = 0;
  std::vector<std::string> events;

  static std::uint32_t status(unsigned ep, unsigned bytes, unsigned pktsts) { return ep | bytes << 4 | pktsts << 17; }

  std::uint32_t endpoint_flags() {
    std::uint32_t daint = 0;
    for (unsigned n = 0; n < otg::kEndpoints; ++n) {
      if (regs[otg::diepint(n)] & regs[otg::kDiepmsk]) daint |= 1u << n;
      if (regs[otg::doepint(n)] & regs[otg::kDoepmsk]) daint |= 1u << (16 + n);
    }
    return daint;
  }
  std::uint32_t read(std::uint32_t off) {
    ++reads;
    if (off == otg::kGrstctl) return core_answers ? otg::kGrstctlAhbidl : 0;  // resets and flushes: instant
    if (off == otg::kGintsts) {
      std::uint32_t v = regs[off];
      if (!rx.empty()) v |= otg::kIntRxflvl;
      const std::uint32_t daint = endpoint_flags();
      if (daint & 0xFFFFu) v |= otg::kIntIepint;
      if (daint >> 16) v |= otg::kIntOepint;
      return v;
    }
    if (off == otg::kDaint) return endpoint_flags();
    if (off == otg::kGrxstsp) {
      if (rx.empty()) return 0;
      Entry e = rx.front();
      rx.pop_front();
      rx_data.assign(e.words.begin(), e.words.end());
      return e.status;
    }
    if (off == otg::fifo(0)) {
      if (rx_data.empty()) {
        ++empty_pops;
        return 0xDEADBEEF;
      }
      const std::uint32_t w = rx_data.front();
      rx_data.pop_front();
      return w;
    }
    for (unsigned n = 0; n < otg::kEndpoints; ++n) {
      if (off == otg::dtxfsts(n)) return 16 - static_cast<std::uint32_t>(tx[n].size());
    }
    return regs[off];
  }
  void write(std::uint32_t off, std::uint32_t v) {
    if (off == otg::kGintsts) {
      regs[off] &= ~v;
      return;
    }
    for (unsigned n = 0; n < otg::kEndpoints; ++n) {
      if (off == otg::diepint(n) || off == otg::doepint(n)) {
        regs[off] &= ~v;
        return;
      }
      if (off == otg::fifo(n)) {
        tx[n].push_back(v);
        return;
      }
    }
    if (off == otg::doepctl(0) && (v & otg::kEpctlCnak)) events.push_back("ep0 out enabled");
    if (off == otg::kGrstctl && (v & otg::kGrstctlTxfflsh)) {
      const std::uint32_t which = (v >> 6) & 0x1Fu;
      for (auto& [n, q] : tx) {
        if (which == 0x10 || which == n) q.clear();
      }
    }
    regs[off] = v;
  }
  void delay_ms(int) {}
};

struct Rig {
  FakeOtg io;
  otg::OtgFs<FakeOtg> driver{io};
  hmp::fw::BoardSeam seam;
  std::optional<hmp::fw::Core> core;
  std::optional<usb::Device> dev;
  bool init_ok = false;

  Rig() {
    seam.ctx = this;
    seam.send = [](void* c, const hmp::protocol::Report& r) { return static_cast<Rig*>(c)->dev->queue_report(r); };
    core.emplace(seam);
    init_ok = driver.init();
    dev.emplace(driver.dcd(), *core, "0123456789AB");
    driver.attach(*dev);
    dev->start();
    io.regs[otg::kGintsts] |= otg::kIntUsbrst | otg::kIntEnumdne;
    driver.on_interrupt();
  }
  void irq() { driver.on_interrupt(); }

  // SETUPs as the host sends them back to back; then "SETUP done" (STUP) once the last is in.
  void setups(const std::vector<Bytes>& packets) {
    io.regs[otg::diepctl(0)] &= ~otg::kEpctlStall;  // the core clears EP0's STALL on a SETUP
    io.regs[otg::doepctl(0)] &= ~otg::kEpctlStall;
    for (const Bytes& p : packets) {
      std::vector<std::uint32_t> w(2);
      std::memcpy(w.data(), p.data(), 8);
      io.rx.push_back({FakeOtg::status(0, 8, otg::kPktstsSetupData), w});
    }
    io.rx.push_back({FakeOtg::status(0, 0, otg::kPktstsSetupComplete), {}});
    io.events.push_back("setup received");
    irq();
    io.events.push_back("setup done");
    io.regs[otg::doepint(0)] |= otg::kDoepintStup;
    irq();
  }
  static Bytes pkt(std::uint8_t type, std::uint8_t req, std::uint16_t value, std::uint16_t index, std::uint16_t len) {
    return {type, req, std::uint8_t(value), std::uint8_t(value >> 8), std::uint8_t(index), std::uint8_t(index >> 8),
            std::uint8_t(len), std::uint8_t(len >> 8)};
  }
  bool stalled0() { return (io.regs[otg::diepctl(0)] & otg::kEpctlStall) != 0; }

  // The host takes the IN packet waiting on `ep`, if the endpoint is enabled.
  std::optional<Bytes> in(unsigned ep) {
    std::uint32_t& ctl = io.regs[otg::diepctl(ep)];
    if ((ctl & otg::kEpctlEpena) == 0 || (ctl & otg::kEpctlStall)) return std::nullopt;
    const std::uint32_t bytes = io.regs[otg::dieptsiz(ep)] & 0x7FFFFu;
    Bytes out;
    for (std::uint32_t at = 0; at < bytes; at += 4) {
      EXPECT_FALSE(io.tx[ep].empty()) << "fewer FIFO words than DIEPTSIZ says";
      if (io.tx[ep].empty()) break;
      const std::uint32_t w = io.tx[ep].front();
      io.tx[ep].pop_front();
      for (std::uint32_t k = 0; k < 4 && at + k < bytes; ++k) out.push_back(std::uint8_t(w >> (8 * k)));
    }
    EXPECT_TRUE(io.tx[ep].empty()) << "more FIFO words than DIEPTSIZ says";
    ctl &= ~otg::kEpctlEpena;
    io.regs[otg::diepint(ep)] |= otg::kEpintXfrc;
    irq();
    return out;
  }
  // The host sends an OUT packet; false = NAK (endpoint not enabled).
  bool out(unsigned ep, const Bytes& data) {
    std::uint32_t& ctl = io.regs[otg::doepctl(ep)];
    if ((ctl & otg::kEpctlEpena) == 0 || (ctl & otg::kEpctlStall)) return false;
    std::vector<std::uint32_t> w((data.size() + 3) / 4);
    if (!data.empty()) std::memcpy(w.data(), data.data(), data.size());
    io.rx.push_back({FakeOtg::status(ep, static_cast<unsigned>(data.size()), otg::kPktstsOutData), w});
    io.rx.push_back({FakeOtg::status(ep, 0, otg::kPktstsOutComplete), {}});
    irq();
    ctl &= ~otg::kEpctlEpena;
    io.regs[otg::doepint(ep)] |= otg::kEpintXfrc;
    irq();
    return true;
  }
  // A control read: SETUP, IN packets until a short one, the status ZLP OUT.
  Bytes control_in(const Bytes& setup) {
    setups({setup});
    Bytes all;
    for (int guard = 0; guard < 20; ++guard) {
      auto p = in(0);
      if (!p) break;
      all.insert(all.end(), p->begin(), p->end());
      if (p->size() < 64) break;
    }
    EXPECT_TRUE(out(0, {})) << "status stage OUT not armed";
    return all;
  }
};

TEST(Stm32OtgFs, FifoLayoutFitsTheFifoRamWithoutOverlapAndMeetsTheMinimums) {
  const otg::FifoLayout& l = otg::kFifoLayout;
  // RM0090 §34.11: (5·1 + 8) + (64/4 + 1) + 2·2 + 1 = 35 words for one control endpoint, 64-byte packets,
  // two OUT endpoints.
  EXPECT_EQ(otg::min_rx_fifo_words(1, 64, 2), 35u);
  EXPECT_GE(l.rx_words, 35u);
  std::vector<int> owner(320, -1);
  for (std::uint32_t w = 0; w < l.rx_words; ++w) owner.at(w) = 99;
  for (unsigned ep = 0; ep < otg::kEndpoints; ++ep) {
    EXPECT_GE(l.tx_words[ep], 16u) << ep;  // RM0090: a TX FIFO is at least 16 words
    if (ep <= 1) {
      EXPECT_GE(l.tx_words[ep], 64u / 4) << "a whole 64-byte packet, ep " << ep;
    }
    for (std::uint32_t w = l.tx_start[ep]; w < l.tx_start[ep] + l.tx_words[ep]; ++w) {
      ASSERT_LT(w, 320u) << "TX FIFO " << ep << " past the 1.25 KB FIFO RAM";
      EXPECT_EQ(owner[w], -1) << "word " << w << " used twice";
      owner[w] = static_cast<int>(ep);
    }
  }
}

TEST(Stm32OtgFs, RxStatusDecodesTheReferenceManualFields) {
  // EPNUM 3:0, BCNT 14:4, DPID 16:15 (10 = DATA1), PKTSTS 20:17, FRMNUM 24:21 ignored.
  const otg::RxStatus s = otg::RxStatus::decode(0x1u | 64u << 4 | 0x2u << 15 | 0x2u << 17 | 0xFu << 21);
  EXPECT_EQ(s.ep, 1);
  EXPECT_EQ(s.bytes, 64);
  EXPECT_EQ(s.pid, 2);
  EXPECT_EQ(s.status, 2);
  const otg::RxStatus z = otg::RxStatus::decode(0x3u | 0x3u << 17);
  EXPECT_EQ(z.ep, 3);
  EXPECT_EQ(z.bytes, 0);
  EXPECT_EQ(z.status, 3);
  EXPECT_EQ(otg::RxStatus::decode(1023u << 4).bytes, 1023);
}

TEST(Stm32OtgFs, ACoreThatNeverAnswersFailsInitInBoundedTime) {
  FakeOtg io;
  io.core_answers = false;
  otg::OtgFs<FakeOtg> driver{io};
  EXPECT_FALSE(driver.init());
  EXPECT_LE(io.reads, otg::OtgFs<FakeOtg>::kPolls + 10);
}

TEST(Stm32OtgFs, InitForcesFullSpeedDeviceModeWithoutVbusSensingAndStaysOffTheBusUntilConnect) {
  FakeOtg io;
  otg::OtgFs<FakeOtg> driver{io};
  ASSERT_TRUE(driver.init());
  EXPECT_TRUE(io.regs[otg::kGccfg] & otg::kGccfgNovbussens);
  EXPECT_TRUE(io.regs[otg::kGccfg] & otg::kGccfgPwrdwn);
  EXPECT_TRUE(io.regs[otg::kGusbcfg] & otg::kGusbcfgFdmod);
  EXPECT_EQ(io.regs[otg::kDcfg] & 0x3u, 0x3u);
  EXPECT_TRUE(io.regs[otg::kDctl] & otg::kDctlSdis);
  driver.connect(true);
  EXPECT_FALSE(io.regs[otg::kDctl] & otg::kDctlSdis);
}

TEST(Stm32OtgFs, EnumerationDescriptorsThroughTheFifos) {
  Rig r;
  ASSERT_TRUE(r.init_ok);
  EXPECT_EQ(r.io.regs[otg::doeptsiz(0)] >> 29, 3u) << "three back-to-back SETUPs allowed after reset";
  const Bytes d8 = r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 8));
  ASSERT_EQ(d8.size(), 8u);
  EXPECT_EQ(d8[0], 18);   // bLength
  EXPECT_EQ(d8[1], 1);    // DEVICE
  EXPECT_EQ(d8[7], 64);   // bMaxPacketSize0
  const Bytes d = r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 64));
  ASSERT_EQ(d.size(), 18u);
  EXPECT_EQ(d[8] | d[9] << 8, 0x1209);
  EXPECT_EQ(d[10] | d[11] << 8, 0x0001);
  EXPECT_EQ(r.io.empty_pops, 0);
}

TEST(Stm32OtgFs, SetAddressIsWrittenBeforeTheStatusStageEnds) {
  Rig r;
  r.setups({Rig::pkt(0x00, 5, 42, 0, 0)});
  EXPECT_EQ((r.io.regs[otg::kDcfg] >> 4) & 0x7Fu, 42u) << "DAD written when SET_ADDRESS arrives";
  EXPECT_TRUE(r.io.regs[otg::diepctl(0)] & otg::kEpctlEpena) << "status ZLP still waiting for the host";
  const auto zlp = r.in(0);
  ASSERT_TRUE(zlp.has_value());
  EXPECT_TRUE(zlp->empty());
  EXPECT_EQ(r.io.empty_pops, 0);
}

TEST(Stm32OtgFs, ZeroLengthOutPacketsPopNoDataWord) {
  Rig r;
  r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 18));  // ends with a ZLP OUT status stage
  EXPECT_EQ(r.io.empty_pops, 0);
}

TEST(Stm32OtgFs, BackToBackSetupsTheLastOneIsAnswered) {
  Rig r;
  r.setups({Rig::pkt(0x80, 6, 0x0200, 0, 9), Rig::pkt(0x80, 6, 0x0300, 0, 255), Rig::pkt(0x80, 6, 0x0100, 0, 18)});
  const auto p = r.in(0);
  ASSERT_TRUE(p.has_value());
  ASSERT_EQ(p->size(), 18u);
  EXPECT_EQ((*p)[1], 1) << "the device descriptor: the third SETUP";
  EXPECT_EQ(r.io.empty_pops, 0);
}

TEST(Stm32OtgFs, Ep0OutIsNeverEnabledBeforeSetupDone) {
  Rig r;
  r.io.events.clear();
  r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 18));
  r.control_in(Rig::pkt(0x80, 6, 0x0200, 0, 9));
  // A control write (HID SET_REPORT, 64 bytes of data): its data stage arms EP0 OUT right away.
  r.setups({Rig::pkt(0x00, 5, 3, 0, 0)});
  r.in(0);
  r.setups({Rig::pkt(0x00, 9, 1, 0, 0)});
  r.in(0);
  r.setups({Rig::pkt(0x21, 0x09, 0x0200, 0, 64)});
  EXPECT_TRUE(r.out(0, Bytes(64, 0))) << "data stage armed";
  // Every "ep0 out enabled" must come after the "setup done" of its own transfer.
  std::size_t setups_done = 0;
  for (const std::string& e : r.io.events) {
    if (e == "setup done") {
      ++setups_done;
    }
    if (e == "ep0 out enabled") {
      EXPECT_GT(setups_done, 0u);
    }
  }
  // And the SETUP handling itself (between its data and "setup done") enabled nothing:
  for (std::size_t i = 0; i + 1 < r.io.events.size(); ++i) {
    if (r.io.events[i] == "setup received") {
      EXPECT_EQ(r.io.events[i + 1], "setup done") << "EP0 OUT enabled while the SETUP was still being received";
    }
  }
  EXPECT_NE(std::find(r.io.events.begin(), r.io.events.end(), "ep0 out enabled"), r.io.events.end());
}

TEST(Stm32OtgFs, UnknownRequestStallsEp0AndTheNextSetupWorks) {
  Rig r;
  r.setups({Rig::pkt(0x80, 0x77, 0, 0, 8)});
  EXPECT_TRUE(r.stalled0());
  EXPECT_TRUE(r.io.regs[otg::doepctl(0)] & otg::kEpctlStall);
  const Bytes d = r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 18));
  EXPECT_EQ(d.size(), 18u);
}

TEST(Stm32OtgFs, HidOutReportReachesTheCoreAndTheReplyComesBackOnEp1In) {
  Rig r;
  r.setups({Rig::pkt(0x00, 5, 7, 0, 0)});
  r.in(0);
  r.setups({Rig::pkt(0x00, 9, 1, 0, 0)});  // SET_CONFIGURATION 1
  r.in(0);
  ASSERT_TRUE(r.io.regs[otg::doepctl(1)] & otg::kEpctlUsbaep) << "EP1 OUT opened";
  hmp::protocol::Message hello = hmp::protocol::make(hmp::protocol::Type::hello, 1);
  hmp::protocol::Report report{};
  hmp::protocol::encode(hello, report);
  ASSERT_TRUE(r.out(1, Bytes(report, report + sizeof report))) << "EP1 OUT armed by the stack";
  r.core->on_tick();
  while (r.core->poll()) {
  }
  r.dev->poll();
  const auto reply = r.in(1);
  ASSERT_TRUE(reply.has_value()) << "a report waiting on EP1 IN";
  ASSERT_EQ(reply->size(), 64u);
  EXPECT_EQ((*reply)[0], static_cast<std::uint8_t>(hmp::protocol::Type::hello_reply));
  EXPECT_EQ(r.io.empty_pops, 0);
}

}  // namespace
