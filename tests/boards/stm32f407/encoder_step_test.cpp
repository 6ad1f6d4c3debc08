// The stm32f407 board's software quadrature decoder (boards/stm32f407/encoders.hpp, Encoders::step),
// against an independent model: a shaft position p gives the pins (A, B) of a quadrature encoder as the
// Gray code of p mod 4 (forward 00 → 01 → 11 → 10); summing step() over any walk of ±1 moves must give
// back the net movement, and a jump of two states (an edge missed) must be reported, never counted.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "boards/stm32f407/encoders.hpp"

namespace {

using hmp::board::stm32::Encoders;

std::uint8_t pins_at(std::int64_t position) {
  const auto phase = static_cast<std::uint8_t>(((position % 4) + 4) % 4);
  constexpr std::uint8_t gray[4] = {0b00, 0b01, 0b11, 0b10};  // a << 1 | b
  return gray[phase];
}

TEST(Stm32EncoderStep, RandomWalksCountExactly) {
  std::mt19937 rng(7);
  for (int walk = 0; walk < 200; ++walk) {
    std::int64_t position = static_cast<std::int64_t>(rng() % 1000) - 500;
    const std::int64_t start = position;
    std::int64_t counted = 0;
    std::uint8_t state = pins_at(position);
    for (int i = 0; i < 5000; ++i) {
      const int move = static_cast<int>(rng() % 3) - 1;  // −1, 0, +1
      position += move;
      const std::uint8_t now = pins_at(position);
      const std::int8_t s = Encoders::step(state, now);
      ASSERT_NE(s, Encoders::kInvalid);
      ASSERT_EQ(s, move);
      counted += s;
      state = now;
    }
    EXPECT_EQ(counted, position - start);
  }
}

TEST(Stm32EncoderStep, TwoStatesAtOnceIsReportedNotGuessed) {
  for (std::int64_t p = -8; p < 8; ++p) {
    EXPECT_EQ(Encoders::step(pins_at(p), pins_at(p + 2)), Encoders::kInvalid) << p;
    EXPECT_EQ(Encoders::step(pins_at(p), pins_at(p - 2)), Encoders::kInvalid) << p;
    EXPECT_EQ(Encoders::step(pins_at(p), pins_at(p)), 0) << p;
  }
}

}  // namespace
