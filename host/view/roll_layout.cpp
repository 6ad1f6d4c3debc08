#include "host/view/roll_layout.hpp"

#include <algorithm>
#include <cmath>

namespace hmp::view {

LayoutParams for_drawable(LayoutParams p, int width_px, int height_px, float scale, double seconds_across) {
  p.width_px = width_px > 1 ? width_px : 1;
  p.height_px = height_px > 1 ? height_px : 1;
  p.seconds_across = seconds_across;
  p.margin_px *= scale;
  p.depth_step_px *= scale;
  p.depth_span_px *= scale;
  p.legend_px *= scale;
  return p;
}

float roll_width(const LayoutParams& p) {
  const auto w = static_cast<float>(p.width_px);
  return std::max(1.0f, w - std::min(p.legend_px, 0.3f * w));
}

RollLayout::RollLayout(const LayoutParams& p, std::uint32_t tracks, std::uint32_t haptic)
    : p_(p), haptic_(haptic), depth_(tracks, 0) {
  std::uint32_t next = 1;
  for (std::uint32_t t = 0; t < tracks; ++t) depth_[t] = t == haptic ? 0 : next++;
}

namespace {
std::int64_t half_span_us(const LayoutParams& p) { return std::llround(p.seconds_across * 0.5e6); }
double px_per_us(const LayoutParams& p) { return static_cast<double>(roll_width(p)) / (p.seconds_across * 1e6); }
}  // namespace

std::int64_t RollLayout::window_begin_us(std::int64_t now_us) const {
  // A layer d is shifted right by d·step px: a bar that ends left of the window's edge can still show.
  const double shift_px = static_cast<double>(depth_step()) * static_cast<double>(depth_.size());
  const auto shift_us = static_cast<std::int64_t>(std::ceil(shift_px / px_per_us(p_)));
  return now_us - half_span_us(p_) - shift_us;
}

std::int64_t RollLayout::window_end_us(std::int64_t now_us) const { return now_us + half_span_us(p_); }

float RollLayout::x_of(std::int64_t t_us, std::int64_t now_us) const {
  return static_cast<float>(static_cast<double>(roll_width(p_)) * 0.5 +
                            static_cast<double>(t_us - now_us) * px_per_us(p_));
}

float RollLayout::row_height() const {
  const int rows = std::max(1, p_.key_high - p_.key_low + 1);
  return (static_cast<float>(p_.height_px) - 2.0f * p_.margin_px) / static_cast<float>(rows);
}

float RollLayout::y_of(int key) const { return p_.margin_px + static_cast<float>(p_.key_high - key) * row_height(); }

void RollLayout::set_depth_blend(std::uint32_t previous, float blend) {
  blend_ = std::clamp(blend, 0.0f, 1.0f);
  if (blend_ >= 1.0f || previous >= depth_.size()) {
    previous_depth_.clear();
    return;
  }
  previous_depth_ = RollLayout(p_, static_cast<std::uint32_t>(depth_.size()), previous).depth_;
}

float RollLayout::depth_step() const {
  const auto deepest = static_cast<float>(depth_.size() > 1 ? depth_.size() - 1 : 1);
  return std::min(p_.depth_step_px, p_.depth_span_px / deepest);
}

float RollLayout::shift_of(std::uint32_t track) const {
  const float now = static_cast<float>(depth_of(track));
  if (previous_depth_.empty()) return depth_step() * now;
  const float before = static_cast<float>(previous_depth_.at(track));
  return depth_step() * (before + (now - before) * blend_);
}

float RollLayout::front_of(std::uint32_t track) const {
  const float now = depth_of(track) == 0 ? 1.0f : 0.0f;
  if (previous_depth_.empty()) return now;
  const float before = previous_depth_.at(track) == 0 ? 1.0f : 0.0f;
  return before + (now - before) * blend_;
}

Rect RollLayout::bar_rect(const Bar& b, std::int64_t now_us) const {
  const float shift = shift_of(b.track);
  // A zero-length note still shows as a sliver one pixel wide; the future ends at the roll's edge.
  const float right = roll_width(p_);
  const float x0 = std::min(x_of(b.start_us, now_us) + shift, right - 1.0f);
  const float x1 = std::min(std::max(x_of(b.end_us, now_us) + shift, x0 + 1.0f), right);
  // The whole row for the haptic layer, kBehindHeight of it, centred, for the ones behind.
  const float full = std::max(1.0f, row_height() - 1.0f);
  const float height = std::max(1.0f, full * (kBehindHeight + (1.0f - kBehindHeight) * front_of(b.track)));
  const float y0 = y_of(b.key) - shift + (full - height) * 0.5f;
  return {x0, y0, x1, y0 + height};
}

Rgb RollLayout::colour(const Bar& b, std::int64_t now_us) const {
  const bool sounding = NoteIndex::sounding(b, now_us);
  if (b.track == haptic_) return sounding ? kSoundingYellow : kHapticBlue;
  const Rgb own = sounding ? kSoundingWhite : kTrackColours[b.track % kTrackColours.size()];
  return mix(kBackground, own, kBehindStrength + (1.0f - kBehindStrength) * front_of(b.track));
}

Rgb RollLayout::track_colour(std::uint32_t track) const { return colour(Bar{0, 0, 0, 0, track}, 1); }

std::optional<Bar> RollLayout::pick(std::span<const Bar> visible, std::int64_t now_us, float x, float y) const {
  std::optional<Bar> best;
  for (const Bar& b : visible) {
    if (!bar_rect(b, now_us).contains(x, y)) continue;
    if (!best || depth_of(b.track) < depth_of(best->track)) best = b;
  }
  return best;
}

Chrome chrome_layout(const LayoutParams& p, float scale) {
  const auto w = static_cast<float>(p.width_px), h = static_cast<float>(p.height_px);
  Chrome c;
  c.text_px = 13.0f * scale;
  c.overlay = {0.0f, 0.0f, w, p.margin_px};
  const float strip_h = std::min(30.0f, p.margin_px * 0.75f);
  c.strip = {0.0f, h - strip_h, w, h};
  c.progress = {0.0f, h - p.margin_px + 1.0f, w, h - strip_h - 1.0f};
  c.legend = {roll_width(p), c.overlay.y1, w, c.progress.y0 - 1.0f};
  c.legend_row = 18.0f * scale;
  c.legend_x0 = c.legend.x0 + 6.0f * scale;
  c.legend_width = std::max(1.0f, c.legend.x1 - c.legend_x0 - 6.0f * scale);
  c.legend_y0 = c.legend.y0 + 4.0f * scale;
  return c;
}

std::int64_t progress_time(const Chrome& c, float x, std::int64_t begin_us, std::int64_t end_us) {
  const float width = c.progress.x1 - c.progress.x0;
  if (!(width > 0.0f) || end_us <= begin_us) return begin_us;
  const double f = std::clamp(static_cast<double>((x - c.progress.x0) / width), 0.0, 1.0);
  return begin_us + std::llround(f * static_cast<double>(end_us - begin_us));
}

std::pair<int, int> key_range(const midi::Song& song, std::optional<std::pair<int, int>> chosen) {
  if (chosen) return *chosen;
  int lo = 127, hi = 0;
  for (const midi::Track& t : song.tracks) {
    if (t.note_count == 0) continue;
    lo = std::min(lo, t.key_min());
    hi = std::max(hi, t.key_max());
  }
  if (lo > hi) return {48, 72};
  lo = std::max(0, lo - 2);
  hi = std::min(127, hi + 2);
  while (hi - lo < 24) {  // at least two octaves, centred on what is there
    if (lo > 0) --lo;
    if (hi - lo < 24 && hi < 127) ++hi;
  }
  return {lo, hi};
}

}  // namespace hmp::view
