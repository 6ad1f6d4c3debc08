#pragma once
// Where the animation puts things (paper Figure 1, docs/view.md): time runs right to left across the
// roll at the song's pace, the present at its centre line, the future on the right; pitch upwards; each
// track one depth layer, the haptic track in front, the others behind it in track order, each layer drawn
// a little up and to the right of the one before (an oblique view of the 3D bars), the layers behind
// thinner and dimmed. The legend is a panel right of the roll, never over it. Pixels, origin at the top
// left, y down. The drawing and the cursor's pick use these same numbers.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "host/view/note_index.hpp"
#include "host/view/palette.hpp"

namespace hmp::view {

struct Rect {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // x0 < x1, y0 < y1
  bool contains(float x, float y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

struct LayoutParams {
  int width_px = 1280, height_px = 720;
  double seconds_across = 12.0;      // the window shows this much song time (zoom: + and − keys)
  int key_low = 21, key_high = 108;  // the keys shown (piano range unless the song says otherwise)
  float margin_px = 40.0f;           // above and below the roll (overlay, vibration strip)
  float depth_step_px = 6.0f;        // each layer behind is this much up and to the right,
  float depth_span_px = 30.0f;       // the deepest at most this much (many tracks: smaller steps)
  float legend_px = 240.0f;          // the legend's panel right of the roll (at most 30 % of the width)
};

// The roll's width: the window less the legend's panel.
float roll_width(const LayoutParams& p);
// A layer behind the haptic one is drawn this fraction of a row high (the haptic one the whole row).
inline constexpr float kBehindHeight = 0.6f;

// The parameters for a drawable of width × height pixels at `scale` pixels per logical pixel (HiDPI): the
// margins and layer offsets grow with the scale, so the window looks the same on every screen.
LayoutParams for_drawable(LayoutParams p, int width_px, int height_px, float scale, double seconds_across);

class RollLayout {
 public:
  // `tracks`: how many; `haptic`: the haptic track (in front).
  RollLayout(const LayoutParams& p, std::uint32_t tracks, std::uint32_t haptic);

  const LayoutParams& params() const { return p_; }
  // The song-time window drawn around `now_us`: [now − half, now + half), half = seconds_across / 2,
  // widened on the left by the layers' offset so that shifted bars are not cut early.
  std::int64_t window_begin_us(std::int64_t now_us) const;
  std::int64_t window_end_us(std::int64_t now_us) const;
  float x_of(std::int64_t t_us, std::int64_t now_us) const;  // before the layer's shift
  float row_height() const;
  float y_of(int key) const;  // top of the key's row, before the shift
  std::uint32_t depth_of(std::uint32_t track) const { return depth_.at(track); }  // 0 = front (haptic)
  Rect bar_rect(const Bar& b, std::int64_t now_us) const;
  // After a switch of the haptic track the layers glide to their new depth: `blend` 0 is the old order
  // (`previous` in front), 1 the new one. Bars are placed at the interpolated depth.
  void set_depth_blend(std::uint32_t previous, float blend);
  // The haptic track blue (yellow while it sounds); any other track its own colour (kTrackColours by
  // track number, white while it sounds), dimmed to kBehindStrength behind the haptic one.
  Rgb colour(const Bar& b, std::int64_t now_us) const;
  // The legend's swatch of a track: its colour as its bars show it, not sounding.
  Rgb track_colour(std::uint32_t track) const;

  // The front-most bar under (x, y) among `visible` (any order, any tracks); null if none.
  std::optional<Bar> pick(std::span<const Bar> visible, std::int64_t now_us, float x, float y) const;

 private:
  LayoutParams p_;
  std::uint32_t haptic_;
  float depth_step() const;                   // px between neighbouring layers
  float shift_of(std::uint32_t track) const;  // px up and right of the track's layer
  float front_of(std::uint32_t track) const;  // 1 in front, 0 behind; between while the layers glide

  std::vector<std::uint32_t> depth_;           // per track
  std::vector<std::uint32_t> previous_depth_;  // per track, before the switch (empty: no glide)
  float blend_ = 1.0f;
};

// The parts around the roll (docs/view.md): the overlay line in the top margin, the legend in its panel
// right of the roll, the progress bar and the vibration strip in the bottom margin. `scale` is the
// screen's pixels per logical pixel (HiDPI), so text and rows keep their size.
struct Chrome {
  Rect overlay;   // the top margin
  Rect progress;  // click or drag: seek
  Rect strip;     // the vibration the device plays now
  Rect legend;    // the legend's panel, beside the roll
  float legend_x0 = 0, legend_y0 = 0, legend_row = 0, legend_width = 0;
  Rect legend_row_rect(std::size_t i) const {
    const float y = legend_y0 + legend_row * static_cast<float>(i);
    return {legend_x0, y, legend_x0 + legend_width, y + legend_row};
  }
  float text_px = 13.0f;  // font size
};
Chrome chrome_layout(const LayoutParams& p, float scale = 1.0f);

// The song time at x on the progress bar for a song (or passage) [begin_us, end_us).
std::int64_t progress_time(const Chrome& c, float x, std::int64_t begin_us, std::int64_t end_us);

// The keys to show for a song: `chosen` where the user chose them, else the song's lowest to highest key
// with a little room, at least two octaves.
std::pair<int, int> key_range(const midi::Song& song, std::optional<std::pair<int, int>> chosen = std::nullopt);

}  // namespace hmp::view
