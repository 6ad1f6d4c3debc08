#pragma once
// Counts the instructions a function executes, under QEMU with `-icount shift=0` (every instruction
// advances virtual time by exactly 1 ns; nothing else does). Virtual time is read from the CMSDK APB
// timer 0 (0x40000000, 32-bit, counting down at the 25 MHz APB clock: one count per 40 instructions).
// To resolve single instructions, the measurement starts right at a count edge (a 3-instruction polling
// loop waits for one) and, after the function, counts 4-instruction polling iterations up to the next
// edge: instructions = 40 × counts − 4 × iterations − (the same for an empty function). Accurate to a
// few instructions; calibrate() checks it against a run of 1000 `nop`s. Interrupts must be masked by
// the caller during measure(). Meaningless on real hardware or without -icount.
#include <cstdint>

namespace hmp::board {

class InstructionCounter {
 public:
  void start();  // timer 0 free-running; then measures an empty function for the fixed overhead
  std::int32_t measure(void (*fn)(void* ctx), void* ctx) const;
  // Instructions measured for a function of exactly 1000 nops (should print 1000).
  std::int32_t calibration_check() const;

 private:
  std::int32_t raw(void (*fn)(void* ctx), void* ctx) const;
  std::int32_t overhead_ = 0;
};

}  // namespace hmp::board
