#pragma once
// The AN386's clock; the Cortex-M system registers come from boards/cortex-m. Peripheral blocks with
// more than a couple of registers (the UART) describe their own layout.
#include <cstdint>

#include "boards/cortex-m/cortex_m.hpp"

namespace hmp::board {

// MPS2 AN386 system clock: the core, SysTick (processor clock source) and the APB peripherals run on it.
inline constexpr std::uint32_t kCoreHz = 25'000'000;

}  // namespace hmp::board
