#include "instruction_counter.hpp"

#include "registers.hpp"

namespace hmp::board {
namespace {

// CMSDK APB timer 0 (Cortex-M System Design Kit TRM): CTRL bit 0 enables; VALUE counts down to 0 and
// reloads from RELOAD.
constexpr std::uintptr_t kTimer0 = 0x40000000;
constexpr std::uintptr_t kCtrl = kTimer0 + 0x0, kValue = kTimer0 + 0x4, kReload = kTimer0 + 0x8;
constexpr std::int32_t kNsPerCount = static_cast<std::int32_t>(1'000'000'000u / kCoreHz);  // 40
constexpr std::int32_t kInstructionsPerSpin = 4;  // the end loop: adds, ldr, cmp, beq

[[gnu::noinline]] void empty(void*) { asm volatile("" ::: "memory"); }
[[gnu::noinline]] void thousand_nops(void*) { asm volatile(".rept 1000\n\tnop\n\t.endr" ::: "memory"); }

}  // namespace

void InstructionCounter::start() {
  reg(kCtrl) = 0;
  reg(kReload) = 0xFFFFFFFFu;
  reg(kValue) = 0xFFFFFFFFu;
  reg(kCtrl) = 1;
  // The mean of a few runs: the overhead is a constant, blurred by the ±3 of edge detection.
  constexpr std::int32_t kRuns = 16;
  std::int32_t sum = 0;
  for (std::int32_t i = 0; i < kRuns; ++i) sum += raw(&empty, nullptr);
  overhead_ = (sum + kRuns / 2) / kRuns;
}

std::int32_t InstructionCounter::raw(void (*fn)(void* ctx), void* ctx) const {
  const std::uintptr_t value = kValue;
  std::uint32_t before, first, spins, last, seen;
  // Wait for a count edge: the load that sees the new count runs within 3 instructions of it.
  asm volatile(
      "ldr %[before], [%[reg]]\n"
      "1:\n\t"
      "ldr %[first], [%[reg]]\n\t"
      "cmp %[first], %[before]\n\t"
      "beq 1b\n"
      : [before] "=&r"(before), [first] "=&r"(first)
      : [reg] "r"(value)
      : "cc", "memory");
  fn(ctx);
  // Count 4-instruction iterations until the next edge.
  asm volatile(
      "movs %[spins], #0\n\t"
      "ldr %[last], [%[reg]]\n"
      "1:\n\t"
      "adds %[spins], %[spins], #1\n\t"
      "ldr %[seen], [%[reg]]\n\t"
      "cmp %[seen], %[last]\n\t"
      "beq 1b\n"
      : [spins] "=&r"(spins), [last] "=&r"(last), [seen] "=&r"(seen)
      : [reg] "r"(value)
      : "cc", "memory");
  const auto counts = static_cast<std::int32_t>(first - seen);  // the timer counts down
  return counts * kNsPerCount - static_cast<std::int32_t>(spins) * kInstructionsPerSpin;
}

std::int32_t InstructionCounter::measure(void (*fn)(void* ctx), void* ctx) const { return raw(fn, ctx) - overhead_; }

std::int32_t InstructionCounter::calibration_check() const { return measure(&thousand_nops, nullptr); }

}  // namespace hmp::board
