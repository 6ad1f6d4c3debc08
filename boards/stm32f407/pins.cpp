#include "pins.hpp"

namespace hmp::board::stm32 {

void pin_mode(Pin pin, std::uint32_t mode, std::uint32_t pull, std::uint32_t alternate) {
  const unsigned two = pin.number * 2u;
  auto field = [&](std::uintptr_t offset, unsigned shift, std::uint32_t width_mask, std::uint32_t value) {
    reg(pin.port + offset) = (reg(pin.port + offset) & ~(width_mask << shift)) | value << shift;
  };
  // The alternate function first: the pin switches to it only when MODER says so.
  const std::uintptr_t afr = pin.number < 8 ? gpio::kAfrl : gpio::kAfrh;
  field(afr, (pin.number % 8u) * 4u, 0xFu, alternate);
  field(gpio::kOspeedr, two, 0x3u, gpio::kSpeedHigh);
  field(gpio::kPupdr, two, 0x3u, pull);
  field(gpio::kModer, two, 0x3u, mode);
}

}  // namespace hmp::board::stm32
