// `hmp sim`: the commanded force it prints is the device's vibration (equal to `hmp render` of the same
// window, an independent path through the host's own engine run), and the actual force follows it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::string kHmp = std::string(HMP_BIN_DIR) + "/hmp";
const std::string kSong = std::string(HMP_REPO_DIR) + "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid";

int run(const std::string& args) { return std::system((kHmp + " " + args + " 2>/dev/null").c_str()); }

std::vector<std::vector<double>> read_csv(const std::string& path, std::string& header) {
  std::ifstream in(path);
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> row;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

TEST(SimCli, CommandedEqualsRenderAndActualFollows) {
  const std::string sim_csv = ::testing::TempDir() + "hmp-sim-test.csv";
  const std::string render_csv = ::testing::TempDir() + "hmp-render-test.csv";
  ASSERT_EQ(run("sim '" + kSong + "' --track flute --from 0 --to 4 --peak-force 2 -f --out " + sim_csv), 0);
  ASSERT_EQ(run("render '" + kSong + "' --track flute --from 0 --to 4 -f --out " + render_csv), 0);
  std::string sim_header, render_header;
  const auto sim = read_csv(sim_csv, sim_header);
  const auto render = read_csv(render_csv, render_header);
  EXPECT_EQ(sim_header, "t_s,commanded_n,actual_n,reported_n,min_tension_n,max_tension_n");
  ASSERT_EQ(sim.size(), 4000u);
  ASSERT_EQ(render.size(), sim.size());
  double worst = 0, energy = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    ASSERT_EQ(sim[i].size(), 6u);
    EXPECT_NEAR(sim[i][0], render[i][0], 1e-6);
    worst = std::max(worst, std::fabs(sim[i][1] - 2.0 * render[i][1]));
    energy += sim[i][1] * sim[i][1];
    EXPECT_GT(sim[i][4], 0.0) << "a string went slack at " << sim[i][0];
  }
  EXPECT_LT(worst, 1e-5) << "commanded = the device's vibration × peak = render × 2 N";
  ASSERT_GT(energy, 1.0) << "the window has notes";
  // The actual force, one tick later (the device's delay is ~1.3 ticks), over 50 ms windows: its RMS
  // within 10% of the commanded RMS wherever something is commanded.
  const std::size_t w = 50;
  int windows = 0;
  for (std::size_t a = 0; a + w + 1 < sim.size(); a += w) {
    double c = 0, x = 0;
    for (std::size_t i = a; i < a + w; ++i) {
      c += sim[i][1] * sim[i][1];
      x += sim[i + 1][2] * sim[i + 1][2];
    }
    c = std::sqrt(c / w);
    x = std::sqrt(x / w);
    if (c < 0.2) continue;
    ++windows;
    EXPECT_NEAR(x / c, 1.0, 0.1) << "window at " << sim[a][0] << " s";
  }
  EXPECT_GT(windows, 10);
  std::remove(sim_csv.c_str());
  std::remove(render_csv.c_str());
}

TEST(SimCli, RejectsBadOptions) {
  EXPECT_EQ(run("sim '" + kSong + "' --track flute --out x.wav"), 2 << 8);
  EXPECT_EQ(run("sim '" + kSong + "' --track flute --integrator euler --out -"), 2 << 8);
  EXPECT_EQ(run("sim '" + kSong + "' --track flute --peak-force 0 --out -"), 2 << 8);
}

}  // namespace
