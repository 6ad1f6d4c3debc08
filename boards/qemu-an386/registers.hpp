#pragma once
// Memory-mapped registers the qemu-an386 board code touches: the Cortex-M4 system control space
// (ARMv7-M Architecture Reference Manual, B3) and the AN386 clock. Peripheral blocks with more than a
// couple of registers (the UART) describe their own layout.
#include <cstdint>

namespace hmp::board {

inline volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}
inline volatile std::uint8_t& reg8(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint8_t*>(address);
}

// MPS2 AN386 system clock: the core, SysTick (processor clock source) and the APB peripherals run on it.
inline constexpr std::uint32_t kCoreHz = 25'000'000;

namespace scb {
inline constexpr std::uintptr_t kIcsr = 0xE000ED04;
inline constexpr std::uintptr_t kVtor = 0xE000ED08;
inline constexpr std::uintptr_t kShpr3 = 0xE000ED20;  // priorities of PendSV (bits 23:16) and SysTick (31:24)
inline constexpr std::uintptr_t kShcsr = 0xE000ED24;
inline constexpr std::uintptr_t kCpacr = 0xE000ED88;
inline constexpr std::uint32_t kIcsrPendStSet = 1u << 26;  // SysTick exception pending
}  // namespace scb

namespace systick {
inline constexpr std::uintptr_t kCsr = 0xE000E010;
inline constexpr std::uintptr_t kRvr = 0xE000E014;  // reload value (24 bits)
inline constexpr std::uintptr_t kCvr = 0xE000E018;  // current value, counts down to 0, then reloads
inline constexpr std::uint32_t kEnable = 1u << 0, kTickInt = 1u << 1, kCoreClock = 1u << 2;
inline constexpr std::uint32_t kMaxReload = 0x00FFFFFFu;
}  // namespace systick

namespace nvic {
inline constexpr std::uintptr_t kIser = 0xE000E100;  // set-enable, one bit per IRQ (IRQs 0–31 in word 0)
inline constexpr std::uintptr_t kIcer = 0xE000E180;  // clear-enable
inline constexpr std::uintptr_t kIspr = 0xE000E200;  // set-pending
inline constexpr std::uintptr_t kIpr = 0xE000E400;   // one priority byte per IRQ
inline void enable(unsigned irq) { reg(kIser) = 1u << irq; }
inline void disable(unsigned irq) { reg(kIcer) = 1u << irq; }
inline void set_pending(unsigned irq) { reg(kIspr) = 1u << irq; }
inline void set_priority(unsigned irq, std::uint8_t priority) { reg8(kIpr + irq) = priority; }
}  // namespace nvic

// PRIMASK: a short section that no interrupt may split (returns the previous state for nesting).
inline std::uint32_t irq_save() {
  std::uint32_t primask;
  asm volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
  return primask;
}
inline void irq_restore(std::uint32_t primask) { asm volatile("msr primask, %0" ::"r"(primask) : "memory"); }

}  // namespace hmp::board
