// The window's colours (host/view/palette.hpp) as people with common colour-vision deficiencies see
// them: the sixteen track colours, drawn dimmed behind the felt track, stay apart from each other and
// from the felt blue, the sounding yellow, white and the background under normal vision and simulated
// protanopia, deuteranopia and tritanopia (Machado, Oliveira and Fernandes 2009, severity 1, applied to
// linear RGB), by CIE76 ΔE*ab in CIELAB (D65) computed here in double precision from the published
// formulas. 12 is what the palette's generator (tools/view/track_palette.py) reached; 2.3 is a just
// noticeable difference.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "host/view/palette.hpp"

namespace {

using namespace hmp::view;
using Matrix = std::array<std::array<double, 3>, 3>;
using Lab = std::array<double, 3>;

struct Vision {
  const char* name;
  Matrix m;
};
const std::array<Vision, 4> kVisions{{
    {"normal", {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}},
    {"protanopia",
     {{{0.152286, 1.052583, -0.204868}, {0.114503, 0.786281, 0.099216}, {-0.003882, -0.048116, 1.051998}}}},
    {"deuteranopia",
     {{{0.367322, 0.860646, -0.227968}, {0.280085, 0.672501, 0.047413}, {-0.011820, 0.042940, 0.968881}}}},
    {"tritanopia",
     {{{1.255528, -0.076749, -0.178779}, {-0.078411, 0.930809, 0.147602}, {0.004733, 0.691367, 0.303900}}}},
}};

double linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

Lab lab(const Rgb& c, const Matrix& m) {
  const double in[3] = {linear(static_cast<double>(c.r)), linear(static_cast<double>(c.g)),
                        linear(static_cast<double>(c.b))};
  double s[3];
  for (int i = 0; i < 3; ++i) s[i] = std::clamp(m[i][0] * in[0] + m[i][1] * in[1] + m[i][2] * in[2], 0.0, 1.0);
  const double x = 0.4124564 * s[0] + 0.3575761 * s[1] + 0.1804375 * s[2];
  const double y = 0.2126729 * s[0] + 0.7151522 * s[1] + 0.0721750 * s[2];
  const double z = 0.0193339 * s[0] + 0.1191920 * s[1] + 0.9503041 * s[2];
  const auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  const double fx = f(x / 0.95047), fy = f(y), fz = f(z / 1.08883);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double distance(const Lab& a, const Lab& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

Rgb behind(const Rgb& c) { return mix(kBackground, c, kBehindStrength); }

TEST(ViewPalette, TrackColoursStayApartForCommonColourVisionDeficiencies) {
  std::vector<std::pair<std::string, Rgb>> drawn;
  for (std::size_t t = 0; t < kTrackColours.size(); ++t)
    drawn.push_back({"track " + std::to_string(t), behind(kTrackColours[t])});
  drawn.push_back({"felt blue", kHapticBlue});
  drawn.push_back({"sounding yellow", kSoundingYellow});
  drawn.push_back({"sounding white (behind)", behind(kSoundingWhite)});
  drawn.push_back({"background", kBackground});
  for (const Vision& v : kVisions) {
    for (std::size_t i = 0; i < drawn.size(); ++i) {
      for (std::size_t j = i + 1; j < drawn.size(); ++j) {
        const double d = distance(lab(drawn[i].second, v.m), lab(drawn[j].second, v.m));
        EXPECT_GE(d, 11.9) << v.name << ": " << drawn[i].first << " and " << drawn[j].first;
      }
    }
  }
}

TEST(ViewPalette, TracksBehindAreVisibleAndTheFeltTrackIsTheOnlyBlue) {
  const Lab background = lab(kBackground, kVisions[0].m);
  const Lab blue = lab(kHapticBlue, kVisions[0].m);
  const double blue_hue = std::atan2(blue[2], blue[1]);
  for (std::size_t t = 0; t < kTrackColours.size(); ++t) {
    const Lab c = lab(behind(kTrackColours[t]), kVisions[0].m);
    EXPECT_GE(c[0] - background[0], 25.0) << "track " << t << " too close to the background in lightness";
    EXPECT_GE(std::hypot(c[1], c[2]), 25.0) << "track " << t << " nearly grey";
    // Hue angle at least 25° from the felt blue's, or clearly lighter or darker than it.
    const double hue = std::remainder(std::atan2(c[2], c[1]) - blue_hue, 2 * M_PI);
    EXPECT_TRUE(std::fabs(hue) > 25.0 * M_PI / 180.0 || std::fabs(c[0] - blue[0]) > 20.0)
        << "track " << t << " looks blue";
  }
}

}  // namespace
