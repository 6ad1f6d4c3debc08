// Reset path and vector table of the qemu-an386 image: enable the FPU, start the C++ runtime
// (boards/cortex-m), run main(), and report faults through semihosting.
#include <cstdint>

#include "boards/cortex-m/vector_table.hpp"
#include "registers.hpp"
#include "semihosting.hpp"

// Symbols from an386.ld.
extern "C" {
extern std::uint32_t __stack_top[];

int main();
void Reset_Handler();
void Default_Handler();
void NMI_Handler();
void HardFault_Handler();
void MemManage_Handler();
void BusFault_Handler();
void UsageFault_Handler();
// Weak: the firmware or the demo main defines the ones it uses.
void SVC_Handler() __attribute__((weak, alias("Default_Handler")));
void DebugMon_Handler() __attribute__((weak, alias("Default_Handler")));
void PendSV_Handler() __attribute__((weak, alias("Default_Handler")));
void SysTick_Handler() __attribute__((weak, alias("Default_Handler")));
void UART0_RX_Handler() __attribute__((weak, alias("Default_Handler")));
void UART0_TX_Handler() __attribute__((weak, alias("Default_Handler")));
void ETHERNET_Handler() __attribute__((weak, alias("Default_Handler")));
}

namespace {

namespace ex = hmp::board::exception;
// AN386 wires 32 external interrupts (QEMU: num-irq 32). UART0 RX/TX are IRQ 0/1, the Ethernet controller IRQ 13.
using VectorTable = hmp::board::VectorTable<32>;

constexpr VectorTable make_vector_table() {
  VectorTable t{__stack_top, {}, {}};
  t.system[ex::kReset] = Reset_Handler;
  t.system[ex::kNmi] = NMI_Handler;
  t.system[ex::kHardFault] = HardFault_Handler;
  t.system[ex::kMemManage] = MemManage_Handler;
  t.system[ex::kBusFault] = BusFault_Handler;
  t.system[ex::kUsageFault] = UsageFault_Handler;
  t.system[ex::kSvc] = SVC_Handler;
  t.system[ex::kDebugMon] = DebugMon_Handler;
  t.system[ex::kPendSv] = PendSV_Handler;
  t.system[ex::kSysTick] = SysTick_Handler;
  for (auto& h : t.irq) h = Default_Handler;
  t.irq[0] = UART0_RX_Handler;
  t.irq[1] = UART0_TX_Handler;
  t.irq[13] = ETHERNET_Handler;
  return t;
}

[[gnu::section(".isr_vector"), gnu::used]] constinit const VectorTable g_vectors = make_vector_table();

using hmp::board::reg;
namespace scb = hmp::board::scb;
constexpr std::uint32_t kShcsrFaultsEnabled = (1u << 16) | (1u << 17) | (1u << 18);  // Mem, Bus, Usage

// Everything after the FPU is on: compiled code here may use floating-point registers freely.
[[gnu::noinline, noreturn]] void start_runtime() {
  hmp::board::init_runtime();
  hmp::board::semihost::exit(main());
}

[[noreturn]] void fault(const char* what) {
  hmp::board::semihost::write0("FAULT: ");
  hmp::board::semihost::write0(what);
  hmp::board::semihost::write0("\n");
  hmp::board::semihost::exit(hmp::board::semihost::kExitFault);
}

}  // namespace

extern "C" {

// Integer-only until CPACR grants access to CP10/CP11: any FP instruction before that would fault.
void Reset_Handler() {
  hmp::board::enable_fpu_and_vectors(&g_vectors);
  // Separate MemManage/BusFault/UsageFault handlers give better messages than an escalated HardFault.
  reg(scb::kShcsr) = reg(scb::kShcsr) | kShcsrFaultsEnabled;
  asm volatile("dsb\n\tisb" ::: "memory");
  start_runtime();
}

void NMI_Handler() { fault("NMI"); }
void HardFault_Handler() { fault("HardFault"); }
void MemManage_Handler() { fault("MemManage"); }
void BusFault_Handler() { fault("BusFault"); }
void UsageFault_Handler() { fault("UsageFault"); }
void Default_Handler() { fault("unexpected interrupt"); }

}  // extern "C"
