#pragma once
// Small pieces the plot module's pictures draw with: owning cairo handles, axis tick spacing, aligned
// text, cairo's status as our error text.
#include <cairo.h>

#include <cmath>
#include <memory>
#include <string>

namespace hmp::plot::cairo_helpers {

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

// A "nice" spacing (1, 2 or 5 × 10^k) giving about `target` divisions of `span`.
inline double nice_step(double span, int target) {
  const double raw = span / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (raw <= m * mag) return m * mag;
  }
  return 10 * mag;
}

// Text at (x, y) baseline; align 0 = left, 0.5 = centred, 1 = right.
inline void text(cairo_t* cr, double x, double y, const std::string& s, double align = 0.0) {
  cairo_text_extents_t ext;
  cairo_text_extents(cr, s.c_str(), &ext);
  cairo_move_to(cr, x - align * ext.width, y);
  cairo_show_text(cr, s.c_str());
}

// "" for success, else cairo's own words.
inline std::string status_text(cairo_status_t status) {
  return status == CAIRO_STATUS_SUCCESS ? std::string() : std::string(cairo_status_to_string(status));
}

}  // namespace hmp::plot::cairo_helpers
