#pragma once
// The chip's USB OTG FS controller as the USB stack's device controller: the driver (otg_fs.hpp) on
// memory-mapped registers, and the bring-up (clock, pins) before it. The 48 MHz USB clock must come from
// the crystal (clocks.hpp); without it USB stays off and the board says `no_usb`.
#include <cstdint>

#include "clocks.hpp"
#include "boards/cortex-m/cortex_m.hpp"
#include "otg_fs.hpp"

namespace hmp::board::stm32 {

struct OtgMmio {
  std::uint32_t read(std::uint32_t offset) { return reg(otg::kBase + offset); }
  void write(std::uint32_t offset, std::uint32_t value) { reg(otg::kBase + offset) = value; }
  void delay_ms(int ms);
};

using UsbController = otg::OtgFs<OtgMmio>;

// Clock and pins (PA11/PA12, AF10), then the driver's init(). false: no crystal clock, or the core did
// not answer; USB then stays off.
bool start_usb_controller(UsbController& controller, const Clocks& clocks);

// The serial number string: the chip's 96-bit unique ID (RM0090 §39.1, at 0x1FFF7A10) in hex.
void unique_id_string(char (&out)[25]);

}  // namespace hmp::board::stm32
