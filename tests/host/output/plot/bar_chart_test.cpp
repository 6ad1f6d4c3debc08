// The plot module's bar chart (output/bar_chart.hpp, drawn in host/output/plot/): the PNG is read back with
// cairo and measured. Each series' bars are found by their colour; their heights must stand in the
// ratio of the values, each group's bars must lie in its own share of its panel, a group without data
// draws no bar, and an empty chart still writes a picture.
#include <gtest/gtest.h>

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <cstdlib>
#include <string>

#include "host/output/bar_chart.hpp"

namespace {

namespace output = hmp::output;

struct Rgb {
  int r, g, b;
};

// Where pixels of one colour are: columns spanned and the tallest column's count.
struct Extent {
  int min_x = 1 << 30, max_x = -1, height = 0;
};

class Picture {
 public:
  explicit Picture(const std::string& path) : surface_(cairo_image_surface_create_from_png(path.c_str())) {}
  ~Picture() { cairo_surface_destroy(surface_); }
  bool ok() const { return cairo_surface_status(surface_) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_); }
  int height() const { return cairo_image_surface_get_height(surface_); }
  Rgb at(int x, int y) const {
    const unsigned char* row = cairo_image_surface_get_data(surface_) + y * cairo_image_surface_get_stride(surface_);
    std::uint32_t px;
    std::memcpy(&px, row + 4 * x, 4);
    return {static_cast<int>(px >> 16 & 0xff), static_cast<int>(px >> 8 & 0xff), static_cast<int>(px & 0xff)};
  }
  // The extent of `colour` in rows [0, rows): the columns where it runs at least 8 pixels down (a bar;
  // the grey edges of anti-aliased text never do), and the longest such run.
  Extent find(Rgb colour, int rows) const {
    Extent e;
    for (int x = 0; x < width(); ++x) {
      int run = 0, longest = 0;
      for (int y = 0; y < rows; ++y) {
        const Rgb p = at(x, y);
        // ±1 per channel: cairo rounds its colours through 16 bits
        const bool same =
            std::abs(p.r - colour.r) <= 1 && std::abs(p.g - colour.g) <= 1 && std::abs(p.b - colour.b) <= 1;
        run = same ? run + 1 : 0;
        longest = std::max(longest, run);
      }
      if (longest < 8) continue;
      e.min_x = std::min(e.min_x, x);
      e.max_x = std::max(e.max_x, x);
      e.height = std::max(e.height, longest);
    }
    return e;
  }

 private:
  cairo_surface_t* surface_;
};

// The series colours as 8-bit values (grey, light blue, dark blue: docs/study.md's figure).
Rgb byte(double r, double g, double b) {
  return {static_cast<int>(std::lround(r * 255)), static_cast<int>(std::lround(g * 255)),
          static_cast<int>(std::lround(b * 255))};
}
const Rgb kSeries[3] = {byte(0.55, 0.55, 0.55), byte(0.55, 0.72, 0.90), byte(0.12, 0.30, 0.60)};

std::string temp_png(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::string("hmp-bar-") + name + ".png")).string();
}

output::BarChartSpec three_series() {
  output::BarChartSpec spec;
  spec.series = {"square", "triangle", "analogue"};
  spec.y_label = "votes";
  spec.mark_note = "* winner";
  return spec;
}

TEST(BarChart, BarHeightsStandInTheRatioOfTheValues) {
  const std::string path = temp_png("ratio");
  output::BarPanel panel{"one panel", {{"a", {1, 2, 4}, {false, false, true}}, {"b", {}, {}}}};
  output::write_bar_chart_png(path, {panel}, three_series(), true);
  const Picture png(path);
  ASSERT_TRUE(png.ok());
  const int plot_rows = png.height() - 50;  // above the legend's squares
  Extent e[3];
  for (int s = 0; s < 3; ++s) e[s] = png.find(kSeries[s], plot_rows);
  ASSERT_GT(e[2].height, 100) << "the tallest bar is too short to measure";
  EXPECT_NEAR(e[0].height * 4.0 / e[2].height, 1.0, 0.05);
  EXPECT_NEAR(e[1].height * 2.0 / e[2].height, 1.0, 0.05);
  // Side by side in series order, all in the left half: group "b" has no data and no bar.
  EXPECT_LT(e[0].max_x, e[1].min_x);
  EXPECT_LT(e[1].max_x, e[2].min_x);
  EXPECT_LT(e[2].max_x, png.width() / 2);
  // The legend has one square per series, below the plot.
  for (int s = 0; s < 3; ++s) {
    const Extent all = png.find(kSeries[s], png.height());
    EXPECT_GT(all.height, 0);
  }
  std::remove(path.c_str());
}

TEST(BarChart, EachPanelDrawsInItsOwnShare) {
  const std::string path = temp_png("panels");
  output::BarPanel left{"left", {{"a", {3, 0, 0}, {}}}};
  output::BarPanel right{"right", {{"a", {0, 0, 3}, {}}}};
  output::write_bar_chart_png(path, {left, right}, three_series(), true);
  const Picture png(path);
  ASSERT_TRUE(png.ok());
  const Extent grey = png.find(kSeries[0], png.height() - 50), dark = png.find(kSeries[2], png.height() - 50);
  EXPECT_LT(grey.max_x, png.width() / 2);
  EXPECT_GT(dark.min_x, png.width() / 2);
  EXPECT_EQ(grey.height, dark.height);                           // equal values, equal bars across panels (one scale)
  EXPECT_EQ(png.find(kSeries[1], png.height() - 50).max_x, -1);  // zero draws nothing
  std::remove(path.c_str());
}

TEST(BarChart, AnEmptyChartIsStillAPicture) {
  const std::string path = temp_png("empty");
  output::write_bar_chart_png(path, {}, {}, true);
  const Picture png(path);
  ASSERT_TRUE(png.ok());
  EXPECT_GT(png.width(), 0);
  std::remove(path.c_str());
}

}  // namespace
