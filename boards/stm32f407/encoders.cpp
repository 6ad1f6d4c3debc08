#include "encoders.hpp"

#include <initializer_list>

#include "pins.hpp"

namespace hmp::board::stm32 {
namespace {

constexpr int kTimerEncoders = 6;

std::uint8_t pin_state(const EncoderPins& e) {
  return static_cast<std::uint8_t>((pin_read(e.a) ? 2u : 0u) | (pin_read(e.b) ? 1u : 0u));
}

}  // namespace

void Encoders::init() {
  using namespace rcc;
  reg(kAhb1enr) = reg(kAhb1enr) | kGpioAEn | kGpioBEn | kGpioCEn | kGpioDEn | kGpioEEn;
  reg(kApb2enr) = reg(kApb2enr) | kTim1En | kTim8En | kSyscfgEn;
  reg(kApb1enr) = reg(kApb1enr) | kTim2En | kTim3En | kTim4En | kTim5En;
  for (int i = 0; i < kTimerEncoders; ++i) {
    const EncoderPins& e = pins::kEncoder[i];
    const std::uintptr_t t = e.timer;
    reg(t + tim::kCr1) = 0;
    const std::uint32_t input = tim::kCcInputTi | tim::kIcFilter8;
    reg(t + tim::kCcmr1) = input | input << 8;
    reg(t + tim::kCcer) = 0;  // both inputs non-inverted
    reg(t + tim::kSmcr) = tim::kSmsEncoder3;
    reg(t + tim::kArr) = 0xFFFFFFFFu;  // 16-bit timers keep the low half
    reg(t + tim::kCnt) = 0;
    reg(t + tim::kCr1) = tim::kCen;
    pin_mode(e.a, gpio::kModeAf, gpio::kPullUp, e.alternate);
    pin_mode(e.b, gpio::kModeAf, gpio::kPullUp, e.alternate);
    last_hw_[i] = 0;
  }
  // Encoders 7 and 8: inputs with pull-ups, an interrupt on both edges of each line.
  for (int k = 0; k < 2; ++k) {
    const EncoderPins& e = pins::kEncoder[kTimerEncoders + k];
    for (const Pin& p : {e.a, e.b}) {
      pin_mode(p, gpio::kModeInput, gpio::kPullUp);
      pin_interrupt(p, true, true);
    }
    soft_state_[k] = pin_state(e);
    soft_count_[k] = 0;
  }
}

void Encoders::on_pin_edge(int encoder) {
  const int k = encoder - kTimerEncoders;
  const std::uint8_t now = pin_state(pins::kEncoder[encoder]);
  const std::int8_t s = step(soft_state_[k], now);
  soft_state_[k] = now;
  if (s == kInvalid) {
    missed_ = missed_ + 1;
  } else {
    soft_count_[k] = soft_count_[k] + s;
  }
}

void Encoders::read(std::int32_t (&counts)[fw::kMotorCount]) {
  for (int i = 0; i < kTimerEncoders; ++i) {
    const std::uint32_t now = reg(pins::kEncoder[i].timer + tim::kCnt);
    // Signed difference in the timer's own width: 32-bit TIM2/TIM5 and 16-bit others alike.
    const bool wide = pins::kEncoder[i].timer == tim::kTim2 || pins::kEncoder[i].timer == tim::kTim5;
    const std::int32_t delta = wide ? static_cast<std::int32_t>(now - last_hw_[i])
                                    : static_cast<std::int16_t>(static_cast<std::uint16_t>(now - last_hw_[i]));
    last_hw_[i] = now;
    count_[i] = static_cast<std::int32_t>(static_cast<std::uint32_t>(count_[i]) + static_cast<std::uint32_t>(delta));
  }
  // The pin-interrupt counts are written above the tick's priority; a 32-bit read is atomic.
  count_[6] = soft_count_[0];
  count_[7] = soft_count_[1];
  for (int i = 0; i < fw::kMotorCount; ++i) counts[i] = count_[i];
}

}  // namespace hmp::board::stm32
