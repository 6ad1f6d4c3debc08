#include "watchdog.hpp"

#include "registers.hpp"

namespace hmp::board::stm32 {

void Watchdog::start() {
  reg(dbgmcu::kApb1Fz) = reg(dbgmcu::kApb1Fz) | dbgmcu::kIwdgStop;  // no resets while a debugger halts us
  reg(iwdg::kKr) = iwdg::kKeyStart;                                 // starts the LSI too
  reg(iwdg::kKr) = iwdg::kKeyUnlock;
  reg(iwdg::kPr) = iwdg::kPrDiv32;                    // ≈ 1 kHz
  reg(iwdg::kRlr) = kTimeoutMs * 32'000 / 32 / 1000;  // at the nominal 32 kHz
  // The new values reach the LSI domain a few LSI cycles later; bounded, an emulator may never say so.
  for (std::uint32_t i = 0; i < 100'000 && (reg(iwdg::kSr) & iwdg::kSrBusy) != 0; ++i) {
  }
  reg(iwdg::kKr) = iwdg::kKeyReload;
}

void Watchdog::feed() { reg(iwdg::kKr) = iwdg::kKeyReload; }

bool Watchdog::take_reset_flag() {
  const bool was = (reg(rcc::kCsr) & rcc::kIwdgRstf) != 0;
  reg(rcc::kCsr) = reg(rcc::kCsr) | rcc::kRmvf;
  return was;
}

}  // namespace hmp::board::stm32
