// Numbers typed as option values (host/common/number_text.hpp): the whole text or nothing, never a
// prefix, an infinity or a count outside its range.
#include <gtest/gtest.h>

#include <climits>
#include <string>

#include "host/common/number_text.hpp"

namespace {

using hmp::finite_number;
using hmp::whole_number;
using namespace std::string_literals;

TEST(FiniteNumber, TakesTheWholeText) {
  EXPECT_EQ(finite_number("2.5"), 2.5);
  EXPECT_EQ(finite_number("-1e-3"), -1e-3);
  EXPECT_EQ(finite_number("1e308"), 1e308);
  EXPECT_FALSE(finite_number(""));
  EXPECT_FALSE(finite_number("5x"));
  EXPECT_FALSE(finite_number("5 "));
  EXPECT_FALSE(
      finite_number("5\0"
                    "1"s));  // a NUL inside does not end it
  EXPECT_FALSE(finite_number("x"));
}

TEST(FiniteNumber, RefusesWhatIsNotFinite) {
  EXPECT_FALSE(finite_number("inf"));
  EXPECT_FALSE(finite_number("-infinity"));
  EXPECT_FALSE(finite_number("nan"));
  EXPECT_FALSE(finite_number("1e400"));  // overflows to infinity
}

TEST(WholeNumber, TakesAnIntegerWithinItsRange) {
  EXPECT_EQ(whole_number("12", 1, 100), 12);
  EXPECT_EQ(whole_number("1", 1, 100), 1);
  EXPECT_EQ(whole_number("100", 1, 100), 100);
  EXPECT_EQ(whole_number("-3", -5, 5), -3);
  EXPECT_EQ(whole_number(std::to_string(LONG_MAX), 0, LONG_MAX), LONG_MAX);
}

TEST(WholeNumber, RefusesAnythingElse) {
  EXPECT_FALSE(whole_number("0", 1, 100));
  EXPECT_FALSE(whole_number("101", 1, 100));
  EXPECT_FALSE(whole_number("", 1, 100));
  EXPECT_FALSE(whole_number("5x", 1, 100));
  EXPECT_FALSE(whole_number("2.5", 1, 100));
  EXPECT_FALSE(whole_number("1e2", 1, 1000));
  EXPECT_FALSE(
      whole_number("7\0"
                   "0"s,
                   1, 100));
  EXPECT_FALSE(whole_number(" 5", 1, 100));  // strtol would skip the space
  EXPECT_FALSE(whole_number("+5", 1, 100));
  EXPECT_FALSE(whole_number("-", -5, 5));
  EXPECT_FALSE(whole_number("- 5", -5, 5));
  EXPECT_FALSE(whole_number("99999999999999999999999", 0, LONG_MAX));  // beyond a long
  EXPECT_FALSE(whole_number("-99999999999999999999999", LONG_MIN, 0));
}

TEST(ShortNumber, ExponentWithoutPlusOrLeadingZeros) {
  EXPECT_EQ(hmp::short_number(1e9), "1e9");
  EXPECT_EQ(hmp::short_number(1e-7), "1e-7");
  EXPECT_EQ(hmp::short_number(2.5e-5), "2.5e-5");
  EXPECT_EQ(hmp::short_number(1e100), "1e100");
  EXPECT_EQ(hmp::short_number(-3e-10), "-3e-10");
  EXPECT_EQ(hmp::short_number(0.001), "0.001");
  EXPECT_EQ(hmp::short_number(1000), "1000");
  EXPECT_EQ(hmp::short_number(0), "0");
}

}  // namespace
