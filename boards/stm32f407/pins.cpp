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

void pin_interrupt(Pin pin, bool rising, bool falling) {
  const std::uintptr_t exticr = syscfg::kExticr1 + 4u * (pin.number / 4u);
  const unsigned shift = (pin.number % 4u) * 4u;
  const auto port_index = static_cast<std::uint32_t>((pin.port - gpio::kA) / 0x400);  // A = 0 … E = 4
  reg(exticr) = (reg(exticr) & ~(0xFu << shift)) | port_index << shift;
  const std::uint32_t line = 1u << pin.number;
  if (rising) reg(exti::kRtsr) = reg(exti::kRtsr) | line;
  if (falling) reg(exti::kFtsr) = reg(exti::kFtsr) | line;
  reg(exti::kPr) = line;  // a stale edge from before is not an event
  reg(exti::kImr) = reg(exti::kImr) | line;
}

}  // namespace hmp::board::stm32
