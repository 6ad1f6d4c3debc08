#pragma once
// ARM semihosting calls (bkpt 0xAB), the qemu-an386 board's log and exit path (design §13). They only work
// under a debugger or QEMU with `-semihosting-config enable=on`; on bare silicon they would fault.
#include <cstdint>

namespace hmp::board::semihost {

// Writes a NUL-terminated string to the host console (QEMU: stderr).
void write0(const char* text);
void writec(char c);

// The command line the debugger passes (QEMU: the -kernel path followed by the -append text, unless
// -semihosting-config arg=… is given), NUL-terminated in `buffer`. false if there is none or it does
// not fit.
bool get_cmdline(char* buffer, std::uint32_t size);

// Ends the emulation with this process exit code (SYS_EXIT_EXTENDED keeps the code; plain SYS_EXIT
// on 32-bit ARM can only report success or failure, so it is the fallback).
[[noreturn]] void exit(int code);

// Exit codes the image uses, so a test can tell a failed self-check from a crash.
inline constexpr int kExitOk = 0;
inline constexpr int kExitCheckFailed = 1;
inline constexpr int kExitFault = 2;
inline constexpr int kExitAbort = 3;

}  // namespace hmp::board::semihost
