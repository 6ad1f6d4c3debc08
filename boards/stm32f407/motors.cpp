#include "motors.hpp"

#include "pins.hpp"

namespace hmp::board::stm32 {
namespace {

std::uintptr_t ccr(const PwmChannel& c) { return c.timer + (c.channel == 1 ? tim::kCcr1 : tim::kCcr2); }
bool on_apb2(std::uintptr_t timer) { return timer >= 0x40010000; }  // TIM9–11 (and TIM1/8) sit on APB2

}  // namespace

bool motor_board_present() {
  reg(rcc::kAhb1enr) = reg(rcc::kAhb1enr) | rcc::kGpioDEn;
  pin_mode(pins::kMotorBoardPresent, gpio::kModeInput, gpio::kPullDown);
  // The pull-down charges the pin's capacitance within microseconds; wait a few hundred clocks.
  for (int i = 0; i < 200; ++i) asm volatile("nop");
  return pin_read(pins::kMotorBoardPresent);
}

void Motors::force_safe() {
  pin_set(pins::kMotorEnable, false);
  for (const PwmChannel& c : pins::kPwm) reg(ccr(c)) = 0;
}

void Motors::init(const Clocks& clocks) {
  using namespace rcc;
  reg(kAhb1enr) = reg(kAhb1enr) | kGpioAEn | kGpioBEn | kGpioDEn | kGpioEEn;
  reg(kApb2enr) = reg(kApb2enr) | kTim9En | kTim10En | kTim11En;
  reg(kApb1enr) = reg(kApb1enr) | kTim12En | kTim13En | kTim14En;
  // Enable low before it becomes an output, so that it never drives high for an instant.
  pin_set(pins::kMotorEnable, false);
  pin_mode(pins::kMotorEnable, gpio::kModeOutput);
  enabled_ = false;
  for (const Pin& d : pins::kDirection) {
    pin_set(d, false);
    pin_mode(d, gpio::kModeOutput);
  }
  for (int i = 0; i < fw::kMotorCount; ++i) {
    const PwmChannel& c = pins::kPwm[i];
    const std::uint32_t timer_hz = on_apb2(c.timer) ? clocks.apb2_timer_hz : clocks.apb1_timer_hz;
    period_[i] = timer_hz / kPwmHz;  // 8400 or 4200 steps at full speed, 800 on the 16 MHz fallback
    reg(c.timer + tim::kPsc) = 0;
    reg(c.timer + tim::kArr) = period_[i] - 1;
    reg(ccr(c)) = 0;
    const std::uint32_t mode = tim::kOcPwm1 | tim::kOcPreload;  // new duty takes effect at the period's end
    const unsigned shift = c.channel == 1 ? 0 : 8;
    reg(c.timer + tim::kCcmr1) = (reg(c.timer + tim::kCcmr1) & ~(0xFFu << shift)) | mode << shift;
    reg(c.timer + tim::kCcer) = reg(c.timer + tim::kCcer) | (c.channel == 1 ? tim::kCc1e : tim::kCc2e);
    reg(c.timer + tim::kCr1) = tim::kArpe | tim::kCen;
    reg(c.timer + tim::kEgr) = tim::kUg;  // load PSC/ARR now
    pin_mode(c.pin, gpio::kModeAf, gpio::kPullNone, c.alternate);
  }
}

void Motors::set(const float (&duty)[fw::kMotorCount]) {
  if (!enabled_) return;
  for (int i = 0; i < fw::kMotorCount; ++i) {
    float d = duty[i] * static_cast<float>(kSign[i]);
    pin_set(pins::kDirection[i], d < 0.0f);
    d = d < 0.0f ? -d : d;
    if (!(d <= 1.0f)) d = d > 1.0f ? 1.0f : 0.0f;  // NaN → 0
    reg(ccr(pins::kPwm[i])) = static_cast<std::uint32_t>(d * static_cast<float>(period_[i]) + 0.5f);
  }
}

void Motors::enable(bool on) {
  if (!on) {
    enabled_ = false;
    force_safe();
    return;
  }
  enabled_ = true;
  pin_set(pins::kMotorEnable, true);
}

}  // namespace hmp::board::stm32
