#include "host/output/plot/drawings.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "host/output/plot/cairo_helpers.hpp"

namespace hmp::plot {

using output::Trace;
using output::TracePlotSpec;

namespace {

using cairo_helpers::Context;
using cairo_helpers::nice_step;
using cairo_helpers::Surface;
using cairo_helpers::text;

}  // namespace

std::string draw_traces_png(const std::string& path, const std::vector<Trace>& traces, const TracePlotSpec& spec) {
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, spec.width, spec.height), cairo_surface_destroy);
  Context context(cairo_create(surface.get()), cairo_destroy);
  cairo_t* cr = context.get();
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);

  std::size_t n = 1;
  float lo = 0.0f, hi = 0.0f;
  for (const Trace& t : traces) {
    n = std::max(n, t.samples.size());
    for (float v : t.samples) {
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  const double span = std::max(1e-3, static_cast<double>(hi - lo));
  const double y_lo = static_cast<double>(lo) - 0.05 * span, y_hi = static_cast<double>(hi) + 0.05 * span;
  const double t0 = spec.t0_s, t1 = spec.t0_s + static_cast<double>(n) / spec.rate_hz;
  const double left = 80, right = 20, top = 60, bottom = 45;
  const double w = spec.width - left - right, h = spec.height - top - bottom;
  auto x_of = [&](double t) { return left + (t - t0) / (t1 - t0) * w; };
  auto y_of = [&](double v) { return top + (y_hi - v) / (y_hi - y_lo) * h; };

  cairo_set_font_size(cr, 15);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, left, 24, spec.title, 0.0);
  cairo_set_font_size(cr, 12);
  cairo_set_line_width(cr, 1.0);
  const double t_step = nice_step(t1 - t0, 10);
  for (double t = std::ceil(t0 / t_step) * t_step; t <= t1 + 1e-12; t += t_step) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, x_of(t), top);
    cairo_line_to(cr, x_of(t), top + h);
    cairo_stroke(cr);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", std::round(t / t_step) * t_step);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    text(cr, x_of(t), top + h + 16, buf, 0.5);
  }
  const double v_step = nice_step(y_hi - y_lo, 6);
  for (double v = std::ceil(y_lo / v_step) * v_step; v <= y_hi + 1e-12; v += v_step) {
    cairo_set_source_rgb(cr, v == 0.0 ? 0.6 : 0.88, v == 0.0 ? 0.6 : 0.88, v == 0.0 ? 0.6 : 0.88);
    cairo_move_to(cr, left, y_of(v));
    cairo_line_to(cr, left + w, y_of(v));
    cairo_stroke(cr);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", std::round(v / v_step) * v_step);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    text(cr, left - 6, y_of(v) + 4, buf, 1.0);
  }

  const auto columns = static_cast<std::size_t>(w);
  double legend_x = left;
  for (const Trace& t : traces) {
    const std::span<const float> s = t.samples;
    cairo_set_source_rgb(cr, t.red, t.green, t.blue);
    if (!s.empty() && s.size() > columns * 2) {  // min/max band per pixel column
      for (std::size_t c = 0; c < columns; ++c) {
        const std::size_t a = c * s.size() / columns, z = std::max(a + 1, (c + 1) * s.size() / columns);
        const auto [mn, mx] = std::minmax_element(s.begin() + static_cast<std::ptrdiff_t>(a),
                                                  s.begin() + static_cast<std::ptrdiff_t>(std::min(z, s.size())));
        cairo_move_to(cr, left + static_cast<double>(c) + 0.5, y_of(static_cast<double>(*mx)));
        cairo_line_to(cr, left + static_cast<double>(c) + 0.5, y_of(static_cast<double>(*mn)) + 0.5);
      }
    } else {
      for (std::size_t i = 0; i < s.size(); ++i) {
        const double x = x_of(t0 + static_cast<double>(i) / spec.rate_hz);
        const double y = y_of(static_cast<double>(s[i]));
        if (i == 0)
          cairo_move_to(cr, x, y);
        else
          cairo_line_to(cr, x, y);
      }
    }
    cairo_set_line_width(cr, 1.2);
    cairo_stroke(cr);
    cairo_rectangle(cr, legend_x, 36, 18, 4);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    text(cr, legend_x + 24, 42, t.label, 0.0);
    cairo_text_extents_t ext;
    cairo_text_extents(cr, t.label.c_str(), &ext);
    legend_x += 24 + ext.width + 30;
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  text(cr, left + w, spec.height - 8.0, "time (s)", 1.0);
  text(cr, 8, top - 4, spec.y_label, 0.0);

  return cairo_helpers::status_text(cairo_surface_write_to_png(surface.get(), path.c_str()));
}

}  // namespace hmp::plot
