#pragma once
// PNG of error against cost, log–log, in one or more panels side by side (cairo, in the plot module): the
// plant simulator's work-precision figures (`hmp sim --work-precision`, the sim-work-precision benchmark).
// Each series is a polyline through its points with a dot on each; one point of a series may be ringed.
#include <string>
#include <utility>
#include <vector>

namespace hmp::output {

struct LogLogSeries {
  std::string label;
  std::vector<std::pair<double, double>> points;  // (x, y), both > 0 (others are left out)
  int ringed = -1;                                // index of a point to ring (the default setting), or −1
};

// One measured point: the series it belongs to (by its label; a series' points come one after the
// other), whether it is the one to ring, and where it lies (NaN where it has no value: left out).
struct LabelledPoint {
  std::string label;
  bool ringed = false;
  double x = 0, y = 0;
};

// The points as series, a new one wherever the label changes.
inline std::vector<LogLogSeries> series_of(const std::vector<LabelledPoint>& points) {
  std::vector<LogLogSeries> out;
  for (const LabelledPoint& p : points) {
    if (out.empty() || out.back().label != p.label) out.push_back({p.label, {}, -1});
    LogLogSeries& s = out.back();
    if (p.ringed) s.ringed = static_cast<int>(s.points.size());
    s.points.emplace_back(p.x, p.y);
  }
  return out;
}

struct LogLogPanel {
  std::string title;
  std::vector<LogLogSeries> series;  // coloured by their index, the same in every panel
};

struct LogLogPlotSpec {
  std::string title, x_label, y_label;
  // Dashed guide lines across every panel (a target), with their labels.
  std::vector<std::pair<double, std::string>> x_guides, y_guides;
  int panel_width = 420, height = 520;
};

// Throws BadInput if the file may not be written (see output_file.hpp).
void write_loglog_png(const std::string& path, const std::vector<LogLogPanel>& panels, const LogLogPlotSpec& spec,
                      bool force);

}  // namespace hmp::output
