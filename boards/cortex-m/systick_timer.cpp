#include "systick_timer.hpp"

#include "cortex_m.hpp"

namespace hmp::board {

bool TickTimer::valid_rate(std::uint32_t core_hz, std::uint32_t tick_hz) {
  return tick_hz != 0 && core_hz % tick_hz == 0 && core_hz / tick_hz >= 2 &&
         core_hz / tick_hz - 1 <= systick::kMaxReload;
}

void TickTimer::start(std::uint32_t core_hz, std::uint32_t tick_hz) {
  reload_ = core_hz / tick_hz - 1;
  scale_ = ~std::uint64_t{0} / (reload_ + 1u);  // (2^64 − 1) / period: the same as 2^64 / period here
  reg(systick::kCsr) = 0;
  reg(systick::kRvr) = reload_;
  reg(systick::kCvr) = 0;  // any write clears the counter: the first period is a full one
  reg(systick::kCsr) = systick::kEnable | systick::kTickInt | systick::kCoreClock;
}

void TickTimer::stop() { reg(systick::kCsr) = 0; }

std::uint32_t TickTimer::subtick() const {
  // Counter first, then the pending bit: if the wrap happens in between, the pending bit catches it.
  const std::uint32_t value = reg(systick::kCvr);
  if ((reg(scb::kIcsr) & scb::kIcsrPendStSet) != 0) return 0xFFFFFFFFu;
  const std::uint32_t elapsed = reload_ - value;  // the counter runs down from reload_ to 0
  // elapsed · 2^32 / period as elapsed · scale_ / 2^32, in two 32 × 32 multiplies: this runs with
  // interrupts masked (the boards' deliver), where a 64-bit division would cost a few hundred instructions.
  const auto hi = static_cast<std::uint32_t>(scale_ >> 32), lo = static_cast<std::uint32_t>(scale_);
  return elapsed * hi + static_cast<std::uint32_t>((static_cast<std::uint64_t>(elapsed) * lo) >> 32);
}

}  // namespace hmp::board
