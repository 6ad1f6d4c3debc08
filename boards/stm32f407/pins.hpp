#pragma once
// The board's pin map (README.md draws it): every pin the firmware drives or reads, in one place. The
// allocation follows design §13 — six timers with an encoder interface (TIM1/2/3/4/5/8) for encoders 1–6,
// pin interrupts for encoders 7–8, TIM9–14 for the eight PWM channels — on pins the STM32F4DISCOVERY
// leaves free or can spare (README.md lists what each one costs on that board).
#include <cstdint>

#include "registers.hpp"

namespace hmp::board::stm32 {

struct Pin {
  std::uintptr_t port;
  std::uint8_t number;
};

// Configures one pin (RM0090 §8.4). Read-modify-write of the port's registers: call before interrupts
// that touch the same port run.
void pin_mode(Pin pin, std::uint32_t mode, std::uint32_t pull = gpio::kPullNone, std::uint32_t alternate = 0);
inline void pin_set(Pin pin, bool high) {
  reg(pin.port + gpio::kBsrr) = high ? 1u << pin.number : 1u << (pin.number + 16);  // atomic: no read
}
inline bool pin_read(Pin pin) { return (reg(pin.port + gpio::kIdr) >> pin.number & 1u) != 0; }
// Routes the pin to its EXTI line (one port per line number: SYSCFG_EXTICR) and unmasks an interrupt on
// the chosen edges (RM0090 §12). Needs the SYSCFG clock; the NVIC side is the caller's.
void pin_interrupt(Pin pin, bool rising, bool falling);

struct PwmChannel {
  Pin pin;
  std::uint8_t alternate;
  std::uintptr_t timer;
  std::uint8_t channel;  // 1 or 2
};
struct EncoderPins {
  Pin a, b;
  std::uint8_t alternate;  // 0: decoded from pin interrupts
  std::uintptr_t timer;    // 0: decoded from pin interrupts
};

namespace pins {
using namespace gpio;
// Motor drivers: PWM magnitude, direction, and one enable for all eight H-bridges (external pull-down:
// the bridges stay off while the pin floats, from power-up until the firmware drives it).
inline constexpr PwmChannel kPwm[8] = {{{kE, 5}, 3, tim::kTim9, 1},   {{kE, 6}, 3, tim::kTim9, 2},
                                       {{kB, 8}, 3, tim::kTim10, 1},  {{kB, 9}, 3, tim::kTim11, 1},
                                       {{kB, 14}, 9, tim::kTim12, 1}, {{kB, 15}, 9, tim::kTim12, 2},
                                       {{kA, 6}, 9, tim::kTim13, 1},  {{kA, 7}, 9, tim::kTim14, 1}};
inline constexpr Pin kDirection[8] = {{kE, 7}, {kE, 8}, {kE, 10}, {kE, 12}, {kE, 13}, {kE, 14}, {kE, 15}, {kB, 12}};
inline constexpr Pin kMotorEnable = {kD, 7};
// The motor board ties this pin to 3.3 V; with the internal pull-down it reads low when no motor board
// is plugged in, and the firmware then runs without the drive (HelloReply flag no_drive).
inline constexpr Pin kMotorBoardPresent = {kD, 8};
// Encoders (A, B): quadrature, 2048 counts per pulley turn after ×4 decoding.
inline constexpr EncoderPins kEncoder[8] = {{{kE, 9}, {kE, 11}, 1, tim::kTim1}, {{kA, 15}, {kB, 3}, 1, tim::kTim2},
                                            {{kB, 4}, {kB, 5}, 2, tim::kTim3},  {{kB, 6}, {kB, 7}, 2, tim::kTim4},
                                            {{kA, 0}, {kA, 1}, 2, tim::kTim5},  {{kC, 6}, {kC, 7}, 3, tim::kTim8},
                                            {{kD, 0}, {kD, 1}, 0, 0},           {{kD, 2}, {kD, 3}, 0, 0}};
// Emergency stop: a normally-closed switch to ground; the pin reads high when pressed or when a wire
// breaks (internal pull-up), and either stops the motors.
inline constexpr Pin kEstop = {kD, 6};
// Host links.
inline constexpr Pin kUartTx = {kA, 2}, kUartRx = {kA, 3};  // USART2, AF7
inline constexpr Pin kUsbDm = {kA, 11}, kUsbDp = {kA, 12};  // OTG FS, AF10 (VBUS on PA9 is not needed)
// STM32F4DISCOVERY extras: its four LEDs, and the accelerometer's chip select held high so that the
// accelerometer keeps off PA6 (PWM 7).
inline constexpr Pin kLedGreen = {kD, 12}, kLedOrange = {kD, 13}, kLedRed = {kD, 14}, kLedBlue = {kD, 15};
inline constexpr Pin kAccelerometerCs = {kE, 3};
}  // namespace pins

}  // namespace hmp::board::stm32
