#pragma once
// Every colour of the window, in one place (docs/view.md "Colours"). The felt (haptic) track is the only
// blue and is drawn at full strength; every other track has a colour of its own, by track number, drawn
// dimmed behind it. The sixteen track colours were chosen by tools/view/track_palette.py: greedy
// farthest-point picks in CIELAB, dimmed as drawn, against the felt blue, the sounding yellow and white and
// the background, under normal vision and simulated protanopia, deuteranopia and tritanopia (Machado et
// al. 2009), each at least 35 in lightness and 25 in chroma; the closest pair in any of the four is
// ΔE*ab 12 apart. tests/host/view/palette_test.cpp checks that with its own colour science.
#include <array>

namespace hmp::view {

struct Rgb {
  float r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

constexpr Rgb rgb8(int r, int g, int b) {
  return {static_cast<float>(r) / 255.0f, static_cast<float>(g) / 255.0f, static_cast<float>(b) / 255.0f};
}

// The roll.
inline constexpr Rgb kBackground{0.07f, 0.07f, 0.08f};
inline constexpr Rgb kHapticBlue = rgb8(30, 136, 229);      // the felt track
inline constexpr Rgb kSoundingYellow = rgb8(240, 228, 66);  // a felt note sounding now
inline constexpr Rgb kSoundingWhite{1.0f, 1.0f, 1.0f};      // another track's note sounding now
// Tracks behind the felt one are drawn this far from the background towards their colour.
inline constexpr float kBehindStrength = 0.7f;
inline constexpr std::array<Rgb, 16> kTrackColours{{
    rgb8(204, 102, 0),
    rgb8(204, 153, 204),
    rgb8(204, 255, 128),
    rgb8(102, 153, 102),
    rgb8(178, 51, 204),
    rgb8(76, 255, 0),
    rgb8(153, 51, 255),
    rgb8(102, 204, 102),
    rgb8(178, 153, 255),
    rgb8(230, 26, 51),
    rgb8(153, 102, 153),
    rgb8(153, 255, 178),
    rgb8(255, 153, 178),
    rgb8(153, 204, 51),
    rgb8(0, 128, 102),
    rgb8(230, 76, 204),
}};

// Around the roll.
inline constexpr Rgb kCentreLine{0.85f, 0.85f, 0.85f};
inline constexpr Rgb kStrip = kHapticBlue;  // the vibration the device plays: the felt track's
inline constexpr Rgb kPanel{0.13f, 0.13f, 0.15f};
inline constexpr Rgb kProgressDone{0.45f, 0.45f, 0.5f};
inline constexpr Rgb kText{0.92f, 0.92f, 0.92f};
inline constexpr Rgb kTextDim{0.55f, 0.55f, 0.58f};
inline constexpr Rgb kCursor{1.0f, 1.0f, 1.0f};

// a + (b − a)·t per channel.
constexpr Rgb mix(const Rgb& a, const Rgb& b, float t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

}  // namespace hmp::view
