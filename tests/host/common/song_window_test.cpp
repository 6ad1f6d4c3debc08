// The window --from/--to pick (host/common/song_window.hpp): every bad time refused by name, an end past
// the song's held to it, and no time so large that its microseconds overflow.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "host/common/error.hpp"
#include "host/common/song_window.hpp"

namespace {

using hmp::BadInput;
using hmp::check_window_times;
using hmp::saturated_us;
using hmp::song_window;

constexpr std::int64_t kSongEnd = 310'000'000;  // µs
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The message of the BadInput that `f` throws ("" if none).
template <typename F>
std::string refusal(F f) {
  try {
    f();
  } catch (const BadInput& e) {
    return e.what();
  }
  return "";
}

TEST(SongWindow, NoTimesIsTheWholeSong) {
  const auto w = song_window(std::nullopt, std::nullopt, kSongEnd);
  EXPECT_EQ(w.begin_us, 0);
  EXPECT_EQ(w.end_us, kSongEnd);
}

TEST(SongWindow, TimesInsideTheSongAreKeptToTheMicrosecond) {
  const auto w = song_window(10.0000004, 12.5, kSongEnd);
  EXPECT_EQ(w.begin_us, 10'000'000);
  EXPECT_EQ(w.end_us, 12'500'000);
  EXPECT_EQ(song_window(0.0, 309.999999, kSongEnd).end_us, 309'999'999);
}

TEST(SongWindow, AnEndPastTheSongIsTheSongsEnd) {
  for (double to : {310.0, 310.5, 1e6, 1e13, 1e300, std::numeric_limits<double>::max()})
    EXPECT_EQ(song_window(300.0, to, kSongEnd).end_us, kSongEnd) << to;
}

TEST(SongWindow, AStartAtOrPastTheSongsEndIsRefused) {
  for (double from : {310.0, 400.0, 1e13, 1e300}) {
    const std::string why = refusal([&] { song_window(from, std::nullopt, kSongEnd); });
    EXPECT_NE(why.find("the song ends at 310.000 s"), std::string::npos) << from << ": " << why;
  }
}

TEST(SongWindow, TimesThatAreNotSecondsAreRefusedByName) {
  EXPECT_NE(refusal([] { check_window_times(-1.0, std::nullopt); }).find("--from -1:"), std::string::npos);
  EXPECT_NE(refusal([] { check_window_times(kNaN, 1.0); }).find("--from nan:"), std::string::npos);
  EXPECT_NE(refusal([] { check_window_times(0.0, kInf); }).find("--to inf:"), std::string::npos);
  EXPECT_NE(refusal([] { check_window_times(std::nullopt, -kInf); }).find("--to -inf:"), std::string::npos);
  EXPECT_NE(refusal([] { song_window(kInf, std::nullopt, kSongEnd); }).find("--from inf:"), std::string::npos);
}

TEST(SongWindow, AnEmptyWindowIsRefused) {
  EXPECT_NE(refusal([] { check_window_times(5.0, 4.0); }).find("empty window"), std::string::npos);
  EXPECT_NE(refusal([] { check_window_times(5.0, 5.0); }).find("empty window"), std::string::npos);
  EXPECT_NE(refusal([] { check_window_times(std::nullopt, 0.0); }).find("empty window"), std::string::npos);
  // Apart by less than the half microsecond the times are rounded to.
  EXPECT_NE(refusal([] { song_window(1.0, 1.0 + 1e-7, kSongEnd); }).find("empty window"), std::string::npos);
  EXPECT_EQ(refusal([] { check_window_times(0.0, 1e-9); }), "");  // only the microseconds say it is empty
}

TEST(SongWindow, MicrosecondsSaturateInsteadOfOverflowing) {
  EXPECT_EQ(saturated_us(0.0), 0);
  EXPECT_EQ(saturated_us(1.5e-6), 2);  // halves away from zero, as llround
  EXPECT_EQ(saturated_us(9.1e12), 9'100'000'000'000'000'000);
  EXPECT_EQ(saturated_us(9.3e12), std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(saturated_us(1e300), std::numeric_limits<std::int64_t>::max());
}

}  // namespace
