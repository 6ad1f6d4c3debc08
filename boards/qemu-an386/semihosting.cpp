#include "semihosting.hpp"

namespace hmp::board::semihost {
namespace {

// Operation numbers and the exit reason from the ARM semihosting specification.
constexpr std::uint32_t kSysWriteC = 0x03;
constexpr std::uint32_t kSysWrite0 = 0x04;
constexpr std::uint32_t kSysGetCmdline = 0x15;
constexpr std::uint32_t kSysExit = 0x18;
constexpr std::uint32_t kSysExitExtended = 0x20;
constexpr std::uint32_t kAdpStoppedApplicationExit = 0x20026;
constexpr std::uint32_t kAdpStoppedRunTimeErrorUnknown = 0x20023;

std::uint32_t call(std::uint32_t op, const void* arg) {
  register std::uint32_t r0 asm("r0") = op;
  register const void* r1 asm("r1") = arg;
  // "memory": the host reads the buffer r1 points to, so pending stores must land first.
  asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

}  // namespace

void write0(const char* text) { call(kSysWrite0, text); }

void writec(char c) { call(kSysWriteC, &c); }

bool get_cmdline(char* buffer, std::uint32_t size) {
  if (size == 0) return false;
  // Parameter block: buffer address and its size; the host writes the length back into the second word.
  std::uint32_t block[2] = {static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(buffer)), size};
  const bool ok = call(kSysGetCmdline, block) == 0;
  if (!ok) buffer[0] = '\0';
  return ok;
}

void exit(int code) {
  const std::uint32_t block[2] = {kAdpStoppedApplicationExit, static_cast<std::uint32_t>(code)};
  call(kSysExitExtended, block);
  // Only reached if the host lacks SYS_EXIT_EXTENDED: report at least pass/fail.
  call(kSysExit, reinterpret_cast<const void*>(static_cast<std::uintptr_t>(
                     code == 0 ? kAdpStoppedApplicationExit : kAdpStoppedRunTimeErrorUnknown)));
  for (;;) asm volatile("bkpt 0");  // no host at all: stop here for a debugger
}

}  // namespace hmp::board::semihost
