#pragma once
// The input format of fuzz_otg (fuzz_otg.cpp), shared with its seed writer (otg_seeds.cpp): a program of
// one-byte operations, each followed by its operands. The low four bits of an operation byte pick it;
// bit 6 set leaves the interrupt pending (the driver's handler runs at a later operation, as when the
// main loop has it masked), clear runs the handler until nothing is pending.
#include <cstdint>

namespace hmp::fuzz::otg_ops {

enum Op : std::uint8_t {
  kSetups = 0,     // n (1 + n % 3), then n × 8 SETUP bytes: back-to-back SETUPs and their "SETUP done"
  kSetupData = 1,  // 8 bytes: one SETUP's data entry alone
  kSetupDone = 2,  // a "SETUP done" entry alone
  kIn = 3,         // ep (% 4): the host's IN token (takes the packet waiting there, if any)
  kOut = 4,        // ep (% 4), length (% 72: up to 7 bytes past a 64-byte packet), data: the host's OUT packet
  kRawEntry = 5,   // 4 bytes: any GRXSTSP word (little-endian; bits 21+ dropped), then its BCNT bytes of data
  kBusReset = 6,   // USB reset signalling
  kEnumDone = 7,   // enumeration done (speed found)
  kSuspend = 8,
  kResume = 9,
  kRawFlags = 10,   // 4 bytes: GINTSTS bits raised (the ones the core computes itself excluded)
  kTicks = 11,      // n (1 + n % 32): core ticks, each with the main loop's work (core poll, device poll)
  kCoreStuck = 12,  // the core stops answering resets and flushes while the handler runs once
  kOutReport = 13,  // a whole 64-byte OUT packet on EP1 from the next bytes
};
inline constexpr std::uint8_t kDeferIrq = 0x40;

}  // namespace hmp::fuzz::otg_ops
