#include "output_trace.hpp"

#include "console.hpp"

namespace hmp::board {

void OutputTrace::record_output(float value) {
  float* slot = outputs_.prepare();
  if (slot == nullptr) {
    ++dropped_outputs_;
    return;
  }
  *slot = value;
  outputs_.commit();
}

void OutputTrace::record_report(std::uint32_t tick, const protocol::Report& report) {
  ReportRecord* slot = reports_.prepare();
  if (slot == nullptr) {
    ++dropped_reports_;
    return;
  }
  slot->tick = tick;
  __builtin_memcpy(slot->bytes, report, protocol::kReportSize);
  reports_.commit();
}

void OutputTrace::drain(bool all) {
  while (const ReportRecord* r = reports_.front()) {
    Line().text("rx ").u32(r->tick).text(" ").hex_bytes(r->bytes, protocol::kReportSize).print();
    reports_.pop();
  }
  // A dropped output would shift every later tick number: stop numbering (the count says why).
  if (dropped_outputs_ != 0) return;
  for (;;) {
    const std::uint32_t ready = outputs_.size();
    if (ready == 0 || (ready < kValuesPerLine && !all)) return;
    const std::uint32_t n = ready < kValuesPerLine ? ready : kValuesPerLine;
    Line line;
    line.text("y ").u32(written_ + 1);
    for (std::uint32_t i = 0; i < n; ++i) {
      std::uint32_t bits;
      __builtin_memcpy(&bits, outputs_.front(), sizeof bits);
      outputs_.pop();
      line.text(" ").hex(bits);
    }
    written_ += n;
    line.print();
  }
}

}  // namespace hmp::board
