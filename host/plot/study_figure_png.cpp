#include "host/plot/drawings.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "host/plot/cairo_helpers.hpp"

namespace hmp::plot {

namespace ch = cairo_helpers;
using study::envelope_name;
using study::GroupAnalysis;
using study::kEnvelopes;
using study::kInstruments;
using study::mapping_of_experiment;

namespace {

constexpr double kWidth = 1000, kHeight = 420, kPanelTop = 50, kPanelBottom = 350;
// Bar colours by envelope (square, triangle, analogue): grey, light and dark blue.
constexpr double kColours[3][3] = {{0.55, 0.55, 0.55}, {0.55, 0.72, 0.90}, {0.12, 0.30, 0.60}};

const GroupAnalysis* find(const std::vector<GroupAnalysis>& groups, int experiment, const char* instrument) {
  for (const GroupAnalysis& g : groups) {
    if (g.experiment == experiment && g.instrument == instrument) return &g;
  }
  return nullptr;
}

void panel(cairo_t* cr, const std::vector<GroupAnalysis>& groups, int experiment, double left, double width, int max_votes) {
  const double plot_left = left + 50, plot_width = width - 70, span = kPanelBottom - kPanelTop;
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 15);
  ch::text(cr, plot_left + plot_width / 2, kPanelTop - 22,
           fmt::format("Experiment {} ({} mapping)", experiment, mapping_of_experiment(experiment)), 0.5);
  cairo_set_font_size(cr, 11);
  const double step = ch::nice_step(max_votes, 5) < 1 ? 1 : ch::nice_step(max_votes, 5);
  cairo_set_line_width(cr, 1);
  for (double v = 0; v <= max_votes + 1e-9; v += step) {
    const double y = kPanelBottom - v / max_votes * span;
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
  ch::text(cr, 0, 0, "first-place votes", 0.5);
  cairo_restore(cr);
  const double group_width = plot_width / static_cast<double>(kInstruments.size());
  for (std::size_t i = 0; i < kInstruments.size(); ++i) {
    const double gx = plot_left + group_width * static_cast<double>(i);
    cairo_set_source_rgb(cr, 0, 0, 0);
    ch::text(cr, gx + group_width / 2, kPanelBottom + 18, kInstruments[i], 0.5);
    const GroupAnalysis* g = find(groups, experiment, kInstruments[i]);
    if (!g) {
      ch::text(cr, gx + group_width / 2, kPanelBottom - 8, "no data", 0.5);
      continue;
    }
    const double bar = group_width * 0.8 / 3;
    for (std::size_t e = 0; e < 3; ++e) {
      const double x = gx + group_width * 0.1 + bar * static_cast<double>(e);
      const double h = g->first_votes[e] / static_cast<double>(max_votes) * span;
      cairo_set_source_rgb(cr, kColours[e][0], kColours[e][1], kColours[e][2]);
      cairo_rectangle(cr, x + 2, kPanelBottom - h, bar - 4, h);
      cairo_fill(cr);
      const bool winner = std::find(g->copeland.winners.begin(), g->copeland.winners.end(), static_cast<int>(e)) !=
                          g->copeland.winners.end();
      cairo_set_source_rgb(cr, 0, 0, 0);
      ch::text(cr, x + bar / 2, kPanelBottom - h - 5, winner ? "*" : "", 0.5);
    }
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_move_to(cr, plot_left, kPanelBottom);
  cairo_line_to(cr, plot_left + plot_width, kPanelBottom);
  cairo_stroke(cr);
}

}  // namespace

std::string draw_study_figure_png(const std::string& path, const std::vector<GroupAnalysis>& groups) {
  int max_votes = 1;
  for (const GroupAnalysis& g : groups) {
    for (const int v : g.first_votes) max_votes = std::max(max_votes, v);
  }
  ch::Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(kWidth), static_cast<int>(kHeight)),
                      cairo_surface_destroy);
  ch::Context cr(cairo_create(surface.get()), cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  cairo_select_font_face(cr.get(), "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  panel(cr.get(), groups, 1, 0, kWidth / 2, max_votes);
  panel(cr.get(), groups, 2, kWidth / 2, kWidth / 2, max_votes);
  // Legend along the bottom.
  cairo_set_font_size(cr.get(), 12);
  double x = 120;
  for (std::size_t e = 0; e < 3; ++e) {
    cairo_set_source_rgb(cr.get(), kColours[e][0], kColours[e][1], kColours[e][2]);
    cairo_rectangle(cr.get(), x, kHeight - 38, 14, 14);
    cairo_fill(cr.get());
    cairo_set_source_rgb(cr.get(), 0, 0, 0);
    ch::text(cr.get(), x + 20, kHeight - 26, envelope_name(kEnvelopes[e]));
    x += 130;
  }
  ch::text(cr.get(), x + 20, kHeight - 26, "* Copeland winner (several: a tie)");
  cairo_surface_flush(surface.get());
  return cairo_helpers::status_text(cairo_surface_write_to_png(surface.get(), path.c_str()));
}

}  // namespace hmp::plot
