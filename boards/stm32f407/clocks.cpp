#include "clocks.hpp"

#include "registers.hpp"

namespace hmp::board::stm32 {
namespace {

// Loop bounds, in polls of a register (each poll is at least a few clocks at 16 MHz, so these are upper
// bounds of several milliseconds; the crystal needs ~2 ms, the PLL ~0.1 ms, a clock switch a few cycles).
constexpr std::uint32_t kHsiPolls = 10'000, kHsePolls = 100'000, kPllPolls = 50'000, kSwitchPolls = 10'000;

bool wait_for(std::uintptr_t address, std::uint32_t mask, std::uint32_t value, std::uint32_t polls) {
  for (std::uint32_t i = 0; i < polls; ++i) {
    if ((reg(address) & mask) == value) return true;
  }
  return false;
}

Clocks at_168mhz(ClockSource source) {
  Clocks c;
  c.source = source;
  c.core_hz = 168'000'000;
  c.apb1_timer_hz = 84'000'000;  // APB1 = 42 MHz; its timers run at twice a divided APB clock
  c.apb2_timer_hz = 168'000'000;
  c.usart2_hz = 42'000'000;
  c.usb_clock_ok = source == ClockSource::hse_pll;
  return c;
}

}  // namespace

Clocks setup_clocks() {
  using namespace rcc;
  reg(kApb1enr) = reg(kApb1enr) | kPwrEn;
  reg(pwr::kCr) = reg(pwr::kCr) | pwr::kVosScale1;

  reg(kCr) = reg(kCr) | kHsiOn;
  if (!wait_for(kCr, kHsiRdy, kHsiRdy, kHsiPolls)) return at_168mhz(ClockSource::rcc_absent);

  reg(kCr) = reg(kCr) | kHseOn;
  const bool hse = wait_for(kCr, kHseRdy, kHseRdy, kHsePolls);
  if (!hse) reg(kCr) = reg(kCr) & ~kHseOn;  // a crystal that does not oscillate is left off

  // VCO input 1 MHz (8 MHz / 8 or 16 MHz / 16), VCO 336 MHz, core 168 MHz, USB 48 MHz.
  reg(kPllcfgr) = hse ? pllcfgr(8, 336, 2, 7, true) : pllcfgr(16, 336, 2, 7, false);
  reg(kCr) = reg(kCr) | kPllOn;
  if (!wait_for(kCr, kPllRdy, kPllRdy, kPllPolls)) {
    reg(kCr) = reg(kCr) & ~kPllOn;
    return Clocks{};  // HSI at 16 MHz, the reset state: no wait states or prescalers to undo
  }

  // Wait states before the faster clock, and read back: a flash that has not taken them would fail.
  reg(flash::kAcr) = flash::kLatency5 | flash::kPrften | flash::kIcen | flash::kDcen;
  if ((reg(flash::kAcr) & flash::kLatencyMask) != flash::kLatency5) {
    reg(kCr) = reg(kCr) & ~kPllOn;
    return Clocks{};
  }
  reg(kCfgr) = (reg(kCfgr) & ~kPrescalerMask) | kHpreDiv1 | kPpre1Div4 | kPpre2Div2;
  reg(kCfgr) = (reg(kCfgr) & ~kSwMask) | kSwPll;
  if (!wait_for(kCfgr, kSwsMask, kSwsPll, kSwitchPolls)) {
    reg(kCfgr) = (reg(kCfgr) & ~kSwMask) | kSwHsi;
    return Clocks{};
  }
  return at_168mhz(hse ? ClockSource::hse_pll : ClockSource::hsi_pll);
}

const char* clock_source_name(ClockSource source) {
  switch (source) {
    case ClockSource::hse_pll: return "crystal PLL 168 MHz";
    case ClockSource::hsi_pll: return "internal-oscillator PLL 168 MHz (crystal did not start)";
    case ClockSource::hsi: return "internal oscillator 16 MHz (PLL did not lock)";
    case ClockSource::rcc_absent: return "no RCC answering (emulator): assumed 168 MHz";
  }
  return "?";
}

}  // namespace hmp::board::stm32
