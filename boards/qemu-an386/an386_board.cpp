#include "an386_board.hpp"

#include "console.hpp"
#include "registers.hpp"

namespace hmp::board {

An386Board::An386Board(std::uint32_t tick_hz, bool trace, BenchMotors* motors, const fw::DriveParams& drive)
    : tick_hz_(tick_hz),
      tracing_(trace),
      motors_(motors),
      core_(make_seam(this, motors != nullptr), tick_hz, 0, drive) {}

fw::BoardSeam An386Board::make_seam(An386Board* self, bool motors) {
  fw::BoardSeam seam;
  seam.ctx = self;
  seam.output = &An386Board::on_output;
  seam.send = &An386Board::on_send;
  seam.log = &An386Board::on_log;
  seam.subtick = &An386Board::on_subtick;
  if (motors) {
    seam.read_encoders = &An386Board::on_read_encoders;
    seam.motor_output = &An386Board::on_motor_output;
  }
  seam.id = protocol::Board::qemu_an386;
  return seam;
}

void An386Board::on_read_encoders(void* ctx, std::int32_t (&counts)[fw::kMotorCount]) {
  const BenchMotors& m = *static_cast<An386Board*>(ctx)->motors_;
  for (int i = 0; i < fw::kMotorCount; ++i) counts[i] = m.counts[i];
}

void An386Board::on_motor_output(void* ctx, const float (&duty)[fw::kMotorCount]) {
  BenchMotors& m = *static_cast<An386Board*>(ctx)->motors_;
  for (int i = 0; i < fw::kMotorCount; ++i) m.duty[i] = duty[i];
}

bool An386Board::start_link(bool net) {
  LinkSink sink;
  sink.ctx = this;
  sink.has_room = &An386Board::inbox_has_room;
  sink.deliver = &An386Board::deliver;
  // Below the tick (SysTick keeps 0): the link never delays the tick, and a report's arrival tick is
  // read consistently (the tick cannot be half-way through when the link's interrupt runs).
  constexpr std::uint8_t kLinkPriority = 0x80;
  if (net) {
    net_.set_sink(sink);
    if (!net_.start()) return false;
    net_on_ = true;
    nvic::set_priority(kEthernet.irq(), kLinkPriority);
    nvic::enable(kEthernet.irq());
    return true;
  }
  link_.set_sink(sink);
  kUart0.init(kCoreHz, 115200);
  nvic::set_priority(kUart0.rx_irq(), kLinkPriority);
  nvic::set_priority(kUart0.tx_irq(), kLinkPriority);
  nvic::enable(kUart0.rx_irq());
  nvic::enable(kUart0.tx_irq());
  return true;
}

void An386Board::drop_rx() {
  for (;;) {
    kUart0.clear_rx_interrupt();
    (void)kUart0.take_rx_overrun();
    if (!kUart0.rx_full()) return;
    (void)kUart0.read();
    ++rx_lost_;
  }
}

void An386Board::start_tick() {
  // SysTick above everything else (0 = highest); its reset priority is 0 already, set for clarity.
  reg(scb::kShpr3) = reg(scb::kShpr3) & 0x00FFFFFFu;
  timer_.start(kCoreHz, tick_hz_);
}

void An386Board::stop() {
  timer_.stop();
  nvic::disable(kUart0.rx_irq());
  nvic::disable(kUart0.tx_irq());
  nvic::disable(kEthernet.irq());
}

void An386Board::on_tick() {
  core_.on_tick();
  ticks_ = ticks_ + 1;
  if (net_on_) {
    net_.resume_rx();
  } else {
    link_.resume_rx();
  }
}

void An386Board::on_output(void* ctx, float value) {
  auto* self = static_cast<An386Board*>(ctx);
  // No motors on this board: the value is only observable through the trace (and Status.output).
  if (self->tracing_) self->trace_.record_output(value);
}

bool An386Board::on_send(void* ctx, const protocol::Report& report) {
  auto* self = static_cast<An386Board*>(ctx);
  return self->net_on_ ? self->net_.queue_report(report) : self->link_.queue_report(report);
}

void An386Board::on_log(void*, const char* line) { Line().text("log: ").text(line).print(); }

std::uint32_t An386Board::on_subtick(void* ctx) { return static_cast<An386Board*>(ctx)->timer_.subtick(); }

bool An386Board::inbox_has_room(void* ctx) { return static_cast<An386Board*>(ctx)->core_.inbox_has_room(); }

void An386Board::deliver(void* ctx, const protocol::Report& report) {
  auto* self = static_cast<An386Board*>(ctx);
  // Decoding takes ~1,000 instructions and touches no core state: done first, interruptible. Then the core
  // stamps the report with its tick counter and commits it; the trace must name the tick the core saw
  // it arrive in, and it must be the next tick that takes it, so no tick may run between the stamp and
  // the commit (a copy of the entry with interrupts masked).
  const fw::InboxEntry decoded = fw::Core::decode_packet(report);
  std::uint32_t tick = 0;
  const std::uint32_t primask = irq_save();
  const bool taken = self->core_.on_decoded(decoded, &tick);
  irq_restore(primask);
  if (!taken) {
    ++self->inbox_refused_;
    return;
  }
  if (self->tracing_) self->trace_.record_report(tick, report);
}

void An386Board::print_summary() const {
  const NetLink::Counters& n = net_.counters();
  const framing::DecoderCounters& f = link_.frame_counters();
  const Link::Counters& l = link_.counters();
  const fw::Stats& s = core_.stats();
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  if (net_on_) {
    Line().text("net: rx_frames=").u32(n.rx_frames).text(" rx_foreign=").u32(n.rx_foreign)
        .text(" rx_held=").u32(n.rx_held).text(" tx_frames=").u32(n.tx_frames)
        .text(" tx_dropped=").u32(n.tx_dropped).text(" inbox_refused=").u32(inbox_refused_)
        .text(" rx_lost=").u32(rx_lost_).print();
  } else {
    Line().text("link: frames=").u32(f.packets).text(" crc_errors=").u32(f.crc_errors)
        .text(" malformed=").u32(f.malformed).text(" oversized=").u32(f.oversized)
        .text(" wrong_size=").u32(f.wrong_size).text(" rx_bytes=").u32(l.rx_bytes)
        .text(" rx_overruns=").u32(l.rx_overruns).text(" rx_held=").u32(l.rx_held)
        .text(" tx_frames=").u32(l.tx_frames).text(" tx_dropped=").u32(l.tx_dropped)
        .text(" inbox_refused=").u32(inbox_refused_).text(" rx_lost=").u32(rx_lost_).print();
  }
  // clang-format on
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line().text("core: ticks=").u32(ticks_).text(" packets=").u32(s.packets).text(" rejected=").u32(s.rejected)
      .text(" started=").u32(s.started).text(" late=").u32(s.late)
      .text(" stolen=").u32(core_.engine().counters().stolen).text(" inbox_full=").u32(s.inbox_full)
      .text(" tx_dropped=").u32(s.tx_dropped).text(" faults=").hex(core_.faults()).print();
  // clang-format on
  if (tracing_) Line().text("trace: dropped=").u32(trace_.dropped()).print();
}

}  // namespace hmp::board
