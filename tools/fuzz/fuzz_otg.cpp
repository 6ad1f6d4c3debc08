// libFuzzer target for the STM32F407's USB OTG FS device driver (boards/stm32f407/otg_fs.hpp) through the
// controller model of its unit test (tests/boards/stm32f407/otg_fs_model.hpp), with the real USB stack
// (firmware/usb) and firmware core above it. The input (format: otg_ops.hpp) is what the hardware does:
// the host's SETUPs (also back to back, or their two halves apart), OUT packets of any length up to a few
// bytes past 64, IN tokens, bus reset, enumeration done, suspend, resume, stray GINTSTS bits, any RX FIFO
// status word (unknown packet status, byte counts up to 2047, endpoint numbers past 3, data or not), and a
// core that stops answering. The driver's interrupt runs after each operation, or is left pending.
// Traps (besides ASan/UBSan) on:
//  - every contract fault the model records: the RX FIFO popped out of step, an IN packet longer than the
//    endpoint's max packet size or armed on an endpoint still enabled, a TX FIFO written past DIEPTSIZ or
//    its depth or while not enabled, the host finding other than DIEPTSIZ's words, EP0 OUT enabled
//    between a SETUP's data and its STUP;
//  - state out of step with the stack: endpoints 1 IN/OUT active exactly while configured, 2 and 3 never;
//    DCFG.DAD the stack's address;
//  - a packet the driver refuses (Device stats: xfer_refused): the stack never sends where it has one
//    queued, so a refusal is the driver holding on to an ended transfer;
//  - an EP1 IN packet that is not a whole device report that decodes;
//  - a handler that does not finish in bounded time (the register reads of one operation);
//  - the report queue above its bound.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "boards/stm32f407/otg_fs.hpp"
#include "firmware/core.hpp"
#include "firmware/usb/device.hpp"
#include "otg_ops.hpp"
#include "tests/boards/stm32f407/otg_fs_model.hpp"

namespace {

namespace otg = hmp::board::stm32::otg;
namespace protocol = hmp::protocol;
namespace usb = hmp::fw::usb;
using namespace hmp::fuzz::otg_ops;
using Model = hmp::test::OtgModel;
using Driver = otg::OtgFs<Model>;

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_otg: %s\n", what);
  __builtin_trap();
}

struct Input {
  const std::uint8_t* data;
  std::size_t size, at = 0;
  bool more() const { return at < size; }
  std::uint8_t byte() { return at < size ? data[at++] : 0; }
  // Up to `n` bytes from the input into `out` (the rest zero); how many came.
  std::size_t take(std::uint8_t* out, std::size_t n) {
    const std::size_t k = size - at < n ? size - at : n;
    if (k > 0) std::memcpy(out, data + at, k);
    std::memset(out + k, 0, n - k);
    at += k;
    return k;
  }
};

// The device the core's reports go to (a captureless seam function needs a place to find it).
usb::Device* g_device = nullptr;

// The interrupt as the NVIC raises it: while GINTSTS & GINTMSK has a bit set, the handler runs again. A
// handler that leaves a bit set for good would spin on the chip: bounded here, then a finding.
void service(Model& io, Driver& driver) {
  for (int i = 0; i < 64; ++i) {
    if ((io.read(otg::kGintsts) & io.read(otg::kGintmsk)) == 0) return;
    driver.on_interrupt();
  }
  // Left pending after 64 runs: only the RX FIFO (64 entries a run) may legitimately still hold entries.
  if ((io.read(otg::kGintsts) & io.read(otg::kGintmsk) & ~otg::kIntRxflvl) != 0) {
    const std::uint32_t pending = io.read(otg::kGintsts) & io.read(otg::kGintmsk);
    std::fprintf(stderr, "fuzz_otg: pending %08x, DAINT %08x\n", pending, io.read(otg::kDaint));
    fail("interrupt never clears");
  }
}

void check_faults(const Model& io) {
  if (io.faults.empty()) return;
  for (const auto& f : io.faults) std::fprintf(stderr, "fuzz_otg: model fault: %s\n", f.c_str());
  __builtin_trap();
}

void check_endpoints(Model& io, const usb::Device& dev) {
  if (io.regs[otg::kGintsts] & otg::kIntUsbrst) return;  // the core has reset them; the handler has not run
  if (((io.regs[otg::kDcfg] >> 4) & 0x7Fu) != dev.address()) fail("DCFG.DAD is not the stack's address");
  const bool configured = dev.configuration() != 0;
  for (unsigned n = 1; n < otg::kEndpoints; ++n) {
    const bool in_active = (io.regs[otg::diepctl(n)] & otg::kEpctlUsbaep) != 0;
    const bool out_active = (io.regs[otg::doepctl(n)] & otg::kEpctlUsbaep) != 0;
    const bool want = n == 1 && configured;
    if (in_active != want || out_active != want) {
      std::fprintf(stderr, "fuzz_otg: EP%u IN %d OUT %d, configuration %u\n", n, in_active, out_active,
                   dev.configuration());
      fail("endpoint activity out of step with the configuration");
    }
  }
}

