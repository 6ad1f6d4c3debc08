#pragma once
// A model of the STM32F407's USB OTG FS core in device mode (RM0090 §34, slave mode), the "hardware" under
// boards/stm32f407/otg_fs.hpp on a PC: the unit test (otg_fs_test.cpp) and the fuzzer (tools/fuzz/
// fuzz_otg.cpp) both drive the driver through it. No GoogleTest here: what the driver does wrong is
// recorded in `faults` (each caller checks it its own way).
//
// What it keeps from the reference manual:
//  - registers keep what is written, except: GINTSTS, DIEPINTx and DOEPINTx are write-1-to-clear;
//    GINTSTS.RXFLVL/IEPINT/OEPINT and DAINT follow the FIFO and endpoint flags (read-only; IEPINT/OEPINT
//    only for endpoints DAINTMSK lets through);
//  - DxEPCTL: EPENA can be set by software, only the core clears it (packet done, or EPDIS: then EPDISD);
//    CNAK/SNAK/SD0PID/EPDIS are commands that read back 0; SNAK/CNAK set and clear NAKSTS;
//  - the RX FIFO presents a status word (GRXSTSP) and then that entry's data words: BCNT bytes rounded up
//    to whole words, whatever the packet status; RXFFLSH empties it;
//  - with `flags_on_pop`, popping "SETUP done" raises DOEPINT.STUP and popping "OUT transfer completed"
//    raises DOEPINT.XFRC (the core raises them then; the unit test raises them itself);
//  - TX FIFOs as deep as DIEPTXF0/DIEPTXFx say (DTXFSTS = free words), emptied by TXFFLSH (and CSRST);
//  - a USB reset (host_reset) deactivates every endpoint but 0 (USBAEP) and leaves queued packets queued;
//  - resets and flushes finish at once while `core_answers`.
// Contract checks (a `faults` entry each): the RX FIFO popped out of step (a data word that is not there,
// a status word popped while the previous entry still has data, or with the FIFO empty); an IN packet
// armed (DIEPTSIZ written) on an endpoint still enabled, enabled on one not active, or longer than the
// endpoint's max packet size; a TX FIFO written while its endpoint is not enabled, past DIEPTSIZ, or past
// its depth; the host finding fewer or more FIFO words than DIEPTSIZ; EP0 OUT enabled between a SETUP's
// data and the handling of its STUP.
#include <array>
#include <cstdint>
#include <cstring>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "boards/stm32f407/otg_fs_regs.hpp"

namespace hmp::test {

class OtgModel {
 public:
  using Bytes = std::vector<std::uint8_t>;
  struct Entry {
    std::uint32_t status;
    std::vector<std::uint32_t> words;
  };
  // The register block (offsets below the FIFOs), indexed by byte offset as in otg_fs_regs.hpp.
  struct Regs {
    std::array<std::uint32_t, 0x1000 / 4> words{};
    std::uint32_t& operator[](std::uint32_t offset) { return words[(offset & 0xFFFu) / 4]; }
  };

  static constexpr unsigned kEps = board::stm32::otg::kEndpoints;
  Regs regs;
  std::deque<Entry> rx;               // entries not yet popped
  std::deque<std::uint32_t> rx_data;  // data words of the entry popped last
  std::array<std::deque<std::uint32_t>, kEps> tx;
  bool core_answers = true;
  bool flags_on_pop = false;
  bool record_events = true;
  int empty_pops = 0;  // FIFO reads with no data word to give
  std::uint64_t reads = 0;
  std::vector<std::string> events;
  std::vector<std::string> faults;

  static std::uint32_t status(unsigned ep, unsigned bytes, unsigned pktsts) { return ep | bytes << 4 | pktsts << 17; }

