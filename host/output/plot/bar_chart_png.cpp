#include <algorithm>

#include <fmt/format.h>

#include "host/output/plot/cairo_helpers.hpp"
#include "host/output/plot/drawings.hpp"

namespace hmp::plot {

namespace ch = cairo_helpers;
using output::BarChartSpec;
using output::BarGroup;
using output::BarPanel;

namespace {

constexpr double kWidth = 1000, kHeight = 420, kPanelTop = 50, kPanelBottom = 350;
// Bar colours by series, cycled: grey, light and dark blue (the study's square, triangle, analogue).
constexpr double kColours[3][3] = {{0.55, 0.55, 0.55}, {0.55, 0.72, 0.90}, {0.12, 0.30, 0.60}};

const double* colour(std::size_t series) { return kColours[series % 3]; }

void panel(cairo_t* cr, const BarPanel& p, const BarChartSpec& spec, double left, double width, double max_value) {
  const double plot_left = left + 50, plot_width = width - 70, span = kPanelBottom - kPanelTop;
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 15);
  ch::text(cr, plot_left + plot_width / 2, kPanelTop - 22, p.title, 0.5);
  cairo_set_font_size(cr, 11);
  const double step = ch::nice_step(max_value, 5) < 1 ? 1 : ch::nice_step(max_value, 5);
  cairo_set_line_width(cr, 1);
  for (double v = 0; v <= max_value + 1e-9; v += step) {
    const double y = kPanelBottom - v / max_value * span;
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, plot_left, y);
    cairo_line_to(cr, plot_left + plot_width, y);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    ch::text(cr, plot_left - 6, y + 4, fmt::format("{}", static_cast<int>(v)), 1.0);
  }
  cairo_save(cr);
  cairo_translate(cr, left + 14, kPanelTop + span / 2);
  cairo_rotate(cr, -1.5707963267948966);
  ch::text(cr, 0, 0, spec.y_label, 0.5);
  cairo_restore(cr);
  const double group_width = plot_width / static_cast<double>(std::max<std::size_t>(1, p.groups.size()));
  const double bar = group_width * 0.8 / static_cast<double>(std::max<std::size_t>(1, spec.series.size()));
  for (std::size_t i = 0; i < p.groups.size(); ++i) {
    const BarGroup& g = p.groups[i];
    const double gx = plot_left + group_width * static_cast<double>(i);
    cairo_set_source_rgb(cr, 0, 0, 0);
    ch::text(cr, gx + group_width / 2, kPanelBottom + 18, g.label, 0.5);
    if (g.values.empty()) {
      ch::text(cr, gx + group_width / 2, kPanelBottom - 8, "no data", 0.5);
      continue;
    }
    for (std::size_t e = 0; e < g.values.size(); ++e) {
      const double x = gx + group_width * 0.1 + bar * static_cast<double>(e);
      const double h = g.values[e] / max_value * span;
      cairo_set_source_rgb(cr, colour(e)[0], colour(e)[1], colour(e)[2]);
      cairo_rectangle(cr, x + 2, kPanelBottom - h, bar - 4, h);
      cairo_fill(cr);
      cairo_set_source_rgb(cr, 0, 0, 0);
      ch::text(cr, x + bar / 2, kPanelBottom - h - 5, e < g.marked.size() && g.marked[e] ? "*" : "", 0.5);
    }
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_move_to(cr, plot_left, kPanelBottom);
  cairo_line_to(cr, plot_left + plot_width, kPanelBottom);
  cairo_stroke(cr);
}

}  // namespace

std::string draw_bar_chart_png(const std::string& path, const std::vector<BarPanel>& panels, const BarChartSpec& spec) {
  double max_value = 1;
  for (const BarPanel& p : panels) {
    for (const BarGroup& g : p.groups) {
      for (const double v : g.values) max_value = std::max(max_value, v);
    }
  }
  ch::Surface surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(kWidth), static_cast<int>(kHeight)),
      cairo_surface_destroy);
  ch::Context cr(cairo_create(surface.get()), cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  cairo_select_font_face(cr.get(), "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  const double panel_width = kWidth / static_cast<double>(std::max<std::size_t>(1, panels.size()));
  for (std::size_t i = 0; i < panels.size(); ++i) {
    panel(cr.get(), panels[i], spec, panel_width * static_cast<double>(i), panel_width, max_value);
  }
  // Legend along the bottom.
  cairo_set_font_size(cr.get(), 12);
  double x = 120;
  for (std::size_t e = 0; e < spec.series.size(); ++e) {
    cairo_set_source_rgb(cr.get(), colour(e)[0], colour(e)[1], colour(e)[2]);
    cairo_rectangle(cr.get(), x, kHeight - 38, 14, 14);
    cairo_fill(cr.get());
    cairo_set_source_rgb(cr.get(), 0, 0, 0);
    ch::text(cr.get(), x + 20, kHeight - 26, spec.series[e]);
    x += 130;
  }
  if (!spec.mark_note.empty()) ch::text(cr.get(), x + 20, kHeight - 26, spec.mark_note);
  cairo_surface_flush(surface.get());
  return cairo_helpers::status_text(cairo_surface_write_to_png(surface.get(), path.c_str()));
}

}  // namespace hmp::plot
