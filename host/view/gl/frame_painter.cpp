#include "host/view/gl/frame_painter.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <climits>
#include <cstdint>

#include "host/common/cpu_time.hpp"
#include "host/view/gl/text_layer.hpp"

namespace hmp::view::gl {
FramePainter::FramePainter(const midi::Song& song, bool draw_everything, std::optional<std::pair<int, int>> keys)
    : draw_everything_(draw_everything), index_(song) {
  const auto [lo, hi] = key_range(song, keys);
  layout_params_.key_low = lo;
  layout_params_.key_high = hi;
  renderer_ = std::make_unique<RollRenderer>();
  text_ = std::make_unique<TextLayer>();
}

FramePainter::~FramePainter() = default;

bool FramePainter::ok() const { return renderer_->ok() && text_->ok(); }

std::string FramePainter::error() const {
  if (!renderer_->ok()) return renderer_->error();
  return text_->ok() ? "" : "the text shader did not build";
}

void FramePainter::paint(const FrameState& state, int width_px, int height_px, float scale, FrameCost& cost) {
  const double cpu0 = 1e3 * thread_cpu_seconds();
  const LayoutParams p = for_drawable(layout_params_, width_px, height_px, scale, state.seconds_across);
  const auto tracks = static_cast<std::uint32_t>(index_.tracks());
  RollLayout layout(p, tracks, std::min(state.haptic_track, tracks == 0 ? 0u : tracks - 1));
  layout.set_depth_blend(state.previous_haptic, state.depth_blend);
  const Chrome chrome = chrome_layout(p, scale);
  auto hidden = [&](std::uint32_t t) {
    return std::any_of(state.legend.begin(), state.legend.end(),
                       [t](const LegendEntry& e) { return e.track == t && e.hidden; });
  };

  // Back to front: the deepest layer first, the haptic track last (on top). Only the visible bars.
  order_.resize(tracks);
  for (std::uint32_t t = 0; t < tracks; ++t) order_[t] = t;
  std::sort(order_.begin(), order_.end(),
            [&](std::uint32_t a, std::uint32_t b) { return layout.depth_of(a) > layout.depth_of(b); });
  instances_.clear();
  const std::int64_t t0 = layout.window_begin_us(state.song_us), t1 = layout.window_end_us(state.song_us);
  for (const std::uint32_t t : order_) {
    if (hidden(t)) continue;
    if (draw_everything_) {
      index_.visible(t, INT64_MIN / 2, INT64_MAX / 2, visible_);
    } else {
      index_.visible(t, t0, t1, visible_);
    }
    for (const Bar& b : visible_)
      instances_.push_back({layout.bar_rect(b, state.song_us), layout.colour(b, state.song_us)});
  }
  for (const Bar& b : state.played) {
    if (b.track < tracks && !hidden(b.track))
      instances_.push_back({layout.bar_rect(b, state.song_us), layout.colour(b, state.song_us)});
  }
  // The present: a thin line at the roll's centre, over it.
  const float cx = roll_width(p) * 0.5f;
  instances_.push_back({{cx - scale, chrome.overlay.y1, cx + scale, chrome.progress.y0}, kCentreLine});
  // The progress bar: the part played so far lighter.
  instances_.push_back({chrome.progress, kPanel});
  if (state.end_us > 0) {
    const double f = std::clamp(static_cast<double>(state.song_us) / static_cast<double>(state.end_us), 0.0, 1.0);
    const float x = chrome.progress.x0 + static_cast<float>(f) * (chrome.progress.x1 - chrome.progress.x0);
    instances_.push_back({{chrome.progress.x0, chrome.progress.y0, x, chrome.progress.y1}, kProgressDone});
  }
  // The vibration the device plays now: a strip along the bottom, one column per sample.
  const int n = std::clamp(state.vibration_samples, 0, 256);
  const float strip_h = chrome.strip.y1 - chrome.strip.y0;
  const float base = chrome.strip.y0 + strip_h * 0.5f;
  for (int i = 0; i < n; ++i) {
    const float x0 = static_cast<float>(p.width_px) * static_cast<float>(i) / static_cast<float>(n);
    const float x1 = static_cast<float>(p.width_px) * static_cast<float>(i + 1) / static_cast<float>(n);
    const float v = std::clamp(state.vibration[i], -1.0f, 1.0f) * strip_h * 0.45f;
    instances_.push_back({{x0, std::min(base, base - v), x1, std::max(base, base - v) + 1.0f}, kStrip});
  }
  // The legend: in its panel beside the roll, a row per track with its colour swatch (hidden tracks dimmed).
  instances_.push_back({chrome.legend, kPanel});
  std::vector<TextItem> text;
  if (!state.overlay.empty())
    text.push_back(
        {6.0f * scale, (chrome.overlay.y1 - chrome.text_px * 1.2f) * 0.5f, chrome.text_px, kText, state.overlay});
  for (std::size_t row = 0; row < state.legend.size(); ++row) {
    const LegendEntry& entry = state.legend[row];
    if (entry.track >= tracks) continue;
    const Rect r = chrome.legend_row_rect(row);
    instances_.push_back({r, kPanel});
    const Rgb swatch = layout.track_colour(entry.track);
    const float sw = r.y1 - r.y0 - 6.0f * scale;
    instances_.push_back({{r.x0 + 3.0f * scale, r.y0 + 3.0f * scale, r.x0 + 3.0f * scale + sw, r.y1 - 3.0f * scale},
                          entry.hidden ? kPanel : swatch});
    const float text_x = r.x0 + 8.0f * scale + sw;
    text.push_back({text_x, r.y0 + 2.0f * scale, chrome.text_px, entry.hidden ? kTextDim : kText,
                    (entry.haptic ? "\u25B6 " : "") + entry.label, r.x1 - text_x});  // cut at the panel's edge
  }
  // The touch cursor: a cross with a box, filled while pushing in.
  if (state.cursor) {
    const float c = 7.0f * scale, t = scale;
    const float x = state.cursor_x, y = state.cursor_y;
    instances_.push_back({{x - c, y - t, x + c, y + t}, kCursor});
    instances_.push_back({{x - t, y - c, x + t, y + c}, kCursor});
    if (state.cursor_pressing)
      instances_.push_back({{x - c * 0.5f, y - c * 0.5f, x + c * 0.5f, y + c * 0.5f}, kSoundingYellow});
  }
  // Help: a panel in the middle.
  if (!state.help.empty()) {
    const float line = chrome.text_px * 1.5f, width = 420.0f * scale;
    const float x0 = (static_cast<float>(p.width_px) - width) * 0.5f, y0 = chrome.overlay.y1 + 20.0f * scale;
    instances_.push_back(
        {{x0, y0, x0 + width, y0 + line * static_cast<float>(state.help.size()) + 12.0f * scale}, kPanel});
    for (std::size_t i = 0; i < state.help.size(); ++i) {
      text.push_back(
          {x0 + 10.0f * scale, y0 + 6.0f * scale + line * static_cast<float>(i), chrome.text_px, kText, state.help[i]});
    }
  }
  text_->prepare(p.width_px, p.height_px, text);
  cost.prepare_cpu_ms = 1e3 * thread_cpu_seconds() - cpu0;
  cost.instances = instances_.size();
  renderer_->draw(p.width_px, p.height_px, instances_);
  text_->draw();
}

}  // namespace hmp::view::gl
