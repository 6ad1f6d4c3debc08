// `hmp render` of real tracks equals an independent reference sample for sample (to 1e-4 of full scale):
// the notes come from `hmp info --json --notes`; frequency/amplitude from design §5 (Eq. 5–7 as linear
// interpolation between the song's lowest and highest pitched key, dB → linear), envelopes from design §6 Table 1
// (values typed in here from the spec), ticks from design §6 "Ticks", voices summed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/reference_envelope.hpp"

namespace {

const std::string kDemo = std::string(HMP_REPO_DIR) + "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid";

std::string run(const std::string& args) {
  const std::string cmd = std::string(HMP_BIN_DIR) + "/hmp " + args;
  std::FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  if (!p) return out;
  char buf[1 << 16];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  EXPECT_EQ(pclose(p), 0) << cmd;
  return out;
}

struct RefNote {
  int key;
  double start_s, end_s;
};

hmp::envelope::Adsr table1(const std::string& name) {
  hmp::envelope::Adsr a;
  if (name == "flute") a = {75, 0, 60, 1.0f, 0.01f, hmp::envelope::Shape::adsr};
  if (name == "contrabass") a = {55, 355, 225, 0.5274f, 0.01f, hmp::envelope::Shape::adsr};
  if (name == "harpsichord") a = {55, 0, 55, 1.0f, 0.1739f, hmp::envelope::Shape::adsr};
  return a;
}

// Reference signal of one track over [0, ticks) at 1 kHz, default ranges 50–250 Hz, 7.5–30 dB, 2 ms fade.
// `keys`: the song's pitched keys (the 2015 paper's k_min and k_max "in the song").
std::vector<double> reference(const std::vector<RefNote>& notes, const std::set<int>& keys,
                              const hmp::envelope::Adsr& env, std::size_t ticks) {
  const double kmin = *keys.begin(), kmax = *keys.rbegin();
  std::vector<double> y(ticks, 0.0);
  for (const auto& n : notes) {
    const double pos = kmax > kmin ? (n.key - kmin) / (kmax - kmin) : 0.5;
    const double f = 50 + 200 * pos;
    const double a = std::pow(10.0, (7.5 + 22.5 * pos - 30) / 20);
    const auto start = static_cast<long long>(std::floor(n.start_s * 1000 + 0.5 + 1e-9));
    const auto end = static_cast<long long>(std::floor(n.end_s * 1000 + 0.5 + 1e-9));
    const long long count = std::max(1LL, end - start);
    for (long long i = 0; i < count && start + i < static_cast<long long>(ticks); ++i) {
      const double x_ms = static_cast<double>(i);
      y[static_cast<std::size_t>(start + i)] +=
          hmp::reference::envelope(env, a, static_cast<double>(count), x_ms, 2.0) *
          std::sin(2 * std::numbers::pi * f * x_ms / 1000);
    }
  }
  return y;
}

void check_track(const std::string& name, int expected_track) {
  const auto info = nlohmann::json::parse(run("info --json --notes '" + kDemo + "'"));
  std::vector<RefNote> notes;
  std::set<int> song_keys;
  for (const auto& n : info["notes"]) {
    if (n["track"] == expected_track) notes.push_back({n["key"], n["start_s"], n["end_s"]});
    if (n["channel"] != 10) song_keys.insert(n["key"].get<int>());  // channel 10's keys are drums
  }
  ASSERT_GT(notes.size(), 100u);

  const std::string csv = run("render '" + kDemo + "' --track " + name + " --out -");
  std::vector<double> got;
  std::size_t pos = csv.find('\n') + 1;
  while (pos < csv.size()) {
    const std::size_t comma = csv.find(',', pos), eol = csv.find('\n', pos);
    got.push_back(std::strtod(csv.c_str() + comma + 1, nullptr));
    pos = eol + 1;
  }
  ASSERT_GT(got.size(), 100000u);
  const auto ref = reference(notes, song_keys, table1(name), got.size());
  double worst = 0;
  std::size_t worst_at = 0, overlaps = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (std::abs(ref[i]) > 1.0) {  // the limiter may act here; the reference has none
      ++overlaps;
      continue;
    }
    const double e = std::abs(got[i] - ref[i]);
    if (e > worst) worst = e, worst_at = i;
  }
  EXPECT_LE(worst, 1e-4) << name << ": worst at tick " << worst_at << " got " << got[worst_at] << " ref "
                         << ref[worst_at];
  EXPECT_EQ(overlaps, 0u) << "reference exceeded full scale (limiter territory)";
  ::testing::Test::RecordProperty(name + "_max_abs_error", std::to_string(worst));
  std::printf("%s: %zu samples, max |error| = %.3g\n", name.c_str(), got.size(), worst);
}

TEST(RenderReference, DemoFluteMatchesSpec) { check_track("flute", 1); }
TEST(RenderReference, DemoContrabassMatchesSpec) { check_track("contrabass", 6); }

}  // namespace