  // ---- the driver's side (the Io of OtgFs) ----
  std::uint32_t read(std::uint32_t off) {
    namespace otg = board::stm32::otg;
    ++reads;
    if (off == otg::kGrstctl) return core_answers ? otg::kGrstctlAhbidl : 0;
    if (off == otg::kGintsts) {
      std::uint32_t v = regs[off];
      if (!rx.empty()) v |= otg::kIntRxflvl;
      const std::uint32_t daint = endpoint_flags() & regs[otg::kDaintmsk];  // DAINTMSK gates IEPINT/OEPINT
      if (daint & 0xFFFFu) v |= otg::kIntIepint;
      if (daint >> 16) v |= otg::kIntOepint;
      return v;
    }
    if (off == otg::kDaint) return endpoint_flags();
    if (off == otg::kGrxstsp) return pop_status();
    if (off == otg::fifo(0)) {
      if (rx_data.empty()) {
        ++empty_pops;
        fault("RX FIFO read with no data word left");
        return 0xDEADBEEF;
      }
      const std::uint32_t w = rx_data.front();
      rx_data.pop_front();
      return w;
    }
    if (off >= 0x1000) {
      fault("read past the register block");
      return 0;
    }
    for (unsigned n = 0; n < kEps; ++n) {
      if (off == otg::dtxfsts(n)) return tx_depth(n) - static_cast<std::uint32_t>(tx[n].size());
    }
    return regs[off];
  }

  void write(std::uint32_t off, std::uint32_t v) {
    namespace otg = board::stm32::otg;
    if (off == otg::kGintsts) {
      regs[off] &= ~v;
      return;
    }
    for (unsigned n = 0; n < kEps; ++n) {
      if (off == otg::dieptsiz(n) && (regs[otg::diepctl(n)] & otg::kEpctlEpena)) {
        fault("IN packet armed on an endpoint still enabled");
      }
      if (off == otg::diepint(n) || off == otg::doepint(n)) {
        if (n == 0 && off == otg::doepint(0) && (v & regs[off] & otg::kDoepintStup)) setup_in_flight_ = false;
        regs[off] &= ~v;
        return;
      }
      if (off == otg::fifo(n)) {
        write_tx(n, v);
        return;
      }
      if (off == otg::diepctl(n)) {
        write_epctl(n, true, v);
        return;
      }
      if (off == otg::doepctl(n)) {
        write_epctl(n, false, v);
        return;
      }
    }
    if (off >= 0x1000) {
      fault("write past the register block");
      return;
    }
    if (off == otg::kGrstctl) {
      if (v & otg::kGrstctlTxfflsh) {
        const std::uint32_t which = (v >> 6) & 0x1Fu;
        for (unsigned n = 0; n < kEps; ++n) {
          if (which == 0x10 || which == n) {
            tx[n].clear();
            in_words_written_[n] = 0;
          }
        }
      }
      if (v & otg::kGrstctlRxfflsh) {
        rx.clear();
        rx_data.clear();
      }
      if (v & otg::kGrstctlCsrst) {  // a core soft reset flushes every FIFO (registers keep their values)
        rx.clear();
        rx_data.clear();
        for (auto& q : tx) q.clear();
      }
    }
    regs[off] = v;
  }
  void delay_ms(int) {}

  // ---- the host's side ----
  // One RX FIFO entry: `status` and BCNT bytes of `data` (zero-padded), in whole words.
  void push_entry(std::uint32_t status_word, const std::uint8_t* data, std::size_t size) {
    const std::uint32_t bytes = (status_word >> 4) & 0x7FFu;
    std::vector<std::uint32_t> w((bytes + 3) / 4, 0);
    const std::size_t take = size < bytes ? size : bytes;
    if (take > 0) std::memcpy(w.data(), data, take);
    rx.push_back({status_word, std::move(w)});
  }
  // A SETUP on EP0: always accepted; clears EP0's STALL in both directions.
  void host_setup(const std::uint8_t (&packet)[8]) {
    namespace otg = board::stm32::otg;
    regs[otg::diepctl(0)] &= ~otg::kEpctlStall;
    regs[otg::doepctl(0)] &= ~otg::kEpctlStall;
    push_entry(status(0, 8, otg::kPktstsSetupData), packet, 8);
  }
  void host_setup_done() { push_entry(status(0, 0, board::stm32::otg::kPktstsSetupComplete), nullptr, 0); }

