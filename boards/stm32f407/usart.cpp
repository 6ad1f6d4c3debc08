#include "usart.hpp"

namespace hmp::board::stm32 {

void Usart2::init(std::uint32_t pclk_hz, std::uint32_t baud) const {
  using namespace usart2;
  reg(kCr1) = 0;
  // Oversampling by 16: BRR holds pclk / baud as 12.4 fixed point, which is just the rounded quotient.
  reg(kBrr) = (pclk_hz + baud / 2) / baud;
  reg(kCr1) = 1u << kCr1Ue | 1u << kCr1Te | 1u << kCr1Re | 1u << kCr1Rxneie;
}

}  // namespace hmp::board::stm32
