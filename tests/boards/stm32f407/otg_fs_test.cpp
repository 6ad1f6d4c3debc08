// The STM32F407's USB OTG FS device driver (boards/stm32f407/otg_fs.hpp) on a PC, against the model of the
// controller in otg_fs_model.hpp (RM0090 §34, device mode, slave mode; the fuzzer tools/fuzz/fuzz_otg.cpp
// drives the same model): registers that keep what is written, write-1-to-clear interrupt flags, an RX
// FIFO that presents a status word (GRXSTSP) and then that entry's data words, TX FIFOs that collect the
// words written, SETUP packets always accepted (STUPCNT), EP0's STALL cleared by the next SETUP, a packet
// taken only from an enabled endpoint; every Rig checks at the end that the model saw no contract fault
// (FIFOs popped or filled out of step, packets over the max packet size, …). The driver runs
// with the real USB stack (firmware/usb) and core above it; expected bytes come from USB 2.0 ch. 9 and
// docs/usb.md's identity (1209:0001), not from the code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "boards/stm32f407/otg_fs.hpp"
#include "firmware/core.hpp"
#include "firmware/usb/device.hpp"
#include "tests/boards/stm32f407/otg_fs_model.hpp"

namespace {

namespace otg = hmp::board::stm32::otg;
namespace usb = hmp::fw::usb;
using Bytes = std::vector<std::uint8_t>;

using FakeOtg = hmp::test::OtgModel;

// Every contract fault the model recorded, one per line (empty: none).
std::string faults(const FakeOtg& io) {
  std::string all;
  for (const std::string& f : io.faults) all += f + "\n";
  return all;
}

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
  ~Rig() { EXPECT_EQ(faults(io), ""); }
  void irq() { driver.on_interrupt(); }

  // SETUPs as the host sends them back to back; then "SETUP done" (STUP) once the last is in.
  void setups(const std::vector<Bytes>& packets) {
    for (const Bytes& p : packets) {
      std::uint8_t b[8];
      std::memcpy(b, p.data(), 8);
      io.host_setup(b);  // the core clears EP0's STALL on a SETUP
    }
    io.host_setup_done();
    io.events.push_back("setup received");
    irq();
    io.events.push_back("setup done");
    io.regs[otg::doepint(0)] |= otg::kDoepintStup;
    irq();
  }
  static Bytes pkt(std::uint8_t type, std::uint8_t req, std::uint16_t value, std::uint16_t index, std::uint16_t len) {
    return {type,
            req,
            std::uint8_t(value),
            std::uint8_t(value >> 8),
            std::uint8_t(index),
            std::uint8_t(index >> 8),
            std::uint8_t(len),
            std::uint8_t(len >> 8)};
  }
  bool stalled0() { return (io.regs[otg::diepctl(0)] & otg::kEpctlStall) != 0; }

  // The host takes the IN packet waiting on `ep`, if the endpoint is enabled.
  std::optional<Bytes> in(unsigned ep) {
    std::optional<Bytes> p = io.host_in(ep);
    if (p) irq();
    return p;
  }
  // The host sends an OUT packet; false = NAK (endpoint not enabled).
  bool out(unsigned ep, const Bytes& data) {
    if (!io.host_out(ep, data.data(), data.size())) return false;
    irq();
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
  EXPECT_EQ(d8[0], 18);  // bLength
  EXPECT_EQ(d8[1], 1);   // DEVICE
  EXPECT_EQ(d8[7], 64);  // bMaxPacketSize0
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

// RX FIFO entries the core does not send (found by fuzz_otg): each one's data is popped and dropped, so
// the FIFO stays in step and the next SETUP is read where it is.
TEST(Stm32OtgFs, OddRxEntriesArePoppedWholeAndTheNextSetupIsRead) {
  Rig r;
  const std::uint8_t junk[64] = {0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA};
  r.io.push_entry(FakeOtg::status(0, 8, 7), junk, 8);                          // PKTSTS 7: reserved
  r.io.push_entry(FakeOtg::status(0, 12, otg::kPktstsOutComplete), junk, 12);  // a status word with data
  r.io.push_entry(FakeOtg::status(9, 64, otg::kPktstsOutData), junk, 64);      // no endpoint 9
  r.irq();
  EXPECT_TRUE(r.io.rx_data.empty()) << "data of a dropped entry left in the FIFO";
  const Bytes d = r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 18));
  ASSERT_EQ(d.size(), 18u);
  EXPECT_EQ(d[1], 1);
  EXPECT_EQ(r.io.empty_pops, 0);
}