  // The host's IN token on `ep`: the packet waiting there, or nothing (NAK or STALL). Takes it and raises
  // DIEPINT.XFRC.
  std::optional<Bytes> host_in(unsigned ep) {
    namespace otg = board::stm32::otg;
    std::uint32_t& ctl = regs[otg::diepctl(ep)];
    if ((ctl & otg::kEpctlEpena) == 0 || (ctl & otg::kEpctlStall)) return std::nullopt;
    const std::uint32_t bytes = regs[otg::dieptsiz(ep)] & 0x7FFFFu;
    Bytes out;
    for (std::uint32_t at = 0; at < bytes; at += 4) {
      if (tx[ep].empty()) {
        fault("fewer TX FIFO words than DIEPTSIZ says");
        break;
      }
      const std::uint32_t w = tx[ep].front();
      tx[ep].pop_front();
      for (std::uint32_t k = 0; k < 4 && at + k < bytes; ++k) out.push_back(std::uint8_t(w >> (8 * k)));
    }
    if (!tx[ep].empty()) fault("more TX FIFO words than DIEPTSIZ says");
    tx[ep].clear();
    ctl &= ~otg::kEpctlEpena;
    in_words_written_[ep] = 0;
    regs[otg::diepint(ep)] |= otg::kEpintXfrc;
    return out;
  }
  // The host's OUT packet on `ep`: false = NAK or STALL (not enabled, or NAKing). Queues the data and the
  // "transfer completed" entry; the endpoint is disabled (and NAKs) until armed again.
  bool host_out(unsigned ep, const std::uint8_t* data, std::size_t size) {
    namespace otg = board::stm32::otg;
    std::uint32_t& ctl = regs[otg::doepctl(ep)];
    if ((ctl & otg::kEpctlEpena) == 0 || (ctl & otg::kEpctlStall) || (ctl & kNaksts)) return false;
    push_entry(status(ep, static_cast<unsigned>(size), otg::kPktstsOutData), data, size);
    push_entry(status(ep, 0, otg::kPktstsOutComplete), nullptr, 0);
    ctl = (ctl & ~otg::kEpctlEpena) | kNaksts;
    return true;
  }
  // USB reset signalling: GINTSTS.USBRST; the core deactivates every endpoint but 0 (USBAEP).
  void host_reset() {
    namespace otg = board::stm32::otg;
    regs[otg::kGintsts] |= otg::kIntUsbrst;
    for (unsigned n = 1; n < kEps; ++n) {
      regs[otg::diepctl(n)] &= ~otg::kEpctlUsbaep;
      regs[otg::doepctl(n)] &= ~otg::kEpctlUsbaep;
    }
    setup_in_flight_ = false;
  }

  // Max packet size of IN endpoint `ep` as DIEPCTL says (EP0: MPSIZ 00 = 64 … 11 = 8).
  std::uint32_t in_max_packet(unsigned ep) {
    const std::uint32_t ctl = regs[board::stm32::otg::diepctl(ep)];
    if (ep == 0) return 64u >> (ctl & 0x3u);
    return ctl & 0x7FFu;
  }

 private:
  static constexpr std::uint32_t kNaksts = 1u << 17;
  void fault(const char* what) { faults.emplace_back(what); }

  std::uint32_t tx_depth(unsigned n) {
    namespace otg = board::stm32::otg;
    const std::uint32_t depth = regs[n == 0 ? otg::kDieptxf0 : otg::dieptxf(n)] >> 16;
    return depth;
  }

  std::uint32_t endpoint_flags() {
    namespace otg = board::stm32::otg;
    std::uint32_t daint = 0;
    for (unsigned n = 0; n < kEps; ++n) {
      if (regs[otg::diepint(n)] & regs[otg::kDiepmsk]) daint |= 1u << n;
      if (regs[otg::doepint(n)] & regs[otg::kDoepmsk]) daint |= 1u << (16 + n);
    }
    return daint;
  }