void check_report(const Model::Bytes& packet) {
  if (packet.size() != protocol::kReportSize) fail("EP1 IN packet is not a whole report");
  protocol::Report r;
  std::memcpy(r, packet.data(), sizeof r);
  protocol::Message m;
  if (protocol::decode(r, m) != protocol::ErrorCode::none || protocol::is_host_to_device(m.type)) {
    fail("EP1 IN packet does not decode as a device report");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Model io;
  io.flags_on_pop = true;  // STUP and OUT XFRC come from the core, when their status words are popped
  io.record_events = false;
  Driver driver{io};
  hmp::fw::BoardSeam seam;
  seam.send = [](void*, const protocol::Report& r) { return g_device->queue_report(r); };
  hmp::fw::Core core(seam, 1000);
  if (!driver.init()) fail("init failed on a core that answers");
  usb::Device dev(driver.dcd(), core, "FUZZ0001");
  g_device = &dev;
  driver.attach(dev);
  dev.start();
  check_faults(io);

  Input in{data, size};
  while (in.more()) {
    const std::uint8_t op = in.byte();
    const std::uint64_t reads_before = io.reads;
    bool stuck = false;
    switch (op & 0x0F) {
      case kSetups: {
        const int n = 1 + in.byte() % 3;
        for (int i = 0; i < n; ++i) {
          std::uint8_t p[8];
          in.take(p, 8);
          io.host_setup(p);
        }
        io.host_setup_done();
        break;
      }
      case kSetupData: {
        std::uint8_t p[8];
        in.take(p, 8);
        io.host_setup(p);
        break;
      }
      case kSetupDone: io.host_setup_done(); break;
      case kIn: {
        const unsigned ep = in.byte() % otg::kEndpoints;
        const auto packet = io.host_in(ep);
        if (packet && ep == 1) check_report(*packet);
        break;
      }
      case kOut: {
        const unsigned ep = in.byte() % otg::kEndpoints;
        std::uint8_t buf[72];
        const std::size_t len = in.byte() % sizeof buf;
        in.take(buf, len);
        io.host_out(ep, buf, len);
        break;
      }
      case kOutReport: {
        std::uint8_t buf[protocol::kReportSize];
        in.take(buf, sizeof buf);
        io.host_out(1, buf, sizeof buf);
        break;
      }
      case kRawEntry: {
        std::uint8_t w[4];
        in.take(w, 4);
        const std::uint32_t word = w[0] | w[1] << 8 | w[2] << 16 | static_cast<std::uint32_t>(w[3]) << 24;
        const std::uint32_t status = word & 0x1FFFFFu;  // EPNUM, BCNT, DPID, PKTSTS
        std::uint8_t buf[2048];
        const std::size_t bytes = (status >> 4) & 0x7FFu;
        in.take(buf, bytes);
        io.push_entry(status, buf, bytes);
        break;
      }
      case kBusReset: io.host_reset(); break;
      case kEnumDone: io.regs[otg::kGintsts] |= otg::kIntEnumdne; break;
      case kSuspend: io.regs[otg::kGintsts] |= otg::kIntUsbsusp; break;
      case kResume: io.regs[otg::kGintsts] |= otg::kIntWkupint; break;
      case kRawFlags: {
        std::uint8_t w[4];
        in.take(w, 4);
        std::uint32_t bits = w[0] | w[1] << 8 | w[2] << 16 | static_cast<std::uint32_t>(w[3]) << 24;
        bits &= ~(otg::kIntRxflvl | otg::kIntIepint | otg::kIntOepint);  // computed by the core
        if (bits & otg::kIntUsbrst) io.host_reset();
        io.regs[otg::kGintsts] |= bits;
        break;
      }
      case kTicks: {
        const int n = 1 + in.byte() % 32;
        for (int i = 0; i < n; ++i) {
          core.on_tick();
          while (core.poll()) {
          }
          dev.poll();
        }
        break;
      }
      case kCoreStuck: stuck = true; break;
      default: break;
    }
    check_faults(io);
    if ((op & kDeferIrq) == 0 || stuck) {
      io.core_answers = !stuck;
      service(io, driver);
      io.core_answers = true;
      check_faults(io);
    }
    // One operation: a few handler runs, each with at most a few bounded waits on the core.
    if (io.reads - reads_before > 64 * 8 * std::uint64_t{Driver::kPolls}) fail("handler took unbounded time");
    check_endpoints(io, dev);
    if (dev.queued_reports() > usb::Device::kQueueReports) fail("report queue past its bound");
    if (dev.stats().xfer_refused != 0) fail("a packet refused although the stack had nothing queued there");
  }
  g_device = nullptr;
  return 0;
}