// OUT data for an endpoint number the core does not have used to land in EP0's buffer (seen while writing
// fuzz_otg): here it would have become the SET_REPORT data and the host's real report been dropped.
TEST(Stm32OtgFs, OutDataForAnEndpointOutOfRangeDoesNotLandInEp0) {
  Rig r;
  r.setups({Rig::pkt(0x00, 5, 7, 0, 0)});
  r.in(0);
  r.setups({Rig::pkt(0x00, 9, 1, 0, 0)});
  r.in(0);
  r.setups({Rig::pkt(0x21, 0x09, 0x0200, 0, 64)});  // SET_REPORT: EP0 OUT armed for 64 bytes
  const Bytes zeros(64, 0);
  r.io.push_entry(FakeOtg::status(9, 64, otg::kPktstsOutData), zeros.data(), zeros.size());
  hmp::protocol::Report report{};
  hmp::protocol::encode(hmp::protocol::make(hmp::protocol::Type::hello, 1), report);
  ASSERT_TRUE(r.out(0, Bytes(report, report + sizeof report)));
  ASSERT_TRUE(r.in(0).has_value()) << "status stage";
  r.core->on_tick();
  while (r.core->poll()) {
  }
  r.dev->poll();
  const auto reply = r.in(1);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ((*reply)[0], static_cast<std::uint8_t>(hmp::protocol::Type::hello_reply)) << "the host's report came";
}

// A SETUP entry that is not 8 bytes is no SETUP (seen while writing fuzz_otg): it used to be handed on with
// the previous SETUP's bytes after its own.
TEST(Stm32OtgFs, ASetupEntryThatIsNot8BytesIsDropped) {
  Rig r;
  ASSERT_EQ(r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 18)).size(), 18u);
  const std::uint8_t head[4] = {0x80, 6, 0x00, 0x02};  // GET_DESCRIPTOR configuration, cut short
  r.io.push_entry(FakeOtg::status(0, 4, otg::kPktstsSetupData), head, 4);
  r.io.host_setup_done();
  r.irq();
  r.io.regs[otg::doepint(0)] |= otg::kDoepintStup;
  r.irq();
  EXPECT_FALSE(r.in(0).has_value()) << "a request the host never sent was answered";
  EXPECT_EQ(r.dev->stats().setups, 1u);
}

// A SETUP entry cut short still opens a setup phase in the core (found by fuzz_otg): the host taking the
// previous control read's reply then used to reach the stack, which enabled EP0 OUT for that transfer's
// status stage before the STUP. After the STUP the transfer has ended and the next SETUP works.
TEST(Stm32OtgFs, AShortSetupEntryKeepsEp0OutOffUntilItsStup) {
  Rig r;
  r.setups({Rig::pkt(0x80, 6, 0x0100, 0, 18)});
  const std::uint8_t head[4] = {0x80, 6, 0x00, 0x02};
  r.io.push_entry(FakeOtg::status(0, 4, otg::kPktstsSetupData), head, 4);
  r.irq();
  r.io.events.clear();
  ASSERT_TRUE(r.in(0).has_value()) << "the reply was queued before the short SETUP";
  EXPECT_EQ(std::count(r.io.events.begin(), r.io.events.end(), "ep0 out enabled"), 0);
  r.io.host_setup_done();
  r.irq();
  r.io.regs[otg::doepint(0)] |= otg::kDoepintStup;
  r.irq();
  EXPECT_FALSE(r.out(0, {})) << "a status stage armed for a transfer the SETUP ended";
  EXPECT_EQ(r.dev->stats().setups, 1u);
  const Bytes d = r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 18));
  EXPECT_EQ(d.size(), 18u);
}