  std::uint32_t pop_status() {
    namespace otg = board::stm32::otg;
    if (!rx_data.empty()) fault("RX status popped before the previous entry's data");
    if (rx.empty()) {
      fault("RX status popped with the RX FIFO empty");
      return 0;
    }
    Entry e = std::move(rx.front());
    rx.pop_front();
    rx_data.assign(e.words.begin(), e.words.end());
    const unsigned ep = e.status & 0xFu, pktsts = (e.status >> 17) & 0xFu;
    if (pktsts == otg::kPktstsSetupData && ep == 0) setup_in_flight_ = true;
    if (flags_on_pop && ep < kEps) {
      if (pktsts == otg::kPktstsSetupComplete) regs[otg::doepint(ep)] |= otg::kDoepintStup;
      if (pktsts == otg::kPktstsOutComplete) regs[otg::doepint(ep)] |= otg::kEpintXfrc;
    }
    return e.status;
  }

  void write_epctl(unsigned n, bool in, std::uint32_t v) {
    namespace otg = board::stm32::otg;
    const std::uint32_t reg = in ? otg::diepctl(n) : otg::doepctl(n);
    const std::uint32_t old = regs[reg];
    constexpr std::uint32_t kCommands =
        otg::kEpctlCnak | otg::kEpctlSnak | otg::kEpctlSd0pid | (1u << 29) | otg::kEpctlEpdis;
    std::uint32_t now =
        (v & ~kCommands & ~otg::kEpctlEpena & ~kNaksts) | (old & kNaksts) | ((old | v) & otg::kEpctlEpena);
    if (v & otg::kEpctlSnak) now |= kNaksts;
    if (v & otg::kEpctlCnak) now &= ~kNaksts;
    if ((v & otg::kEpctlEpdis) && (old & otg::kEpctlEpena)) {
      now &= ~otg::kEpctlEpena;
      regs[in ? otg::diepint(n) : otg::doepint(n)] |= otg::kEpintEpdisd;
    }
    const bool enabled = (now & otg::kEpctlEpena) && !(old & otg::kEpctlEpena);
    if (!in && n == 0 && ((v & otg::kEpctlCnak) || enabled)) {
      if (record_events && (v & otg::kEpctlCnak)) events.push_back("ep0 out enabled");
      if (setup_in_flight_) fault("EP0 OUT enabled between a SETUP's data and its STUP");
    }
    regs[reg] = now;
    if (in && enabled) {
      // (Unless a USB reset deactivated it and the driver's handler has not run yet: the stack could not know.)
      if (n != 0 && !(now & otg::kEpctlUsbaep) && !(regs[otg::kGintsts] & otg::kIntUsbrst)) {
        fault("IN packet armed on an endpoint that is not active");
      }
      const std::uint32_t siz = regs[otg::dieptsiz(n)];
      const std::uint32_t bytes = siz & 0x7FFFFu, packets = (siz >> 19) & 0x3FFu;
      if (bytes > in_max_packet(n)) fault("IN packet longer than the endpoint's max packet size");
      if (packets != 1) fault("IN packet count is not 1");
      in_words_expected_[n] = (bytes + 3) / 4;
      in_words_written_[n] = 0;
    }
  }

  void write_tx(unsigned n, std::uint32_t v) {
    namespace otg = board::stm32::otg;
    if ((regs[otg::diepctl(n)] & otg::kEpctlEpena) == 0) fault("TX FIFO written while its endpoint is not enabled");
    if (in_words_written_[n] >= in_words_expected_[n]) fault("TX FIFO written past DIEPTSIZ");
    if (tx[n].size() >= tx_depth(n)) {
      fault("TX FIFO written past its depth");
      return;
    }
    ++in_words_written_[n];
    tx[n].push_back(v);
  }

  bool setup_in_flight_ = false;
  std::array<std::uint32_t, kEps> in_words_expected_{}, in_words_written_{};
};

}  // namespace hmp::test
