#pragma once
// The STM32F407's peripheral registers this board touches: addresses, offsets and bits as RM0090 (the
// STM32F405/407 reference manual) gives them. Only what the drivers use; each block is a namespace of
// constants over boards/cortex-m's reg(). Bit-band aliases give single-bit writes that an interrupt
// cannot tear (RM0090 §2.3.3).
#include <cstdint>

#include "boards/cortex-m/cortex_m.hpp"

namespace hmp::board::stm32 {

// Bit-band alias of one bit of a peripheral register (0x4000_0000 – 0x400F_FFFF → 0x4200_0000 + …).
inline volatile std::uint32_t& bitband(std::uintptr_t address, unsigned bit) {
  return reg(0x42000000u + (address - 0x40000000u) * 32u + bit * 4u);
}

namespace rcc {
inline constexpr std::uintptr_t kBase = 0x40023800;
inline constexpr std::uintptr_t kCr = kBase + 0x00, kPllcfgr = kBase + 0x04, kCfgr = kBase + 0x08,
                                kAhb1enr = kBase + 0x30, kAhb2enr = kBase + 0x34, kApb1enr = kBase + 0x40,
                                kApb2enr = kBase + 0x44, kCsr = kBase + 0x74;
// CR
inline constexpr std::uint32_t kHsiOn = 1u << 0, kHsiRdy = 1u << 1, kHseOn = 1u << 16, kHseRdy = 1u << 17,
                               kPllOn = 1u << 24, kPllRdy = 1u << 25;
// PLLCFGR: VCO in = src / M (1–2 MHz), VCO = in · N (100–432 MHz), SYSCLK = VCO / P, USB = VCO / Q.
inline constexpr std::uint32_t pllcfgr(std::uint32_t m, std::uint32_t n, std::uint32_t p, std::uint32_t q, bool hse) {
  return m | n << 6 | ((p / 2 - 1) << 16) | (hse ? 1u << 22 : 0u) | q << 24;
}
// CFGR
inline constexpr std::uint32_t kSwMask = 0x3, kSwHsi = 0x0, kSwPll = 0x2;
inline constexpr std::uint32_t kSwsMask = 0x3u << 2, kSwsPll = 0x2u << 2;
inline constexpr std::uint32_t kHpreDiv1 = 0x0u << 4, kPpre1Div4 = 0x5u << 10, kPpre2Div2 = 0x4u << 13;
inline constexpr std::uint32_t kPrescalerMask = (0xFu << 4) | (0x7u << 10) | (0x7u << 13);
// AHB1ENR / AHB2ENR / APB1ENR / APB2ENR
inline constexpr std::uint32_t kGpioAEn = 1u << 0, kGpioBEn = 1u << 1, kGpioCEn = 1u << 2, kGpioDEn = 1u << 3,
                               kGpioEEn = 1u << 4, kCcmEn = 1u << 20;
inline constexpr std::uint32_t kOtgFsEn = 1u << 7;
inline constexpr std::uint32_t kTim2En = 1u << 0, kTim3En = 1u << 1, kTim4En = 1u << 2, kTim5En = 1u << 3,
                               kTim12En = 1u << 6, kTim13En = 1u << 7, kTim14En = 1u << 8, kUsart2En = 1u << 17,
                               kPwrEn = 1u << 28;
inline constexpr std::uint32_t kTim1En = 1u << 0, kTim8En = 1u << 1, kSyscfgEn = 1u << 14, kTim9En = 1u << 16,
                               kTim10En = 1u << 17, kTim11En = 1u << 18;
// CSR: reset causes (sticky until RMVF)
inline constexpr std::uint32_t kLsiOn = 1u << 0, kRmvf = 1u << 24, kIwdgRstf = 1u << 29;
}  // namespace rcc

namespace flash {
inline constexpr std::uintptr_t kAcr = 0x40023C00;
// 168 MHz at 2.7–3.6 V needs 5 wait states (RM0090 table 10); prefetch and both caches hide most of them.
inline constexpr std::uint32_t kLatencyMask = 0x7, kLatency5 = 5, kPrften = 1u << 8, kIcen = 1u << 9, kDcen = 1u << 10;
}  // namespace flash

namespace pwr {
inline constexpr std::uintptr_t kCr = 0x40007000;
inline constexpr std::uint32_t kVosScale1 = 1u << 14;  // regulator scale 1: needed above 144 MHz
}  // namespace pwr

namespace gpio {
inline constexpr std::uintptr_t kA = 0x40020000, kB = 0x40020400, kC = 0x40020800, kD = 0x40020C00, kE = 0x40021000;
inline constexpr std::uintptr_t kModer = 0x00, kOtyper = 0x04, kOspeedr = 0x08, kPupdr = 0x0C, kIdr = 0x10, kOdr = 0x14,
                                kBsrr = 0x18, kAfrl = 0x20, kAfrh = 0x24;
inline constexpr std::uint32_t kModeInput = 0, kModeOutput = 1, kModeAf = 2;
inline constexpr std::uint32_t kPullNone = 0, kPullUp = 1, kPullDown = 2;
inline constexpr std::uint32_t kSpeedHigh = 2;
}  // namespace gpio

// General-purpose and advanced timers share this layout (RM0090 §14, §17, §18, §19).
namespace tim {
inline constexpr std::uintptr_t kTim1 = 0x40010000, kTim2 = 0x40000000, kTim3 = 0x40000400, kTim4 = 0x40000800,
                                kTim5 = 0x40000C00, kTim8 = 0x40010400, kTim9 = 0x40014000, kTim10 = 0x40014400,
                                kTim11 = 0x40014800, kTim12 = 0x40001800, kTim13 = 0x40001C00, kTim14 = 0x40002000;
inline constexpr std::uintptr_t kCr1 = 0x00, kSmcr = 0x08, kDier = 0x0C, kSr = 0x10, kEgr = 0x14, kCcmr1 = 0x18,
                                kCcer = 0x20, kCnt = 0x24, kPsc = 0x28, kArr = 0x2C, kCcr1 = 0x34, kCcr2 = 0x38,
                                kBdtr = 0x44;
inline constexpr std::uint32_t kCen = 1u << 0, kArpe = 1u << 7, kUg = 1u << 0;
inline constexpr std::uint32_t kSmsEncoder3 = 0x3;  // count on both edges of both inputs (×4)
// CCMR1: channel 1 in bits 7:0, channel 2 in 15:8.
inline constexpr std::uint32_t kCcInputTi = 0x1;                           // CCxS = 01: input on its own pin
inline constexpr std::uint32_t kOcPwm1 = 0x6u << 4, kOcPreload = 1u << 3;  // OCxM = 110, OCxPE
inline constexpr std::uint32_t kIcFilter8 = 0x3u << 4;                     // ICxF = 0011: 8 samples at f_CK_INT
inline constexpr std::uint32_t kCc1e = 1u << 0, kCc2e = 1u << 4;
inline constexpr std::uint32_t kMoe = 1u << 15;  // BDTR (TIM1/TIM8 only): main output enable
}  // namespace tim

namespace usart2 {
inline constexpr std::uintptr_t kBase = 0x40004400;
inline constexpr std::uintptr_t kSr = kBase + 0x00, kDr = kBase + 0x04, kBrr = kBase + 0x08, kCr1 = kBase + 0x0C;
inline constexpr std::uint32_t kSrOre = 1u << 3, kSrRxne = 1u << 5, kSrTxe = 1u << 7;
inline constexpr unsigned kCr1Re = 2, kCr1Te = 3, kCr1Rxneie = 5, kCr1Txeie = 7, kCr1Ue = 13;  // bit numbers
inline constexpr unsigned kIrq = 38;
}  // namespace usart2

namespace iwdg {
inline constexpr std::uintptr_t kKr = 0x40003000, kPr = 0x40003004, kRlr = 0x40003008, kSr = 0x4000300C;
inline constexpr std::uint32_t kKeyStart = 0xCCCC, kKeyReload = 0xAAAA, kKeyUnlock = 0x5555;
inline constexpr std::uint32_t kPrDiv32 = 0x3;  // LSI (≈ 32 kHz, 17–47 kHz) / 32
inline constexpr std::uint32_t kSrBusy = 0x3;   // PVU | RVU: an earlier write still being taken
}  // namespace iwdg

namespace exti {
inline constexpr std::uintptr_t kImr = 0x40013C00, kRtsr = 0x40013C08, kFtsr = 0x40013C0C, kPr = 0x40013C14;
inline constexpr unsigned kIrqLine0 = 6, kIrqLine1 = 7, kIrqLine2 = 8, kIrqLine3 = 9, kIrqLines5to9 = 23;
}  // namespace exti

namespace syscfg {
inline constexpr std::uintptr_t kExticr1 = 0x40013808;  // EXTICR1 … 4: four bits per line, the port's number
}  // namespace syscfg

namespace dbgmcu {
inline constexpr std::uintptr_t kApb1Fz = 0xE0042008;
inline constexpr std::uint32_t kIwdgStop = 1u << 12;  // the watchdog pauses while a debugger halts the core
}  // namespace dbgmcu

}  // namespace hmp::board::stm32