// A SETUP ends the control transfer before it (USB 2.0 §8.5.3), also one whose reply the host did not
// read: the core keeps that packet queued, so the driver takes it back (found by fuzz_otg: the new reply
// used to be refused and the host got the old one).
TEST(Stm32OtgFs, ASetupTakesBackAnUnreadEp0InPacket) {
  Rig r;
  r.setups({Rig::pkt(0x80, 6, 0x0200, 0, 9)});  // configuration header, never read
  const Bytes d = r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 18));
  ASSERT_EQ(d.size(), 18u);
  EXPECT_EQ(d[1], 1) << "the device descriptor, not the old reply";
  EXPECT_EQ(r.dev->stats().xfer_refused, 0u);
}

// The previous transfer's last IN packet taken by the host and the next SETUP: as the handler sees them
// when the SETUP's entries were popped in one run and its STUP and the IN completion come in the next, the
// old completion is not taken for the new transfer's first packet (the second one used to be refused and
// the reply cut short).
TEST(Stm32OtgFs, AStaleEp0InCompletionIsNotTakenForTheNewTransfer) {
  Rig r;
  r.setups({Rig::pkt(0x00, 5, 7, 0, 0)});  // SET_ADDRESS: its status ZLP waits on EP0 IN
  const std::uint8_t product[8] = {0x80, 6, 0x02, 0x03, 0x09, 0x04, 255, 0};  // 82 bytes: two packets
  r.io.host_setup(product);
  r.io.host_setup_done();
  r.irq();                                   // the SETUP's entries popped
  ASSERT_TRUE(r.io.host_in(0).has_value());  // the ZLP's completion, not seen yet
  r.io.regs[otg::doepint(0)] |= otg::kDoepintStup;
  r.irq();  // STUP and the old completion in one run
  Bytes all;
  for (int guard = 0; guard < 4; ++guard) {
    auto p = r.in(0);
    if (!p) break;
    all.insert(all.end(), p->begin(), p->end());
    if (p->size() < 64) break;
  }
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.size(), all[0]);
  EXPECT_GT(all.size(), 64u);
  EXPECT_EQ(r.dev->stats().xfer_refused, 0u);
}

// A bus reset takes back an EP0 IN packet still queued (the core keeps it; the reset flushes its FIFO):
// the new session's first reply used to be refused.
TEST(Stm32OtgFs, ABusResetTakesBackAQueuedEp0InPacket) {
  Rig r;
  r.setups({Rig::pkt(0x80, 6, 0x0200, 0, 9)});  // reply never read
  r.io.host_reset();
  r.io.regs[otg::kGintsts] |= otg::kIntEnumdne;
  r.irq();
  const Bytes d = r.control_in(Rig::pkt(0x80, 6, 0x0100, 0, 18));
  ASSERT_EQ(d.size(), 18u);
  EXPECT_EQ(d[1], 1);
  EXPECT_EQ(r.dev->stats().xfer_refused, 0u);
}

// A control read's last IN packet taken by the host and the next SETUP read, but its STUP not handled yet
// (found by fuzz_otg): the old completion used to reach the stack then, which enabled EP0 OUT for the
// status stage of the transfer the SETUP had already ended.
TEST(Stm32OtgFs, AnEp0InCompletionWithASetupPendingDoesNotEnableEp0Out) {
  Rig r;
  r.setups({Rig::pkt(0x80, 6, 0x0100, 0, 18)});
  ASSERT_TRUE(r.io.host_in(0).has_value()) << "host takes the reply; the handler has not run yet";
  std::uint8_t next[8] = {0x80, 6, 0x00, 0x01, 0, 0, 18, 0};
  r.io.host_setup(next);
  r.io.host_setup_done();
  r.io.events.clear();
  r.irq();  // the SETUP's data and the IN completion together
  EXPECT_EQ(std::count(r.io.events.begin(), r.io.events.end(), "ep0 out enabled"), 0);
  r.io.regs[otg::doepint(0)] |= otg::kDoepintStup;
  r.irq();
  const auto d = r.in(0);
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->size(), 18u);
  EXPECT_TRUE(r.out(0, {})) << "status stage armed after the reply";
}

}  // namespace
