// The runtime's exits on the an386 images: through semihosting, so QEMU ends with the code.
#include "semihosting.hpp"

extern "C" {

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
