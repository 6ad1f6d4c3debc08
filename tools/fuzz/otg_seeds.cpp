// Writes the seed corpus of fuzz_otg (input format: otg_ops.hpp): whole enumerations as Linux does them
// (device descriptor, SET_ADDRESS, configuration, strings, SET_CONFIGURATION, HID report descriptor), then
// HID reports both ways (interrupt OUT, SET_REPORT), a suspend/resume and a second enumeration after a bus
// reset, back-to-back SETUPs, and RX FIFO entries of the kinds the core does not send.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "otg_ops.hpp"
#include "seed_file.hpp"
#include "shared/protocol/protocol.hpp"

namespace protocol = hmp::protocol;
using namespace hmp::fuzz::otg_ops;

namespace {

struct Program {
  std::vector<std::uint8_t> bytes;

  void op(Op o, std::initializer_list<std::uint8_t> operands = {}) {
    bytes.push_back(o);
    bytes.insert(bytes.end(), operands);
  }
  void setup(std::uint8_t type, std::uint8_t request, std::uint16_t value, std::uint16_t index, std::uint16_t len) {
    op(kSetups, {0, type, request, std::uint8_t(value), std::uint8_t(value >> 8), std::uint8_t(index),
                 std::uint8_t(index >> 8), std::uint8_t(len), std::uint8_t(len >> 8)});
  }
  // A control read of up to `len` bytes: SETUP, `packets` IN tokens, the status stage's ZLP.
  void control_in(std::uint8_t type, std::uint8_t request, std::uint16_t value, std::uint16_t len, int packets) {
    setup(type, request, value, 0, len);
    for (int i = 0; i < packets; ++i) op(kIn, {0});
    op(kOut, {0, 0});
  }
  // A request without data: SETUP, the status stage's IN ZLP.
  void control_none(std::uint8_t type, std::uint8_t request, std::uint16_t value) {
    setup(type, request, value, 0, 0);
    op(kIn, {0});
  }
  void enumerate() {
    op(kBusReset);
    op(kEnumDone);
    control_in(0x80, 6, 0x0100, 64, 1);  // GET_DESCRIPTOR device, 64 as Linux asks first
    control_none(0x00, 5, 7);            // SET_ADDRESS 7
    control_in(0x80, 6, 0x0100, 18, 1);
    control_in(0x80, 6, 0x0200, 9, 1);    // configuration, header
    control_in(0x80, 6, 0x0200, 255, 2);  // configuration, whole
    control_in(0x80, 6, 0x0300, 255, 1);  // string 0 (languages)
    control_in(0x80, 6, 0x0302, 255, 2);  // product
    control_in(0x80, 6, 0x0303, 255, 2);  // serial
    control_none(0x00, 9, 1);             // SET_CONFIGURATION 1
    control_none(0x21, 0x0A, 0);          // SET_IDLE
    setup(0x81, 6, 0x2200, 0, 255);       // HID report descriptor
    op(kIn, {0});
    op(kIn, {0});
    op(kOut, {0, 0});
  }
  void report(const protocol::Report& r) { bytes.insert(bytes.end(), r, r + sizeof r); }
};

bool write(const std::string& dir, const std::string& name, const Program& p) {
  return hmp::fuzz::write_seed_file(dir + "/" + name + ".bin", p.bytes.data(), p.bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = hmp::fuzz::seed_dir(argc, argv);
  if (dir.empty()) return 2;
  protocol::Report hello;
  if (!protocol::encode(protocol::make(protocol::Type::hello, 1), hello)) return 1;
  bool ok = true;

  Program enumerate;
  enumerate.enumerate();
  ok = write(dir, "enumerate", enumerate) && ok;

  Program interrupt_out = enumerate;  // a report on EP1 OUT, the reply read on EP1 IN
  interrupt_out.op(kOutReport);
  interrupt_out.report(hello);
  interrupt_out.op(kTicks, {3});
  interrupt_out.op(kIn, {1});
  ok = write(dir, "interrupt_out", interrupt_out) && ok;

  Program set_report = enumerate;  // hidapi's fallback: SET_REPORT on EP0, 64 bytes of data
  set_report.setup(0x21, 0x09, 0x0200, 0, 64);
  set_report.op(kOut, {0, 64});
  set_report.report(hello);
  set_report.op(kIn, {0});
  set_report.op(kTicks, {3});
  set_report.op(kIn, {1});
  ok = write(dir, "set_report", set_report) && ok;

  Program again = interrupt_out;  // suspend, resume, and a new host session
  again.op(kSuspend);
  again.op(kResume);
  again.enumerate();
  again.op(kOutReport);
  again.report(hello);
  again.op(static_cast<Op>(kTicks | kDeferIrq), {3});
  again.op(kIn, {1});
  ok = write(dir, "reset_again", again) && ok;

  Program back_to_back;  // three SETUPs before the handler runs: the last one is answered
  back_to_back.op(kBusReset);
  back_to_back.op(kEnumDone);
  back_to_back.op(static_cast<Op>(kSetups | kDeferIrq),
                  {2, 0x80, 6, 0, 2, 0, 0, 9, 0, 0x80, 6, 0, 3, 0, 0, 255, 0, 0x80, 6, 0, 1, 0, 0, 18, 0});
  back_to_back.op(kIn, {0});
  back_to_back.op(kOut, {0, 0});
  ok = write(dir, "back_to_back", back_to_back) && ok;

  Program odd = enumerate;  // entries the core does not send: global OUT NAK, an unknown status, EP 9
  odd.op(kRawEntry, {0x00, 0x00, 0x02, 0x00});  // PKTSTS 1, no data
  odd.op(kRawEntry, {0x80, 0x00, 0x0E, 0x00});  // PKTSTS 7, 8 bytes
  odd.bytes.insert(odd.bytes.end(), 8, 0xAA);
  odd.op(kRawEntry, {0x09, 0x04, 0x04, 0x00});  // OUT data for EP 9, 64 bytes
  odd.bytes.insert(odd.bytes.end(), 64, 0x55);
  odd.op(kRawEntry, {0x40, 0x00, 0x0C, 0x00});  // SETUP data of 4 bytes
  odd.bytes.insert(odd.bytes.end(), 4, 0x80);
  odd.control_in(0x80, 6, 0x0100, 18, 1);
  ok = write(dir, "odd_entries", odd) && ok;
  return ok ? 0 : 1;
}
