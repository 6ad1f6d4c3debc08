// Reset path and vector table of the stm32f407 image. Every fault and every interrupt nobody expects
// ends the same way: motors off (register writes only) and a system reset, which starts the firmware
// again from the safe state. There is no console to print to on this board (USART2 carries the framed
// protocol), so nothing is printed; the watchdog reset flag reaches the host in HelloReply.
#include <cstdint>

#include "boards/cortex-m/vector_table.hpp"
#include "motors.hpp"

extern "C" {
extern std::uint32_t __stack_top[], __ccm_start[], __ccm_end[];
int main();
void Reset_Handler();
void Fault_Handler();
// Weak: main.cpp defines the ones the firmware uses; the rest reset the chip.
void SysTick_Handler() __attribute__((weak, alias("Fault_Handler")));
void USART2_IRQHandler() __attribute__((weak, alias("Fault_Handler")));
void EXTI0_IRQHandler() __attribute__((weak, alias("Fault_Handler")));
void EXTI1_IRQHandler() __attribute__((weak, alias("Fault_Handler")));
void EXTI2_IRQHandler() __attribute__((weak, alias("Fault_Handler")));
void EXTI3_IRQHandler() __attribute__((weak, alias("Fault_Handler")));
void EXTI9_5_IRQHandler() __attribute__((weak, alias("Fault_Handler")));
void OTG_FS_IRQHandler() __attribute__((weak, alias("Fault_Handler")));
}

namespace {

namespace board = hmp::board;
namespace ex = board::exception;

// The STM32F405/407 have 82 external interrupts (RM0090 table 61, positions 0–81).
using VectorTable = board::VectorTable<82>;
constexpr unsigned kIrqExti0 = 6, kIrqExti1 = 7, kIrqExti2 = 8, kIrqExti3 = 9, kIrqExti9_5 = 23, kIrqUsart2 = 38,
                   kIrqOtgFs = 67;

constexpr VectorTable make_vector_table() {
  VectorTable t{__stack_top, {}, {}};
  t.system[ex::kReset] = Reset_Handler;
  for (unsigned i = ex::kNmi; i <= ex::kUsageFault; ++i) t.system[i] = Fault_Handler;
  t.system[ex::kSvc] = Fault_Handler;  // never used
  t.system[ex::kDebugMon] = Fault_Handler;
  t.system[ex::kPendSv] = Fault_Handler;  // never used
  t.system[ex::kSysTick] = SysTick_Handler;
  for (auto& h : t.irq) h = Fault_Handler;
  t.irq[kIrqExti0] = EXTI0_IRQHandler;
  t.irq[kIrqExti1] = EXTI1_IRQHandler;
  t.irq[kIrqExti2] = EXTI2_IRQHandler;
  t.irq[kIrqExti3] = EXTI3_IRQHandler;
  t.irq[kIrqExti9_5] = EXTI9_5_IRQHandler;
  t.irq[kIrqUsart2] = USART2_IRQHandler;
  t.irq[kIrqOtgFs] = OTG_FS_IRQHandler;
  return t;
}

[[gnu::section(".isr_vector"), gnu::used]] constinit const VectorTable g_vectors = make_vector_table();

[[gnu::noinline, noreturn]] void start_runtime() {
  for (std::uint32_t* p = __ccm_start; p < __ccm_end; ++p) *p = 0;
  board::init_runtime();
  main();
  board::stm32::Motors::force_safe();  // main() does not return; if it ever did, start again
  board::system_reset();
}

}  // namespace

extern "C" {

// Integer-only until the FPU is on: any FP instruction before that would fault.
void Reset_Handler() {
  board::enable_fpu_and_vectors(&g_vectors);
  start_runtime();
}

void Fault_Handler() {
  board::stm32::Motors::force_safe();
  board::system_reset();
}

// The C runtime's exits: the same safe reset.
[[noreturn]] void abort() {
  board::stm32::Motors::force_safe();
  board::system_reset();
}
[[noreturn]] void _exit(int) { abort(); }
[[noreturn]] void __cxa_pure_virtual() { abort(); }

}  // extern "C"
