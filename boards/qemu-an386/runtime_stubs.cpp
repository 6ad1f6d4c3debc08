// The few C/C++ runtime hooks a heap-free, exception-free image still needs. Anything not defined here
// (malloc's _sbrk, file I/O syscalls) is deliberately missing, so code that needs it fails to link.
#include <cstdint>

#include "semihosting.hpp"

extern "C" {

// Firmware never returns from main() normally, so registered destructors never need to run. Keeping
// these as no-ops stops newlib's atexit tables (and their optional allocation) from being linked.
void* __dso_handle = nullptr;
int atexit(void (*)()) { return 0; }
int __cxa_atexit(void (*)(void*), void*, void*) { return 0; }
int __aeabi_atexit(void*, void (*)(void*), void*) { return 0; }

[[noreturn]] void abort() {
  hmp::board::semihost::write0("ABORT\n");
  hmp::board::semihost::exit(hmp::board::semihost::kExitAbort);
}

[[noreturn]] void _exit(int code) { hmp::board::semihost::exit(code); }

// A call through a pure virtual slot is a bug: stop loudly instead of pulling in libsupc++'s version
// (which goes through std::terminate and the exception machinery).
[[noreturn]] void __cxa_pure_virtual() {
  hmp::board::semihost::write0("pure virtual call\n");
  hmp::board::semihost::exit(hmp::board::semihost::kExitAbort);
}

}  // extern "C"
