#include "usb_controller.hpp"

#include "pins.hpp"

namespace hmp::board::stm32 {

void OtgMmio::delay_ms(int ms) {
  // ~4 cycles per iteration at 168 MHz: a lower bound on the wait is all that is needed.
  for (std::int32_t i = 0; i < ms * 42'000; ++i) asm volatile("nop");
}

bool start_usb_controller(UsbController& controller, const Clocks& clocks) {
  if (!clocks.usb_clock_ok) return false;
  reg(rcc::kAhb1enr) = reg(rcc::kAhb1enr) | rcc::kGpioAEn;
  reg(rcc::kAhb2enr) = reg(rcc::kAhb2enr) | rcc::kOtgFsEn;
  pin_mode(pins::kUsbDm, gpio::kModeAf, gpio::kPullNone, 10);
  pin_mode(pins::kUsbDp, gpio::kModeAf, gpio::kPullNone, 10);
  return controller.init();
}

void unique_id_string(char (&out)[25]) {
  constexpr std::uintptr_t kUniqueId = 0x1FFF7A10;
  constexpr char kHex[] = "0123456789ABCDEF";
  for (unsigned i = 0; i < 12; ++i) {
    const std::uint8_t b = reg8(kUniqueId + i);
    out[2 * i] = kHex[b >> 4];
    out[2 * i + 1] = kHex[b & 0xF];
  }
  out[24] = '\0';
}

}  // namespace hmp::board::stm32
