// The video export's RGB → I420 conversion against BT.709 computed here in double precision from the
// standard's equations (ITU-R BT.709-6 §3.2–3.4, limited range): every Y, U and V within ±1 of the exact
// value, extreme colours exact, rows flipped from OpenGL's bottom-up order, chroma the mean of 2×2 pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "host/video/yuv_convert.hpp"

namespace {

using hmp::video::I420Planes;

struct Reference {
  std::vector<double> y, u, v;
};

// Picture rows from the top: source row (h − 1 − row).
Reference reference(const std::vector<std::uint8_t>& rgba, int w, int h) {
  auto px = [&](int x, int row, int c) {
    return rgba[(static_cast<std::size_t>(h - 1 - row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) *
                    4 +
                static_cast<std::size_t>(c)] /
           255.0;
  };
  Reference r;
  for (int row = 0; row < h; ++row) {
    for (int x = 0; x < w; ++x) {
      const double luma = 0.2126 * px(x, row, 0) + 0.7152 * px(x, row, 1) + 0.0722 * px(x, row, 2);
      r.y.push_back(16 + 219 * luma);
    }
  }
  for (int row = 0; row < h; row += 2) {
    for (int x = 0; x < w; x += 2) {
      double m[3] = {};
      for (int c = 0; c < 3; ++c)
        m[c] = (px(x, row, c) + px(x + 1, row, c) + px(x, row + 1, c) + px(x + 1, row + 1, c)) / 4;
      const double luma = 0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2];
      r.u.push_back(128 + 224 * (m[2] - luma) / 1.8556);
      r.v.push_back(128 + 224 * (m[0] - luma) / 1.5748);
    }
  }
  return r;
}

std::vector<std::uint8_t> convert(const std::vector<std::uint8_t>& rgba, int w, int h) {
  std::vector<std::uint8_t> out(hmp::video::i420_bytes(w, h), 0xAA);
  hmp::video::rgba_bottom_up_to_i420(rgba.data(), w, h, hmp::video::i420_planes(out.data(), w, h));
  return out;
}

// Largest |ours − exact| over a plane.
double worst(const std::uint8_t* ours, const std::vector<double>& exact) {
  double d = 0;
  for (std::size_t i = 0; i < exact.size(); ++i) d = std::max(d, std::abs(ours[i] - exact[i]));
  return d;
}

void expect_close(const std::vector<std::uint8_t>& rgba, int w, int h) {
  const std::vector<std::uint8_t> out = convert(rgba, w, h);
  const Reference r = reference(rgba, w, h);
  std::vector<std::uint8_t> copy = out;
  const I420Planes p = hmp::video::i420_planes(copy.data(), w, h);
  // Rounding to nearest (half a step) plus the Q15 matrix's own rounding: three coefficients off by at
  // most 2^-16 each, times at most 255 (Y) or a 2×2 mean of 255 (U, V): under 0.012 of a step.
  const double bound = 0.5 + 0.012;
  EXPECT_LE(worst(p.y, r.y), bound) << w << "x" << h;
  EXPECT_LE(worst(p.u, r.u), bound) << w << "x" << h;
  EXPECT_LE(worst(p.v, r.v), bound) << w << "x" << h;
}

std::vector<std::uint8_t> fill(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  std::vector<std::uint8_t> rgba;
  for (int i = 0; i < w * h; ++i) rgba.insert(rgba.end(), {r, g, b, 255});
  return rgba;
}

TEST(YuvConvert, RandomFramesWithinHalfAStepOfBt709) {
  std::mt19937 rng(7);
  for (const auto& [w, h] : {std::pair{2, 2}, {64, 36}, {1280, 8}, {18, 720}}) {
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
    for (auto& b : rgba) b = static_cast<std::uint8_t>(rng());
    expect_close(rgba, w, h);
  }
}

TEST(YuvConvert, ExtremeColoursAreExact) {
  // Black and white at the ends of limited range, and grey on the neutral axis: no tint.
  const auto black = convert(fill(4, 4, 0, 0, 0), 4, 4);
  EXPECT_EQ(black[0], 16);
  EXPECT_EQ(black[16], 128);
  EXPECT_EQ(black[20], 128);
  const auto white = convert(fill(4, 4, 255, 255, 255), 4, 4);
  EXPECT_EQ(white[0], 235);
  EXPECT_EQ(white[16], 128);
  EXPECT_EQ(white[20], 128);
  for (int g = 0; g < 256; ++g) {
    const auto grey = convert(
        fill(2, 2, static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(g)), 2, 2);
    EXPECT_EQ(grey[4], 128) << g;
    EXPECT_EQ(grey[5], 128) << g;
  }
  // The primaries take the chroma extremes the standard gives: blue U = 240, red V = 240.
  EXPECT_EQ(convert(fill(2, 2, 0, 0, 255), 2, 2)[4], 240);
  EXPECT_EQ(convert(fill(2, 2, 255, 0, 0), 2, 2)[5], 240);
  for (const auto& [r, g, b] : {std::tuple{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 0}, {0, 255, 255}}) {
    expect_close(fill(6, 4, static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b)),
                 6, 4);
  }
}

TEST(YuvConvert, RowsComeOutTopDown) {
  // OpenGL's last row is the picture's top: white there, black elsewhere.
  const int w = 8, h = 6;
  std::vector<std::uint8_t> rgba = fill(w, h, 0, 0, 0);
  for (int x = 0; x < w; ++x) {
    for (int c = 0; c < 3; ++c)
      rgba[(static_cast<std::size_t>(h - 1) * w + static_cast<std::size_t>(x)) * 4 + static_cast<std::size_t>(c)] = 255;
  }
  const auto out = convert(rgba, w, h);
  for (int x = 0; x < w; ++x) {
    EXPECT_EQ(out[static_cast<std::size_t>(x)], 235);               // picture row 0
    EXPECT_EQ(out[static_cast<std::size_t>(w * (h - 1) + x)], 16);  // picture's last row
  }
}

TEST(YuvConvert, ChromaIsTheMeanOfTwoByTwo) {
  // A checkerboard of red and blue: every 2×2 block averages to the same purple; a 1-pixel shift of the
  // pattern must not change it (no sample is taken from one pixel only).
  const int w = 16, h = 8;
  std::vector<std::uint8_t> rgba;
  for (int i = 0; i < w * h; ++i) {
    const bool red = ((i % w) + (i / w)) % 2 == 0;
    rgba.insert(rgba.end(),
                {static_cast<std::uint8_t>(red ? 255 : 0), 0, static_cast<std::uint8_t>(red ? 0 : 255), 255});
  }
  const auto out = convert(rgba, w, h);
  const auto purple = convert(fill(2, 2, 128, 0, 128), 2, 2);
  for (int c = 0; c < w / 2 * h / 2; ++c) {
    EXPECT_NEAR(out[static_cast<std::size_t>(w * h + c)], purple[4], 1);
    EXPECT_NEAR(out[static_cast<std::size_t>(w * h + w * h / 4 + c)], purple[5], 1);
  }
  expect_close(rgba, w, h);
}

}  // namespace
