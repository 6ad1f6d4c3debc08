#include "stm32f407_board.hpp"

#include <initializer_list>

#include "pins.hpp"

namespace hmp::board::stm32 {
namespace {

constexpr std::uint8_t kEdgePriority = 0x00, kTickPriority = 0x40, kUartPriority = 0x80;
constexpr unsigned kEncoderIrqs[4] = {exti::kIrqLine0, exti::kIrqLine1, exti::kIrqLine2, exti::kIrqLine3};

// At a tick above 1 kHz the drive is split: pose and QP planned at 1 kHz by the main loop, the rest in the
// tick (firmware/drive.hpp; docs/performance.md "Split drive": 2,384 instructions per 10 kHz tick at most).
fw::DriveParams drive_params() {
  fw::DriveParams p;
  if (fw::kDefaultTickHz > 1000) p.plan_hz = 1000;
  return p;
}

}  // namespace

Stm32Board::Stm32Board(const Clocks& clocks, std::uint8_t board_flags, UsbController* usb)
    : clocks_(clocks),
      usb_controller_(usb),
      core_(make_seam(this, clocks, board_flags), fw::kDefaultTickHz, 0, drive_params()),
      usb_(usb != nullptr ? usb->dcd() : fw::usb::Dcd{}, core_, serial_) {
  motors_.init(clocks_);  // first: the enable pin driven low before anything else can go wrong
}

fw::BoardSeam Stm32Board::make_seam(Stm32Board* self, const Clocks& clocks, std::uint8_t flags) {
  fw::BoardSeam seam;
  seam.ctx = self;
  seam.send = &Stm32Board::on_send;
  seam.subtick = &Stm32Board::on_subtick;
  // At 16 MHz the drive does not fit a tick, and without a motor board there is nothing to drive: the
  // core then runs without it (vibration value only) and the motors stay off (motors_allowed()).
  if (clocks.full_speed() && (flags & protocol::board_no_drive) == 0) {
    seam.read_encoders = &Stm32Board::on_read_encoders;
    seam.motor_output = &Stm32Board::on_motor_output;
  }
  seam.id = protocol::Board::stm32f407;
  seam.flags = flags;
  return seam;
}

void Stm32Board::start() {
  reg(rcc::kAhb1enr) = reg(rcc::kAhb1enr) | rcc::kGpioAEn | rcc::kGpioDEn | rcc::kGpioEEn;
  reg(rcc::kApb1enr) = reg(rcc::kApb1enr) | rcc::kUsart2En;
  reg(rcc::kApb2enr) = reg(rcc::kApb2enr) | rcc::kSyscfgEn;
  for (const Pin& led : {pins::kLedGreen, pins::kLedOrange, pins::kLedRed, pins::kLedBlue}) {
    pin_set(led, false);
    pin_mode(led, gpio::kModeOutput);
  }
  pin_set(pins::kAccelerometerCs, true);
  pin_mode(pins::kAccelerometerCs, gpio::kModeOutput);

  // Emergency stop: pull-up input, interrupt on the rising edge (pressed, or a wire broken).
  pin_mode(pins::kEstop, gpio::kModeInput, gpio::kPullUp);
  pin_interrupt(pins::kEstop, true, false);
  nvic::set_priority(exti::kIrqLines5to9, kEdgePriority);
  nvic::enable(exti::kIrqLines5to9);

  encoders_.init();
  for (unsigned irq : kEncoderIrqs) {
    nvic::set_priority(irq, kEdgePriority);
    nvic::enable(irq);
  }

  Link::Sink sink;
  sink.ctx = this;
  sink.has_room = &Stm32Board::inbox_has_room;
  sink.deliver = &Stm32Board::deliver;
  link_.set_sink(sink);
  pin_mode(pins::kUartTx, gpio::kModeAf, gpio::kPullNone, 7);
  pin_mode(pins::kUartRx, gpio::kModeAf, gpio::kPullUp, 7);
  kUsart2.init(clocks_.usart2_hz, kUartBaud);
  nvic::set_priority(usart2::kIrq, kUartPriority);
  nvic::enable(usart2::kIrq);

  if (usb_controller_ != nullptr) {
    unique_id_string(serial_);
    usb_controller_->attach(usb_);
    nvic::set_priority(otg::kIrq, kUartPriority);
    nvic::enable(otg::kIrq);
    usb_.start();
  }

  reg(scb::kShpr3) = (reg(scb::kShpr3) & 0x00FFFFFFu) | std::uint32_t{kTickPriority} << 24;
  timer_.start(clocks_.core_hz, fw::kDefaultTickHz);
  motors_.enable(motors_allowed());
}

bool Stm32Board::estop_input_active() const { return pin_read(pins::kEstop); }

// The drive needs the full clock to fit its tick (docs/performance.md), and no emergency stop may be
// pending at the pin or unacknowledged in the core.
bool Stm32Board::motors_allowed() const {
  return core_.has_drive() && !estop_input_active() && (core_.faults() & protocol::fault_estop) == 0;
}

void Stm32Board::on_estop_edge() {
  reg(exti::kPr) = 1u << pins::kEstop.number;
  if (!estop_input_active()) return;  // a bounce that is already over
  motors_.enable(false);              // at once, not at the next tick
  core_.on_estop_input();
}

void Stm32Board::on_tick() {
  core_.on_tick();
  ticks_ = ticks_ + 1;
  link_.resume_rx();
  // Level check as well as the edge: a press during start-up, or an edge lost to a bounce, still stops.
  if (estop_input_active() && motors_.enabled()) on_estop_edge();
  if (!motors_.enabled() && motors_allowed()) motors_.enable(true);
}

void Stm32Board::show_state() {
  pin_set(pins::kLedGreen, (ticks_ / 500u) % 2u == 0);  // heartbeat: the tick runs
  pin_set(pins::kLedOrange, !clocks_.usb_clock_ok);
  pin_set(pins::kLedRed, core_.faults() != 0 || !motors_.enabled());
  pin_set(pins::kLedBlue, usb_controller_ != nullptr && usb_.configuration() != 0);
}

void Stm32Board::on_read_encoders(void* ctx, std::int32_t (&counts)[fw::kMotorCount]) {
  static_cast<Stm32Board*>(ctx)->encoders_.read(counts);
}

void Stm32Board::on_motor_output(void* ctx, const float (&duty)[fw::kMotorCount]) {
  static_cast<Stm32Board*>(ctx)->motors_.set(duty);
}

// Main loop: the core's background work (it sends through on_send), then the USB stack's own (arming
// the OUT endpoint again, starting the next IN report) with the USB interrupt masked: the stack runs in
// one context at a time (firmware/usb/device.hpp).
bool Stm32Board::poll() {
  const bool any = core_.poll();
  if (usb_controller_ != nullptr) {
    nvic::disable(otg::kIrq);
    usb_.poll();
    nvic::enable(otg::kIrq);
  }
  return any;
}

bool Stm32Board::on_send(void* ctx, const protocol::Report& report) {
  auto* self = static_cast<Stm32Board*>(ctx);
  if (self->usb_controller_ == nullptr || self->usb_.configuration() == 0) return self->link_.queue_report(report);
  nvic::disable(otg::kIrq);
  const bool queued = self->usb_.queue_report(report);
  nvic::enable(otg::kIrq);
  return queued;
}

std::uint32_t Stm32Board::on_subtick(void* ctx) { return static_cast<Stm32Board*>(ctx)->timer_.subtick(); }

bool Stm32Board::inbox_has_room(void* ctx) { return static_cast<Stm32Board*>(ctx)->core_.inbox_has_room(); }

void Stm32Board::deliver(void* ctx, const protocol::Report& report) {
  static_cast<void>(static_cast<Stm32Board*>(ctx)->core_.on_packet(report));  // room was checked first
}

}  // namespace hmp::board::stm32
