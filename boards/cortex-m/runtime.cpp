// The C/C++ runtime start shared by our Cortex-M images (cortex_m.hpp), and the few runtime hooks a
// heap-free, exception-free image still needs. Anything not defined here (malloc's _sbrk, file I/O
// syscalls) is deliberately missing, so code that needs it fails to link.
#include <cstdint>

#include "cortex_m.hpp"

// Symbols every board's linker script defines.
extern "C" {
extern std::uint32_t __data_start[], __data_end[], __data_load[];
extern std::uint32_t __bss_start[], __bss_end[];
using InitFunction = void (*)();
extern InitFunction __preinit_array_start[], __preinit_array_end[];
extern InitFunction __init_array_start[], __init_array_end[];

// Firmware never returns from main() normally, so registered destructors never need to run. Keeping
// these as no-ops stops newlib's atexit tables (and their optional allocation) from being linked.
void* __dso_handle = nullptr;
int atexit(void (*)()) { return 0; }
int __cxa_atexit(void (*)(void*), void*, void*) { return 0; }
int __aeabi_atexit(void*, void (*)(void*), void*) { return 0; }
}

namespace hmp::board {

void init_runtime() {
  for (std::uint32_t *src = __data_load, *dst = __data_start; dst < __data_end;) *dst++ = *src++;
  for (std::uint32_t* dst = __bss_start; dst < __bss_end;) *dst++ = 0;
  for (InitFunction* f = __preinit_array_start; f < __preinit_array_end; ++f) (*f)();
  for (InitFunction* f = __init_array_start; f < __init_array_end; ++f) (*f)();
}

void system_reset() {
  asm volatile("dsb" ::: "memory");
  reg(scb::kAircr) = scb::kAircrVectKey | scb::kAircrSysResetReq;
  asm volatile("dsb" ::: "memory");
  for (;;) {
  }
}

}  // namespace hmp::board
