#pragma once
// boards/cortex-m: what every Cortex-M4 board of ours shares — the system control space registers
// (ARMv7-M Architecture Reference Manual, B3: SCB, SysTick, NVIC), PRIMASK sections, the C/C++ runtime
// start, the SysTick tick timer and the framed serial link. Nothing here names a vendor peripheral.
#include <cstdint>

namespace hmp::board {

inline volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}
inline volatile std::uint8_t& reg8(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint8_t*>(address);
}

namespace scb {
inline constexpr std::uintptr_t kIcsr = 0xE000ED04;
inline constexpr std::uintptr_t kVtor = 0xE000ED08;
inline constexpr std::uintptr_t kAircr = 0xE000ED0C;
inline constexpr std::uintptr_t kShpr3 = 0xE000ED20;  // priorities of PendSV (bits 23:16) and SysTick (31:24)
inline constexpr std::uintptr_t kShcsr = 0xE000ED24;
inline constexpr std::uintptr_t kCfsr = 0xE000ED28;  // configurable fault status (MemManage, Bus, Usage)
inline constexpr std::uintptr_t kCpacr = 0xE000ED88;
inline constexpr std::uint32_t kIcsrPendStSet = 1u << 26;  // SysTick exception pending
// AIRCR writes need the key in the top half; SYSRESETREQ asks the chip for a system reset.
inline constexpr std::uint32_t kAircrVectKey = 0x05FAu << 16, kAircrSysResetReq = 1u << 2;
}  // namespace scb

namespace systick {
inline constexpr std::uintptr_t kCsr = 0xE000E010;
inline constexpr std::uintptr_t kRvr = 0xE000E014;  // reload value (24 bits)
inline constexpr std::uintptr_t kCvr = 0xE000E018;  // current value, counts down to 0, then reloads
inline constexpr std::uint32_t kEnable = 1u << 0, kTickInt = 1u << 1, kCoreClock = 1u << 2;
inline constexpr std::uint32_t kMaxReload = 0x00FFFFFFu;
}  // namespace systick

namespace nvic {
inline constexpr std::uintptr_t kIser = 0xE000E100;  // set-enable, one bit per IRQ, 32 per word
inline constexpr std::uintptr_t kIcer = 0xE000E180;  // clear-enable
inline constexpr std::uintptr_t kIspr = 0xE000E200;  // set-pending
inline constexpr std::uintptr_t kIpr = 0xE000E400;   // one priority byte per IRQ
inline void enable(unsigned irq) { reg(kIser + 4 * (irq / 32)) = 1u << (irq % 32); }
inline void disable(unsigned irq) { reg(kIcer + 4 * (irq / 32)) = 1u << (irq % 32); }
inline void set_pending(unsigned irq) { reg(kIspr + 4 * (irq / 32)) = 1u << (irq % 32); }
inline void set_priority(unsigned irq, std::uint8_t priority) { reg8(kIpr + irq) = priority; }
}  // namespace nvic

// PRIMASK: a short section that no interrupt may split (returns the previous state for nesting).
inline std::uint32_t irq_save() {
  std::uint32_t primask;
  asm volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
  return primask;
}
inline void irq_restore(std::uint32_t primask) { asm volatile("msr primask, %0" ::"r"(primask) : "memory"); }

// Copies .data, zeroes .bss and runs the static constructors (-nostartfiles: there is no crt0). Call
// from the reset handler once the FPU is on (constructors may use it).
void init_runtime();

// Asks the chip for a system reset (AIRCR.SYSRESETREQ) and waits for it.
[[noreturn]] void system_reset();

}  // namespace hmp::board
