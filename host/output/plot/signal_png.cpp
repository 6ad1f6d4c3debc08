#include "host/output/plot/drawings.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "host/output/plot/cairo_helpers.hpp"

namespace hmp::plot {

using output::PlotNote;
using output::PlotSpec;

namespace {

using cairo_helpers::text;

using cairo_helpers::Context;
using cairo_helpers::nice_step;
using cairo_helpers::Surface;

struct Box {
  double x, y, w, h;
};

void draw_time_grid(cairo_t* cr, const Box& b, double t0, double t1, bool labels) {
  const double step = nice_step(t1 - t0, 10);
  cairo_set_line_width(cr, 1.0);
  for (double t = std::ceil(t0 / step) * step; t <= t1 + 1e-12; t += step) {
    const double x = b.x + (t - t0) / (t1 - t0) * b.w;
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, x, b.y);
    cairo_line_to(cr, x, b.y + b.h);
    cairo_stroke(cr);
    if (labels) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%g", std::round(t / step) * step);
      cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
      text(cr, x, b.y + b.h + 16, buf, 0.5);
    }
  }
}

void draw_notes(cairo_t* cr, const Box& b, std::span<const PlotNote> notes, double t0, double t1) {
  int lo = 127, hi = 0;
  for (const PlotNote& n : notes) {
    if (n.end_s < t0 || n.start_s > t1) continue;
    lo = std::min(lo, n.key);
    hi = std::max(hi, n.key);
  }
  if (lo > hi) return;
  const double rows = hi - lo + 1;
  const double row_h = b.h / rows;
  cairo_set_source_rgb(cr, 0.16, 0.35, 0.75);  // the haptic track is blue (paper §5.2)
  for (const PlotNote& n : notes) {
    if (n.end_s < t0 || n.start_s > t1) continue;
    const double xa = b.x + (std::max(n.start_s, t0) - t0) / (t1 - t0) * b.w;
    const double xb = b.x + (std::min(n.end_s, t1) - t0) / (t1 - t0) * b.w;
    const double y = b.y + (hi - n.key) * row_h;
    cairo_rectangle(cr, xa, y + 0.1 * row_h, std::max(1.0, xb - xa - 0.5), std::max(1.0, 0.8 * row_h));
  }
  cairo_fill(cr);
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  text(cr, b.x - 6, b.y + 10, "key " + std::to_string(hi), 1.0);
  text(cr, b.x - 6, b.y + b.h, "key " + std::to_string(lo), 1.0);
}

void draw_waveform(cairo_t* cr, const Box& b, std::span<const float> s) {
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_line_width(cr, 1.0);
  for (double v : {-1.0, 0.0, 1.0}) {
    const double y = b.y + (1 - v) / 2 * b.h;
    cairo_move_to(cr, b.x, y);
    cairo_line_to(cr, b.x + b.w, y);
    cairo_stroke(cr);
    char buf[8];
    std::snprintf(buf, sizeof buf, "%+.0f", v);
    text(cr, b.x - 6, y + 4, v == 0.0 ? "0" : buf, 1.0);
  }
  if (s.empty()) return;
  cairo_set_source_rgb(cr, 0.10, 0.25, 0.60);
  const auto columns = static_cast<std::size_t>(b.w);
  const bool dense = s.size() > columns * 2;
  if (dense) {  // min/max band per pixel column
    for (std::size_t c = 0; c < columns; ++c) {
      const std::size_t a = c * s.size() / columns, z = std::max(a + 1, (c + 1) * s.size() / columns);
      const auto [mn, mx] = std::minmax_element(s.begin() + static_cast<std::ptrdiff_t>(a),
                                                s.begin() + static_cast<std::ptrdiff_t>(std::min(z, s.size())));
      const double x = b.x + static_cast<double>(c) + 0.5;
      cairo_move_to(cr, x, b.y + (1.0 - static_cast<double>(*mx)) / 2 * b.h);
      cairo_line_to(cr, x, b.y + (1.0 - static_cast<double>(*mn)) / 2 * b.h + 0.5);
    }
  } else {
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double x = b.x + (static_cast<double>(i) + 0.5) / static_cast<double>(s.size()) * b.w;
      const double y = b.y + (1.0 - static_cast<double>(s[i])) / 2 * b.h;
      if (i == 0)
        cairo_move_to(cr, x, y);
      else
        cairo_line_to(cr, x, y);
    }
  }
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
}

}  // namespace

std::string draw_signal_png(const std::string& path, std::span<const float> samples, std::span<const PlotNote> notes,
                            const PlotSpec& spec) {
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, spec.width, spec.height), cairo_surface_destroy);
  Context cr(cairo_create(surface.get()), cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  cairo_select_font_face(cr.get(), "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr.get(), 13);

  const double t0 = static_cast<double>(spec.first_tick) / spec.tick_hz;
  const double t1 = t0 + std::max<double>(1.0, static_cast<double>(samples.size())) / spec.tick_hz;
  const double left = 70, right = 20, top = 40, gap = 30, bottom = 45;
  const double inner_h = spec.height - top - gap - bottom;
  // One note (hmp tone) needs no piano roll: the waveform gets the whole height.
  const bool with_roll = notes.size() > 1;
  const Box roll{left, top, spec.width - left - right, with_roll ? inner_h * 0.35 : 0.0};
  const Box wave{left, top + (with_roll ? roll.h : 0.0) + gap, roll.w, with_roll ? inner_h * 0.65 : inner_h};

  cairo_set_source_rgb(cr.get(), 0.1, 0.1, 0.1);
  cairo_set_font_size(cr.get(), 15);
  text(cr.get(), left, 24, spec.title);
  cairo_set_font_size(cr.get(), 12);
  if (with_roll) draw_time_grid(cr.get(), roll, t0, t1, false);
  draw_time_grid(cr.get(), wave, t0, t1, true);
  if (with_roll) draw_notes(cr.get(), roll, notes, t0, t1);
  draw_waveform(cr.get(), wave, samples);
  cairo_set_source_rgb(cr.get(), 0.2, 0.2, 0.2);
  text(cr.get(), wave.x + wave.w, spec.height - 8.0, "time (s)", 1.0);
  text(cr.get(), 8, wave.y - 8, "value (full scale)");

  return cairo_helpers::status_text(cairo_surface_write_to_png(surface.get(), path.c_str()));
}

}  // namespace hmp::plot
