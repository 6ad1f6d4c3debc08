#pragma once
// Test instrumentation (command-line option `trace`, docs in README.md): the host needs every tick's
// output value and every report the core was handed, with its arrival tick, to replay the same reports
// into the simulated board at the same ticks and compare the outputs tick by tick.
//
// The interrupts only append to lock-free rings (a float per tick: a few instructions); the main loop
// writes them out over semihosting between ticks. Under QEMU with -icount a semihosting call costs one
// instruction of virtual time, so tracing does not move any tick. Lines on the semihosting console:
//   y <tick> <bits> …      output of `tick` and the following ticks, each the float's bits as 0x%08x
//   rx <tick> <128 hex>    a report handed to the core while tick() was <tick> (it is handled at tick+1)
#include <cstdint>

#include "firmware/spsc_queue.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::board {

class OutputTrace {
 public:
  static constexpr std::uint32_t kOutputCapacity = 4096;  // > 0.4 s at 10 kHz between two main-loop passes
  static constexpr std::uint32_t kReportCapacity = 32;
  static constexpr std::uint32_t kValuesPerLine = 8;

  // Tick context: the output of the tick being processed (the first call is tick 1).
  void record_output(float value);
  // UART context: a report the core took while its tick counter read `tick`.
  void record_report(std::uint32_t tick, const protocol::Report& report);
  // Main loop: writes what has been recorded. `all`: also a last, partial line of outputs.
  void drain(bool all);
  std::uint32_t dropped() const { return dropped_outputs_ + dropped_reports_; }

 private:
  struct ReportRecord {
    std::uint32_t tick;
    protocol::Report bytes;
  };
  fw::SpscQueue<float, kOutputCapacity> outputs_;
  fw::SpscQueue<ReportRecord, kReportCapacity> reports_;
  std::uint32_t written_ = 0;  // outputs written (main loop): the next one is tick written_ + 1
  std::uint32_t dropped_outputs_ = 0, dropped_reports_ = 0;
};

}  // namespace hmp::board
