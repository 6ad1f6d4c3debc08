#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "host/output/plot/cairo_helpers.hpp"
#include "host/output/plot/drawings.hpp"

namespace hmp::plot {

using output::LogLogPanel;
using output::LogLogPlotSpec;
using output::LogLogSeries;

namespace {

using cairo_helpers::Context;
using cairo_helpers::Surface;
using cairo_helpers::text;

// Series colours by index (Okabe–Ito, distinguishable with the common colour-vision deficiencies).
constexpr double kColours[][3] = {{0.90, 0.62, 0.00}, {0.34, 0.71, 0.91}, {0.00, 0.62, 0.45}, {0.80, 0.47, 0.65},
                                  {0.00, 0.45, 0.70}, {0.84, 0.37, 0.00}, {0.10, 0.10, 0.10}, {0.60, 0.60, 0.60}};
constexpr int kColourCount = sizeof kColours / sizeof kColours[0];

bool usable(const std::pair<double, double>& p) {
  return std::isfinite(p.first) && std::isfinite(p.second) && p.first > 0 && p.second > 0;
}

// Whole decades around every usable point of every panel (and the guides).
void decades(const std::vector<LogLogPanel>& panels, const LogLogPlotSpec& spec, bool x, int& lo, int& hi) {
  double mn = std::numeric_limits<double>::infinity(), mx = -std::numeric_limits<double>::infinity();
  for (const LogLogPanel& p : panels)
    for (const LogLogSeries& s : p.series)
      for (const auto& pt : s.points)
        if (usable(pt)) {
          const double v = std::log10(x ? pt.first : pt.second);
          mn = std::min(mn, v);
          mx = std::max(mx, v);
        }
  for (const auto& g : x ? spec.x_guides : spec.y_guides)
    if (g.first > 0) {
      mn = std::min(mn, std::log10(g.first));
      mx = std::max(mx, std::log10(g.first));
    }
  if (!(mn <= mx)) mn = mx = 0;
  lo = static_cast<int>(std::floor(mn));
  hi = std::max(lo + 1, static_cast<int>(std::ceil(mx)));
}

}  // namespace

std::string draw_loglog_png(const std::string& path, const std::vector<LogLogPanel>& panels,
                            const LogLogPlotSpec& spec) {
  const int columns = std::max<int>(1, static_cast<int>(panels.size()));
  const double left = 70, right = 20, top = 70, bottom = 60, gap = 30, legend = 200;
  const int width = static_cast<int>(left + columns * spec.panel_width + (columns - 1) * gap + legend + right);
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, spec.height), cairo_surface_destroy);
  Context context(cairo_create(surface.get()), cairo_destroy);
  cairo_t* cr = context.get();
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  int x0, x1, y0, y1;
  decades(panels, spec, true, x0, x1);
  decades(panels, spec, false, y0, y1);
  const double pw = spec.panel_width, ph = spec.height - top - bottom;

  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_font_size(cr, 15);
  text(cr, left, 24, spec.title);
  cairo_set_font_size(cr, 12);
  text(cr, left + (width - left - legend) / 2, spec.height - 15, spec.x_label, 0.5);
  cairo_save(cr);
  cairo_translate(cr, 18, top + ph / 2);
  cairo_rotate(cr, -M_PI / 2);
  text(cr, 0, 0, spec.y_label, 0.5);
  cairo_restore(cr);

  for (int c = 0; c < columns; ++c) {
    const double pl = left + c * (pw + gap);
    auto px = [&](double v) { return pl + (std::log10(v) - x0) / (x1 - x0) * pw; };
    auto py = [&](double v) { return top + (y1 - std::log10(v)) / (y1 - y0) * ph; };
    cairo_set_line_width(cr, 1);
    for (int d = x0; d <= x1; ++d) {
      cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
      cairo_move_to(cr, px(std::pow(10.0, d)), top);
      cairo_line_to(cr, px(std::pow(10.0, d)), top + ph);
      cairo_stroke(cr);
      cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
      text(cr, px(std::pow(10.0, d)), top + ph + 16, "1e" + std::to_string(d), 0.5);
    }
    for (int d = y0; d <= y1; ++d) {
      cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
      cairo_move_to(cr, pl, py(std::pow(10.0, d)));
      cairo_line_to(cr, pl + pw, py(std::pow(10.0, d)));
      cairo_stroke(cr);
      if (c == 0) {
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        text(cr, pl - 6, py(std::pow(10.0, d)) + 4, "1e" + std::to_string(d), 1.0);
      }
    }
    const double dashes[] = {6, 4};
    cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
    cairo_set_dash(cr, dashes, 2, 0);
    for (const auto& g : spec.y_guides) {
      cairo_move_to(cr, pl, py(g.first));
      cairo_line_to(cr, pl + pw, py(g.first));
      cairo_stroke(cr);
    }
    for (const auto& g : spec.x_guides) {
      cairo_move_to(cr, px(g.first), top);
      cairo_line_to(cr, px(g.first), top + ph);
      cairo_stroke(cr);
    }
    cairo_set_dash(cr, nullptr, 0, 0);
    for (const auto& g : spec.y_guides) text(cr, pl + 4, py(g.first) - 4, g.second);
    for (const auto& g : spec.x_guides) text(cr, px(g.first) - 4, top + 14, g.second, 1.0);  // left of its line
    const LogLogPanel& panel = panels[static_cast<std::size_t>(c)];
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_set_font_size(cr, 13);
    text(cr, pl + pw / 2, top - 10, panel.title, 0.5);
    cairo_set_font_size(cr, 12);
    cairo_save(cr);
    cairo_rectangle(cr, pl, top, pw, ph);
    cairo_clip(cr);
    for (std::size_t si = 0; si < panel.series.size(); ++si) {
      const LogLogSeries& s = panel.series[si];
      const double* rgb = kColours[si % kColourCount];
      cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
      cairo_set_line_width(cr, 2);
      bool first = true;
      for (const auto& pt : s.points) {
        if (!usable(pt)) continue;
        if (first)
          cairo_move_to(cr, px(pt.first), py(pt.second));
        else
          cairo_line_to(cr, px(pt.first), py(pt.second));
        first = false;
      }
      cairo_stroke(cr);
      for (std::size_t k = 0; k < s.points.size(); ++k) {
        const auto& pt = s.points[k];
        if (!usable(pt)) continue;
        cairo_new_sub_path(cr);
        cairo_arc(cr, px(pt.first), py(pt.second), 3.5, 0, 2 * M_PI);
        cairo_fill(cr);
        if (static_cast<int>(k) == s.ringed) {
          cairo_set_source_rgb(cr, 0, 0, 0);
          cairo_set_line_width(cr, 1.5);
          cairo_new_sub_path(cr);
          cairo_arc(cr, px(pt.first), py(pt.second), 8, 0, 2 * M_PI);
          cairo_stroke(cr);
          cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        }
      }
    }
    cairo_restore(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, pl, top, pw, ph);
    cairo_stroke(cr);
  }
  // Legend: the first panel's series names (every panel has the same series in the same order).
  if (!panels.empty()) {
    const double lx = left + columns * (pw + gap);
    for (std::size_t si = 0; si < panels[0].series.size(); ++si) {
      const double* rgb = kColours[si % kColourCount];
      const double ly = top + 10 + 22 * static_cast<double>(si);
      cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
      cairo_rectangle(cr, lx, ly - 9, 18, 10);
      cairo_fill(cr);
      cairo_set_source_rgb(cr, 0, 0, 0);
      text(cr, lx + 24, ly, panels[0].series[si].label);
    }
    const double ly = top + 20 + 22 * static_cast<double>(panels[0].series.size());
    text(cr, lx, ly, "ring: the default");
  }
  return cairo_helpers::status_text(cairo_surface_write_to_png(surface.get(), path.c_str()));
}

}  // namespace hmp::plot
