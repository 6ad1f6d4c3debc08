#pragma once
// The Cortex-M vector table (ARMv7-M ARM B1.5.3): the initial stack pointer, the 15 system exceptions
// (Reset … SysTick, exception numbers 1 … 15; 7–10 and 13 reserved) and the chip's external interrupts.
// Each board's startup.cpp builds one at compile time and places it in `.isr_vector`.
#include <cstdint>

#include "cortex_m.hpp"

namespace hmp::board {

using Handler = void (*)();

template <unsigned kExternalIrqs>
struct VectorTable {
  const void* initial_sp;
  Handler system[15];
  Handler irq[kExternalIrqs];
};

// Slots of VectorTable::system.
namespace exception {
inline constexpr unsigned kReset = 0, kNmi = 1, kHardFault = 2, kMemManage = 3, kBusFault = 4, kUsageFault = 5,
                          kSvc = 10, kDebugMon = 11, kPendSv = 13, kSysTick = 14;
}

// The reset handler's first steps, before any floating-point instruction (they would fault until CPACR
// grants CP10/CP11): point VTOR at our table and turn the FPU on.
inline void enable_fpu_and_vectors(const void* table) {
  constexpr std::uint32_t kCpacrCp10Cp11Full = 0xFu << 20;
  reg(scb::kVtor) = reinterpret_cast<std::uintptr_t>(table);
  reg(scb::kCpacr) = reg(scb::kCpacr) | kCpacrCp10Cp11Full;
  asm volatile("dsb\n\tisb" ::: "memory");
}

}  // namespace hmp::board
