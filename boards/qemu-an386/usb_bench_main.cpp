// Benchmark image (tools/bench/usb-path.sh): instructions the USB device stack (firmware/usb) spends on one
// report each way, counted under QEMU -icount (instruction_counter.hpp) on the Cortex-M4F build:
//  - out: the interrupt OUT completion of a 64-byte Notes report (five notes) already in the stack's
//    buffer — Device::on_xfer_complete(0x01): the copy, Core::on_packet (decode into the inbox) and the
//    endpoint armed again; also the stack's share alone (the same minus Core::on_packet);
//  - in: a device report through Device::queue_report (the copy into the queue, the IN transfer started)
//    and its IN completion (the queue advanced, nothing else waiting).
// The controller is a stub that only records the request: a real driver's FIFO copy (16 words) is not
// counted, as the goal says. Output: `usb out=… out_stack=… on_packet=… queue=… in_complete=…` lines
// (worst of 200 rounds each), after the counter's calibration line.
#include <new>

#include "console.hpp"
#include "firmware/core.hpp"
#include "firmware/usb/device.hpp"
#include "instruction_counter.hpp"
#include "registers.hpp"
#include "semihosting.hpp"
#include "shared/synth/frequency.hpp"

namespace {

namespace p = hmp::protocol;
namespace usb = hmp::fw::usb;
using hmp::board::Line;

// The stub controller: remembers what was armed so the bench can complete it.
std::uint8_t* g_out_buffer = nullptr;
bool g_in_armed = false;

usb::Dcd stub_dcd() {
  usb::Dcd d;
  d.ep_open = [](void*, std::uint8_t, usb::EpType, std::uint16_t) {};
  d.ep_close = [](void*, std::uint8_t) {};
  d.set_address = [](void*, std::uint8_t) {};
  d.ep_xfer = [](void*, std::uint8_t ep, std::uint8_t* buf, std::uint16_t) {
    if (ep == usb::kEpOut) g_out_buffer = buf;
    if (ep == usb::kEpIn) g_in_armed = true;
    return true;
  };
  return d;
}

bool no_send(void*, const p::Report&) { return true; }

alignas(hmp::fw::Core) unsigned char g_core_storage[sizeof(hmp::fw::Core)];
alignas(usb::Device) unsigned char g_device_storage[sizeof(usb::Device)];
hmp::fw::Core* g_core = nullptr;
usb::Device* g_device = nullptr;
p::Report g_notes;
p::Report g_status;

void setup_packet(std::uint8_t type, std::uint8_t req, std::uint16_t value) {
  const std::uint8_t pkt[8] = {type, req, static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8), 0, 0,
                               0,    0};
  g_device->on_setup(pkt);
  g_device->on_xfer_complete(usb::kDirIn, 0);  // the status stage's ZLP
}

void out_complete(void*) { g_device->on_xfer_complete(usb::kEpOut, usb::kReportSize); }
void on_packet_only(void*) { g_core->on_packet(g_notes); }
void queue_one(void*) { g_device->queue_report(g_status); }
void in_complete(void*) { g_device->on_xfer_complete(usb::kEpIn, usb::kReportSize); }

void drain_core() {
  for (int i = 0; i < 8; ++i) {
    g_core->on_tick();
    while (g_core->poll()) {
    }
  }
}

}  // namespace

int main() {
  hmp::fw::BoardSeam seam;
  seam.send = no_send;
  g_core = new (g_core_storage) hmp::fw::Core(seam, 1000);
  g_device = new (g_device_storage) usb::Device(stub_dcd(), *g_core, "BENCH");
  g_device->on_bus_reset();
  setup_packet(0x00, 5, 1);  // SET_ADDRESS 1
  setup_packet(0x00, 9, 1);  // SET_CONFIGURATION 1: endpoints open, OUT armed

  p::Message m = p::make(p::Type::notes, 1);
  m.notes.count = 5;
  m.notes.base_tick = 1000000;  // far ahead: the notes wait in the queue
  for (std::uint8_t i = 0; i < 5; ++i) {
    m.notes.notes[i].offset = static_cast<std::uint8_t>(10 * i);
    m.notes.notes[i].duration_ticks = 100;
    m.notes.notes[i].freq_q20 = hmp::synth::freq_to_q20(120.0 + 10.0 * i);
    m.notes.notes[i].amp_q16 = 30000;
  }
  p::encode(m, g_notes);
  p::encode(p::make(p::Type::sync_reply, 7), g_status);

  hmp::board::InstructionCounter counter;
  counter.start();
  const std::uint32_t primask = hmp::board::irq_save();
  Line().text("calibration: nops=1000 measured=").i32(counter.calibration_check()).print();
  std::int32_t out = 0, on_packet = 0, queue = 0, in = 0;
  for (int round = 0; round < 200; ++round) {
    // OUT: the host's report lands in the armed buffer (the controller's copy, not counted).
    for (std::size_t i = 0; i < usb::kReportSize; ++i) g_out_buffer[i] = g_notes[i];
    const std::int32_t o = counter.measure(&out_complete, nullptr);
    drain_core();  // the ticks take the report out of the inbox (refused once the note queue is full:
                   // the measured part, decoding into the inbox, is the same)
    const std::int32_t op = counter.measure(&on_packet_only, nullptr);
    drain_core();
    if (o > out) out = o;
    if (op > on_packet) on_packet = op;
    // IN: one report queued while the endpoint is idle, then its completion.
    g_in_armed = false;
    const std::int32_t q = counter.measure(&queue_one, nullptr);
    if (!g_in_armed) Line().text("WARNING: the IN transfer did not start").print();
    const std::int32_t c = counter.measure(&in_complete, nullptr);
    if (q > queue) queue = q;
    if (c > in) in = c;
  }
  hmp::board::irq_restore(primask);
  const hmp::fw::usb::DeviceStats& s = g_device->stats();
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line().text("usb out=").i32(out).text(" out_stack=").i32(out - on_packet).text(" on_packet=").i32(on_packet)
      .text(" queue=").i32(queue).text(" in_complete=").i32(in).text(" in=").i32(queue + in)
      .text(" out_reports=").u32(s.out_reports).print();
  // clang-format on
  hmp::board::semihost::exit(0);
}
