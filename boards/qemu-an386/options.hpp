#pragma once
// Run-time options of the qemu-an386 images, read from the semihosting command line (QEMU: the words of
// `-append "…"`; the first word QEMU passes is the image path and is skipped). README.md lists them.
#include <cstdint>

#include "shared/synth/tick_rate.hpp"

namespace hmp::board {

struct Options {
#ifdef HMP_TICK_HZ
  std::uint32_t tick_hz = HMP_TICK_HZ;  // hz=N: tick rate (must divide 25 MHz; see TickTimer)
#else
  std::uint32_t tick_hz = synth::kNominalTickHz;
#endif
  bool trace = false;                 // trace: per-tick outputs and received reports on semihosting
  std::uint32_t exit_idle_ms = 0;     // exit-idle-ms=N: exit 0 after N ms without a received byte (0: never)
  std::uint32_t listen_after_ms = 0;  // listen-after-ms=N: the link drops what it receives for N ms
  bool net = false;                   // link=net: the host link is the Ethernet controller (link=uart: UART0)
  const char* error = nullptr;        // the first word that could not be used (then the rest is unread)
};

// Parses a command line (modified in place: words are cut out with NULs).
Options parse_options(char* cmdline);

// What an image's main() does first: reads the semihosting command line and parses it; on a bad word
// it prints "bad option: WORD (…)" and the image should exit with kExitBadOption.
Options read_options();
inline constexpr int kExitBadOption = 4;

}  // namespace hmp::board
