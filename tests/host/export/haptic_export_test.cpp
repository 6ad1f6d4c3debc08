// .ahap and .haptic exports (host/export/): (1) a schema check written from Apple's and Meta's public
// descriptions of the formats (required keys, types, ranges, AHAP limits); (2) the envelope an .ahap
// describes, rebuilt (linear between control points × event intensity) and sampled at the tick rate,
// against the track's per-tick envelope computed from shared/envelope; (3) extreme and hostile inputs.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/export/haptic_export.hpp"
#include "host/export/json_writers.hpp"
#include "host/haptics/track_window.hpp"
#include "tests/support/midi_builder.hpp"

namespace {

using nlohmann::json;
namespace ex = hmp::exporting;
namespace fs = std::filesystem;

const std::string kDemo = std::string(HMP_REPO_DIR) + "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid";

struct Loaded {
  hmp::haptics::HapticOptions opts;
  hmp::haptics::TrackWindow w;
  ex::ExportSpec spec() const { return {&w.haptic, &opts, w.first_tick, w.end_tick, "test"}; }
};

Loaded load(const std::string& song, const std::string& track, std::optional<double> from = {},
            std::optional<double> to = {}) {
  Loaded l;
  l.w = hmp::haptics::load_track_window(song, track, l.opts, from, to, [](const std::string&) {});
  return l;
}

bool in01(const json& v) { return v.is_number() && v.get<double>() >= 0.0 && v.get<double>() <= 1.0; }

// AHAP rules (Apple, "Representing haptic patterns in AHAP files" and CHHapticPattern keys).
void check_ahap(const json& j) {
  ASSERT_TRUE(j.is_object());
  ASSERT_TRUE(j.contains("Version") && j["Version"].is_number());
  ASSERT_TRUE(j.contains("Pattern") && j["Pattern"].is_array());
  if (j.contains("Metadata")) {
    ASSERT_TRUE(j["Metadata"].is_object());
  }
  double last_time = 0;
  for (const json& e : j["Pattern"]) {
    ASSERT_TRUE(e.is_object());
    ASSERT_EQ(e.size(), 1u);
    if (e.contains("Event")) {
      const json& ev = e["Event"];
      ASSERT_TRUE(ev["Time"].is_number());
      ASSERT_GE(ev["Time"].get<double>(), last_time - 1e-9) << "times non-decreasing";
      last_time = ev["Time"].get<double>();
      ASSERT_EQ(ev["EventType"], "HapticContinuous");
      ASSERT_TRUE(ev["EventDuration"].is_number());
      EXPECT_GT(ev["EventDuration"].get<double>(), 0.0);
      EXPECT_LE(ev["EventDuration"].get<double>(), ex::kAhapMaxEventS + 1e-9);
      ASSERT_TRUE(ev["EventParameters"].is_array());
      bool intensity = false, sharpness = false;
      for (const json& p : ev["EventParameters"]) {
        ASSERT_TRUE(p["ParameterID"].is_string());
        EXPECT_TRUE(in01(p["ParameterValue"]));
        intensity |= p["ParameterID"] == "HapticIntensity";
        sharpness |= p["ParameterID"] == "HapticSharpness";
      }
      EXPECT_TRUE(intensity && sharpness);
    } else {
      ASSERT_TRUE(e.contains("ParameterCurve"));
      const json& c = e["ParameterCurve"];
      ASSERT_EQ(c["ParameterID"], "HapticIntensityControl");
      ASSERT_TRUE(c["Time"].is_number());
      ASSERT_GE(c["Time"].get<double>(), last_time - 1e-9);
      last_time = c["Time"].get<double>();
      const json& pts = c["ParameterCurveControlPoints"];
      ASSERT_TRUE(pts.is_array());
      EXPECT_GE(pts.size(), 1u);
      EXPECT_LE(pts.size(), ex::kAhapMaxCurvePoints);
      double pt = -1;
      for (const json& p : pts) {
        ASSERT_TRUE(p["Time"].is_number());
        EXPECT_GE(p["Time"].get<double>(), pt) << "control point times non-decreasing";
        pt = p["Time"].get<double>();
        EXPECT_TRUE(in01(p["ParameterValue"]));
      }
    }
  }
}

// .haptic rules (Meta haptic-file-spec: version, metadata, signals.continuous.envelopes).
void check_meta(const json& j) {
  ASSERT_TRUE(j["version"].is_object());
  for (const char* k : {"major", "minor", "patch"}) ASSERT_TRUE(j["version"][k].is_number_integer());
  ASSERT_TRUE(j["metadata"].is_object());
  const json& env = j["signals"]["continuous"]["envelopes"];
  ASSERT_TRUE(env["amplitude"].is_array());
  ASSERT_TRUE(env["frequency"].is_array());
  for (const char* key : {"amplitude", "frequency"}) {
    double last = -1;
    for (const json& p : env[key]) {
      ASSERT_TRUE(p["time"].is_number());
      EXPECT_GT(p["time"].get<double>(), last) << "times increasing";
      last = p["time"].get<double>();
      EXPECT_TRUE(in01(p[key]));
    }
  }
}

// The per-tick envelope of the track over the window (sum of the notes' envelopes, as the engine applies them).
std::vector<double> track_envelope(const Loaded& l) {
  std::vector<double> y(l.w.end_tick - l.w.first_tick, 0.0);
  for (const auto& hn : l.w.haptic.notes) {
    const auto env = ex::note_envelope(l.w.haptic, l.opts, hn.note);
    for (std::uint64_t k = std::max(hn.note.start_tick, l.w.first_tick);
         k < std::min(hn.note.start_tick + hn.note.duration_ticks, l.w.end_tick); ++k)
      y[k - l.w.first_tick] += static_cast<double>(env.at(static_cast<std::uint32_t>(k - hn.note.start_tick)));
  }
  return y;
}

// What an .ahap player would do: each event's intensity times its curves, linear between control points.
std::vector<double> rebuild_ahap(const json& j, std::size_t ticks, double hz) {
  std::vector<double> y(ticks, 0.0);
  const json& pat = j["Pattern"];
  for (std::size_t i = 0; i < pat.size(); ++i) {
    if (!pat[i].contains("Event")) continue;
    const json& ev = pat[i]["Event"];
    const double t0 = ev["Time"], dur = ev["EventDuration"];
    const double inten = ev["EventParameters"][0]["ParameterValue"];
    std::vector<std::pair<double, double>> pts;  // absolute time, value
    for (std::size_t k = i + 1; k < pat.size() && pat[k].contains("ParameterCurve"); ++k) {
      const json& c = pat[k]["ParameterCurve"];
      for (const json& p : c["ParameterCurveControlPoints"])
        pts.emplace_back(c["Time"].get<double>() + p["Time"].get<double>(), p["ParameterValue"].get<double>());
    }
    for (auto k = static_cast<std::size_t>(std::llround(t0 * hz)); k < ticks && static_cast<double>(k) / hz < t0 + dur - 1e-9; ++k) {
      const double t = static_cast<double>(k) / hz;
      double v = pts.empty() ? 1.0 : pts.back().second;
      for (std::size_t p = 0; p + 1 < pts.size(); ++p)
        if (t >= pts[p].first - 1e-9 && t <= pts[p + 1].first + 1e-9) {
          const double span = pts[p + 1].first - pts[p].first;
          v = span > 0 ? pts[p].second + (pts[p + 1].second - pts[p].second) * (t - pts[p].first) / span : pts[p + 1].second;
          break;
        }
      y[k] += inten * v;
    }
  }
  return y;
}

int run_hmp(const std::string& args, std::string* err = nullptr) {
  const std::string errfile = (fs::temp_directory_path() / "hmp-export-test-stderr.txt").string();
  const int rc = std::system((std::string(HMP_BIN_DIR) + "/hmp render " + args + " 2>" + errfile + " </dev/null").c_str());
  if (err) {
    std::ifstream f(errfile);
    *err = std::string(std::istreambuf_iterator<char>(f), {});
  }
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string write_midi(const std::string& name, const midi_test::Bytes& bytes) {
  const fs::path p = fs::temp_directory_path() / name;
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return p.string();
}

TEST(HapticExport, DemoSongPassesBothSchemas) {
  const Loaded l = load(kDemo, "flute");
  const json a = ex::ahap_json(l.spec());
  check_ahap(a);
  EXPECT_GT(a["Pattern"].size(), 100u);
  check_meta(ex::meta_haptic_json(l.spec()));
}

TEST(HapticExport, AhapEnvelopeMatchesTheTrackEnvelope) {
  for (const char* track : {"flute", "7", "contrabass"}) {
    const Loaded l = load(kDemo, track, 0.0, 60.0);
    const std::vector<double> want = track_envelope(l);
    const std::vector<double> got = rebuild_ahap(ex::ahap_json(l.spec()), want.size(), l.opts.tick_hz);
    double max_err = 0, sum_err = 0;
    std::size_t worst = 0;
    for (std::size_t k = 0; k < want.size(); ++k) {
      if (std::abs(got[k] - want[k]) > max_err) worst = k;
      max_err = std::max(max_err, std::abs(got[k] - want[k]));
      sum_err += std::abs(got[k] - want[k]);
    }
    std::printf("worst tick %zu: got %.4f want %.4f (prev %.4f/%.4f next %.4f/%.4f)\n", worst, got[worst], want[worst],
                got[worst ? worst - 1 : 0], want[worst ? worst - 1 : 0], got[worst + 1], want[worst + 1]);
    std::printf("%s: max |error| %.4f, mean %.6f of full scale over %zu ticks\n", track, max_err,
                sum_err / static_cast<double>(want.size()), want.size());
    EXPECT_LT(max_err, 0.02) << track;  // 0.01 of each note's peak (kRefineTolerance), overlaps add
    EXPECT_LT(sum_err / static_cast<double>(want.size()), 0.001) << track;
  }
}

TEST(HapticExport, MetaAmplitudeFollowsTheSummedEnvelope) {
  const Loaded l = load(kDemo, "flute", 0.0, 60.0);
  const std::vector<double> want = track_envelope(l);
  const json j = ex::meta_haptic_json(l.spec());
  for (const json& p : j["signals"]["continuous"]["envelopes"]["amplitude"]) {
    const auto k = static_cast<std::size_t>(std::llround(p["time"].get<double>() * l.opts.tick_hz));
    ASSERT_LT(k, want.size());
    EXPECT_NEAR(p["amplitude"].get<double>(), want[k], 1e-6);
  }
}

TEST(HapticExport, NoteLongerThan30sIsSplit) {
  midi_test::Events t;
  t.tempo(0, 500000).program(0, 0, 73).on(0, 0, 72).off(480 * 140, 0, 72).end();  // 70 s at 120 bpm
  const std::string song = write_midi("hmp-export-long.mid", midi_test::smf(0, 480, {t}));
  const Loaded l = load(song, "0");
  const json a = ex::ahap_json(l.spec());
  check_ahap(a);
  double total = 0;
  int events = 0;
  for (const json& e : a["Pattern"])
    if (e.contains("Event")) {
      total += e["Event"]["EventDuration"].get<double>();
      ++events;
    }
  EXPECT_EQ(events, 3);
  EXPECT_NEAR(total, 70.0, 1e-6);
}

TEST(HapticExport, ThousandsOfNotes) {
  midi_test::Events t;
  t.tempo(0, 500000).program(0, 0, 73);
  for (int i = 0; i < 5000; ++i) t.on(i == 0 ? 0 : 24, 0, 48 + i % 36).off(24, 0, 48 + i % 36);  // 25 ms each
  t.end();
  const std::string song = write_midi("hmp-export-many.mid", midi_test::smf(0, 480, {t}));
  const auto t0 = std::chrono::steady_clock::now();
  const Loaded l = load(song, "0");
  const json a = ex::ahap_json(l.spec());
  const json m = ex::meta_haptic_json(l.spec());
  std::printf("5000 notes: both exports in %.2f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  check_ahap(a);
  check_meta(m);
  int events = 0;
  for (const json& e : a["Pattern"]) events += e.contains("Event");
  EXPECT_EQ(events, 5000);
}

TEST(HapticExport, WindowWithoutNotesGivesAnEmptyPattern) {
  midi_test::Events t;
  t.tempo(0, 500000).program(0, 0, 73).on(0, 0, 60).off(960, 0, 60).on(960 * 3, 0, 62).off(960, 0, 62).end();
  const std::string song = write_midi("hmp-export-gap.mid", midi_test::smf(0, 480, {t}));
  const Loaded l = load(song, "0", 1.5, 2.5);
  const json a = ex::ahap_json(l.spec());
  check_ahap(a);
  EXPECT_TRUE(a["Pattern"].empty());
  const json m = ex::meta_haptic_json(l.spec());
  check_meta(m);
  for (const json& p : m["signals"]["continuous"]["envelopes"]["amplitude"]) EXPECT_EQ(p["amplitude"].get<double>(), 0.0);
}

TEST(HapticExport, CommandLine) {
  const fs::path dir = fs::temp_directory_path() / "hmp-export-cli";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* ext : {"ahap", "haptic"}) {
    const std::string out = (dir / (std::string("flute.") + ext)).string();
    ASSERT_EQ(run_hmp(kDemo + " --track flute --to 20 --out " + out), 0);
    std::ifstream f(out);
    const json j = json::parse(f);
    if (std::string(ext) == "ahap") {
      check_ahap(j);
    } else {
      check_meta(j);
    }
    std::string err;
    EXPECT_EQ(run_hmp(kDemo + " --track flute --to 20 --out " + out, &err), 2) << "no overwrite without --force";
    EXPECT_EQ(run_hmp(kDemo + " --track flute --to 20 --force --out " + out), 0);
    EXPECT_EQ(run_hmp(kDemo + " --track flute --out " + (dir / "missing" / "x.").string() + ext, &err), 2);
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(run_hmp(kDemo + " --track flute --from 5 --to 5 --out " + (dir / "empty.").string() + ext, &err), 2);
  }
  fs::remove_all(dir);
}

}  // namespace
