// .ahap and .haptic exports (host/export/): (1) a schema check written from Apple's and Meta's public
// descriptions of the formats (required keys, types, ranges, AHAP limits); (2) the envelope an .ahap
// describes, rebuilt the way Core Haptics plays it ((event intensity × control curve)², the curve linear
// between its points) and sampled at the tick rate, against the track's per-tick envelope computed from
// shared/envelope; (3) the intensity law, the curve's end, the metadata; (4) extreme and hostile inputs.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/common/error.hpp"
#include "host/export/haptic_export.hpp"
#include "host/export/json_writers.hpp"
#include "host/haptics/track_window.hpp"
#include "tests/support/json_schema.hpp"
#include "tests/support/midi_builder.hpp"

namespace {

using nlohmann::json;
namespace ex = hmp::exporting;
namespace fs = std::filesystem;

const std::string kDemo = std::string(HMP_REPO_DIR) + "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid";

struct Loaded {
  hmp::haptics::HapticOptions opts;
  hmp::haptics::TrackWindow w;
  ex::ExportSpec spec() const { return {&w.haptic, &opts, w.first_tick, w.end_tick, "test", ""}; }
};

Loaded load(const std::string& song, const std::string& track, std::optional<double> from = {},
            std::optional<double> to = {}) {
  Loaded l;
  l.w = hmp::haptics::load_track_window(song, track, l.opts, from, to, [](const std::string&) {});
  return l;
}

json read_json(const fs::path& p) {
  std::ifstream f(p);
  return json::parse(f);
}

const hmp::test::JsonSchema& ahap_schema() {
  static const hmp::test::JsonSchema s(read_json(fs::path(HMP_REPO_DIR) / "tests/host/export/schema/ahap.schema.json"));
  return s;
}
const hmp::test::JsonSchema& haptic_schema() {
  static const hmp::test::JsonSchema s(
      read_json(fs::path(HMP_REPO_DIR) / "tests/host/export/schema/haptic.schema.json"));
  return s;
}

std::string joined(const std::vector<std::string>& errors) {
  std::string out;
  for (std::size_t i = 0; i < errors.size() && i < 5; ++i) out += errors[i] + "\n";
  return out;
}

// AHAP: the schema, then what it cannot say — entries in time order, curve control points in time order,
// each curve after the previous one's start (Apple: curves are pattern-wide; ours must not overlap).
std::vector<std::string> ahap_errors(const json& j) {
  std::vector<std::string> errors = ahap_schema().validate(j);
  if (!errors.empty()) return errors;
  double last_event = 0, curve_end = 0;
  for (const json& e : j["Pattern"]) {
    if (e.contains("Event")) {
      const double t = e["Event"]["Time"];
      if (t < last_event - 1e-9) errors.push_back("event at " + std::to_string(t) + " s before the previous one");
      last_event = t;
    } else {
      const json& c = e["ParameterCurve"];
      const double t0 = c["Time"];
      if (t0 < curve_end - 1e-9) errors.push_back("curve at " + std::to_string(t0) + " s overlaps the previous curve");
      double last = -1;
      for (const json& pt : c["ParameterCurveControlPoints"]) {
        if (pt["Time"].get<double>() < last)
          errors.push_back("curve at " + std::to_string(t0) + " s: control points out of order");
        last = pt["Time"];
      }
      curve_end = t0 + last;
    }
  }
  return errors;
}

// .haptic: the schema, then the spec's validation rules the schema cannot say.
std::vector<std::string> haptic_errors(const json& j) {
  std::vector<std::string> errors = haptic_schema().validate(j);
  if (!errors.empty()) return errors;
  const json& env = j["signals"]["continuous"]["envelopes"];
  for (const char* key : {"amplitude", "frequency"}) {
    double last = 0;
    for (const json& p : env[key]) {
      if (p["time"].get<double>() < last) errors.push_back(std::string(key) + ": times decrease");
      last = p["time"];
      if (p.contains("emphasis") && p["emphasis"]["amplitude"].get<double>() < p["amplitude"].get<double>()) {
        errors.push_back("emphasis below the envelope's amplitude");
      }
    }
  }
  const json& am = env["amplitude"];
  const double end = am.back()["time"];
  if (!(end > am.front()["time"].get<double>())) errors.push_back("amplitude envelope of zero duration");
  for (const json& p : env["frequency"]) {
    if (p["time"].get<double>() > end + 1e-12)
      errors.push_back("frequency breakpoint after the amplitude envelope's end");
  }
  return errors;
}

void check_ahap(const json& j) {
  const auto errors = ahap_errors(j);
  EXPECT_TRUE(errors.empty()) << joined(errors);
}
void check_meta(const json& j) {
  const auto errors = haptic_errors(j);
  EXPECT_TRUE(errors.empty()) << joined(errors);
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

// What a Core Haptics player does with our .ahap, as Apple documents it: each continuous event plays at its
// HapticIntensity for its duration; a HapticIntensityControl curve multiplies the intensity of every event
// playing while it runs (curves are pattern-wide), linearly between its control points, holding its last
// value until the next curve. Intensity is quadratic (Meta's and Lofelt's converters write √amplitude): an
// event's vibration amplitude is (intensity × control)². Simultaneous events are taken to add (the
// device's sum).
std::vector<double> rebuild_ahap(const json& j, std::size_t ticks, double hz) {
  std::vector<double> intensity2_sum(ticks, 0.0), control(ticks, 1.0);
  std::vector<std::pair<double, double>> points;  // every control point, absolute time
  for (const json& e : j["Pattern"]) {
    if (e.contains("Event")) {
      const json& ev = e["Event"];
      const double t0 = ev["Time"], dur = ev["EventDuration"];
      double inten = 0;
      for (const json& p : ev["EventParameters"])
        if (p["ParameterID"] == "HapticIntensity") inten = p["ParameterValue"];
      for (auto k = static_cast<std::size_t>(std::llround(t0 * hz));
           k < ticks && static_cast<double>(k) / hz < t0 + dur - 1e-9; ++k) {
        intensity2_sum[k] += inten * inten;
      }
    } else {
      const json& c = e["ParameterCurve"];
      for (const json& p : c["ParameterCurveControlPoints"]) {
        points.emplace_back(c["Time"].get<double>() + p["Time"].get<double>(), p["ParameterValue"].get<double>());
      }
    }
  }
  std::size_t p = 0;
  for (std::size_t k = 0; k < ticks && !points.empty(); ++k) {
    const double t = static_cast<double>(k) / hz;
    while (p + 1 < points.size() && points[p + 1].first <= t + 1e-9) ++p;
    if (t < points[0].first - 1e-9) continue;
    if (p + 1 < points.size() && points[p + 1].first > points[p].first) {
      const double f = (t - points[p].first) / (points[p + 1].first - points[p].first);
      control[k] = points[p].second + (points[p + 1].second - points[p].second) * std::clamp(f, 0.0, 1.0);
    } else {
      control[k] = points[p].second;
    }
  }
  std::vector<double> y(ticks);
  for (std::size_t k = 0; k < ticks; ++k) y[k] = intensity2_sum[k] * control[k] * control[k];
  return y;
}

// Every event's HapticIntensity, in pattern order.
std::vector<double> event_intensities(const json& j) {
  std::vector<double> out;
  for (const json& e : j["Pattern"]) {
    if (!e.contains("Event")) continue;
    for (const json& p : e["Event"]["EventParameters"])
      if (p["ParameterID"] == "HapticIntensity") out.push_back(p["ParameterValue"]);
  }
  return out;
}

// The end of the last event and the end of the last parameter curve, in seconds.
std::pair<double, double> event_and_curve_end(const json& j) {
  double events = 0, curves = 0;
  for (const json& e : j["Pattern"]) {
    if (e.contains("Event")) {
      events = std::max(events, e["Event"]["Time"].get<double>() + e["Event"]["EventDuration"].get<double>());
    } else {
      const json& c = e["ParameterCurve"];
      curves =
          std::max(curves, c["Time"].get<double>() + c["ParameterCurveControlPoints"].back()["Time"].get<double>());
    }
  }
  return {events, curves};
}

int run_hmp(const std::string& args, std::string* err = nullptr) {
  const std::string errfile = (fs::temp_directory_path() / "hmp-export-test-stderr.txt").string();
  const int rc =
      std::system((std::string(HMP_BIN_DIR) + "/hmp render " + args + " 2>" + errfile + " </dev/null").c_str());
  if (err) {
    std::ifstream f(errfile);
    *err = std::string(std::istreambuf_iterator<char>(f), {});
  }
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string write_midi(const std::string& name, const midi_test::Bytes& bytes) {
  const fs::path p = fs::temp_directory_path() / name;
  std::ofstream(p, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return p.string();
}

TEST(HapticExport, TheCheckersRejectWhatTheRulesForbid) {
  // Hand-made documents that break one rule each: the checkers must say so.
  const json good_ahap = json::parse(R"({"Version": 1.0, "Pattern": [
      {"Event": {"Time": 0.0, "EventType": "HapticContinuous", "EventDuration": 1.0, "EventParameters": [
          {"ParameterID": "HapticIntensity", "ParameterValue": 0.5},
          {"ParameterID": "HapticSharpness", "ParameterValue": 0.2}]}},
      {"ParameterCurve": {"ParameterID": "HapticIntensityControl", "Time": 0.0, "ParameterCurveControlPoints": [
          {"Time": 0.0, "ParameterValue": 0.0}, {"Time": 0.5, "ParameterValue": 1.0}]}}]})");
  EXPECT_TRUE(ahap_errors(good_ahap).empty()) << joined(ahap_errors(good_ahap));
  auto broken = [](json j, const std::string& pointer, const json& value) {
    if (value.is_null()) {
      const json::json_pointer ptr(pointer);
      json& parent = j[ptr.parent_pointer()];
      if (parent.is_array()) {
        parent.erase(std::stoul(ptr.back()));
      } else {
        parent.erase(ptr.back());
      }
    } else {
      j[json::json_pointer(pointer)] = value;
    }
    return j;
  };
  EXPECT_FALSE(ahap_errors(broken(good_ahap, "/Pattern/0/Event/EventDuration", 31.0)).empty())
      << "31 s continuous event";
  EXPECT_FALSE(ahap_errors(broken(good_ahap, "/Pattern/0/Event/EventDuration", nullptr)).empty()) << "no duration";
  EXPECT_FALSE(ahap_errors(broken(good_ahap, "/Pattern/0/Event/EventType", "HapticBuzz")).empty());
  EXPECT_FALSE(ahap_errors(broken(good_ahap, "/Pattern/0/Event/EventParameters/0/ParameterValue", 1.5)).empty());
  EXPECT_FALSE(
      ahap_errors(broken(good_ahap, "/Pattern/1/ParameterCurve/ParameterCurveControlPoints/1/Time", -0.1)).empty());
  EXPECT_FALSE(
      ahap_errors(broken(good_ahap, "/Pattern/1/ParameterCurve/ParameterCurveControlPoints/0/Time", 0.7)).empty())
      << "out of order";
  EXPECT_FALSE(ahap_errors(broken(good_ahap, "/Pattern/0/Sound", json::object())).empty()) << "two keys in one entry";
  EXPECT_FALSE(ahap_errors(broken(good_ahap, "/Version", nullptr)).empty());
  json seventeen = good_ahap;
  for (int i = 2; i < 17; ++i)
    seventeen["Pattern"][1]["ParameterCurve"]["ParameterCurveControlPoints"].push_back(
        {{"Time", i}, {"ParameterValue", 0.5}});
  EXPECT_FALSE(ahap_errors(seventeen).empty()) << "17 control points";

  const json good_haptic = json::parse(R"({"version": {"major": 1, "minor": 0, "patch": 0}, "metadata": {},
      "signals": {"continuous": {"envelopes": {"amplitude": [{"time": 0.0, "amplitude": 0.0},
      {"time": 1.0, "amplitude": 0.3,
      "emphasis": {"amplitude": 0.5, "frequency": 0.5}}], "frequency": []}}}})");
  EXPECT_TRUE(haptic_errors(good_haptic).empty()) << joined(haptic_errors(good_haptic));
  const std::string amp = "/signals/continuous/envelopes/amplitude";
  EXPECT_FALSE(haptic_errors(broken(good_haptic, amp + "/1", nullptr)).empty()) << "one breakpoint";
  EXPECT_FALSE(haptic_errors(broken(good_haptic, amp + "/1/time", 0.0)).empty()) << "zero duration";
  EXPECT_FALSE(haptic_errors(broken(good_haptic, amp + "/0/time", 2.0)).empty()) << "times decrease";
  EXPECT_FALSE(haptic_errors(broken(good_haptic, amp + "/1/amplitude", 1.2)).empty());
  EXPECT_FALSE(haptic_errors(broken(good_haptic, amp + "/1/emphasis/amplitude", 0.1)).empty()) << "emphasis below";
  EXPECT_FALSE(haptic_errors(broken(good_haptic, "/signals/continuous/envelopes/frequency",
                                    json::parse(R"([{"time": 2.0, "frequency": 0.5}])")))
                   .empty())
      << "frequency after the end";
  EXPECT_FALSE(haptic_errors(broken(good_haptic, "/version/minor", "0")).empty());
  EXPECT_FALSE(haptic_errors(broken(good_haptic, "/metadata", nullptr)).empty());
}

TEST(HapticExport, OverlappingNotesSumInTheAhapModel) {
  // Two notes overlapping with different amplitudes and envelopes: a pattern-wide control curve must still
  // give the summed envelope (a per-note curve would scale the other note too).
  midi_test::Events t;
  t.tempo(0, 500000).program(0, 0, 0).on(0, 0, 48).on(240, 0, 72).off(480, 0, 48).off(480, 0, 72).end();
  const std::string song = write_midi("hmp-export-overlap.mid", midi_test::smf(0, 480, {t}));
  const Loaded l = load(song, "0");
  const std::vector<double> want = track_envelope(l);
  const std::vector<double> got = rebuild_ahap(ex::ahap_json(l.spec()), want.size(), l.opts.tick_hz);
  double max_err = 0;
  for (std::size_t k = 0; k < want.size(); ++k) max_err = std::max(max_err, std::abs(got[k] - want[k]));
  EXPECT_LT(max_err, 0.012);  // 0.005 of M times the two notes' summed intensity (≤ 2) plus rounding
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
    // The curve is within 0.005 of M = Σ envelope / Σ intensity at every tick, times Σ intensity (under 2
    // for these tracks' overlaps): under 0.01 of full scale.
    EXPECT_LT(max_err, 0.01) << track;
    EXPECT_LT(sum_err / static_cast<double>(want.size()), 0.001) << track;
  }
}

TEST(HapticExport, MetaAmplitudeFollowsTheSummedEnvelope) {
  const Loaded l = load(kDemo, "flute", 0.0, 60.0);
  const std::vector<double> want = track_envelope(l);
  const json j = ex::meta_haptic_json(l.spec());
  const json& am = j["signals"]["continuous"]["envelopes"]["amplitude"];
  for (std::size_t i = 0; i < am.size(); ++i) {
    // Each point is the envelope at its tick; the last stands at the window's end with the last tick's value.
    const auto k =
        std::min(static_cast<std::size_t>(std::llround(am[i]["time"].get<double>() * l.opts.tick_hz)), want.size() - 1);
    EXPECT_NEAR(am[i]["amplitude"].get<double>(), std::min(want[k], 1.0), 1e-6) << i;
  }
  EXPECT_NEAR(am.back()["time"].get<double>(), static_cast<double>(want.size()) / l.opts.tick_hz, 1e-9);
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

TEST(HapticExport, AhapIntensityIsTheSquareRootOfTheAmplitude) {
  // Three keys under the paper mapping: the lowest gets the range's quietest amplitude, a_min = 7.5 dB,
  // 22.5 dB below full scale: 10^(−22.5/20) = 0.0750, whose square root is 0.2738.
  midi_test::Events t;
  t.tempo(0, 500000)
      .program(0, 0, 73)
      .on(0, 0, 48)
      .off(480, 0, 48)
      .on(0, 0, 72)
      .off(480, 0, 72)
      .on(0, 0, 60)
      .off(480, 0, 60)
      .end();
  const std::string song = write_midi("hmp-export-sqrt.mid", midi_test::smf(0, 480, {t}));
  const Loaded l = load(song, "0");
  const json a = ex::ahap_json(l.spec());
  check_ahap(a);
  const std::vector<double> got = event_intensities(a);
  const auto& notes = l.w.haptic.notes;
  ASSERT_EQ(got.size(), notes.size());
  double quietest_amp = 1, quietest_intensity = 1;
  for (std::size_t i = 0; i < notes.size(); ++i) {
    const double amp = static_cast<double>(notes[i].note.amp_q16) / 65535.0;  // what the engine plays
    EXPECT_NEAR(got[i], std::sqrt(amp), 1e-12) << "note " << i << ", amplitude " << amp;
    if (amp < quietest_amp) {
      quietest_amp = amp;
      quietest_intensity = got[i];
    }
  }
  EXPECT_NEAR(quietest_amp, std::pow(10.0, -22.5 / 20.0), 2e-5);
  EXPECT_NEAR(quietest_intensity, 0.274, 0.0005);

  // The control curve is in the same domain: value² × the note's amplitude = the note's envelope at that
  // tick (the notes do not overlap; a point at a note's end belongs to the next note; the very last point
  // holds the last tick's value).
  const double hz = l.opts.tick_hz;
  int checked = 0;
  for (const json& e : a["Pattern"]) {
    if (!e.contains("ParameterCurve")) continue;
    const json& c = e["ParameterCurve"];
    for (const json& p : c["ParameterCurveControlPoints"]) {
      auto k = static_cast<std::uint64_t>(std::llround((c["Time"].get<double>() + p["Time"].get<double>()) * hz)) +
               l.w.first_tick;
      const auto& last = notes.back().note;
      if (k == last.start_tick + last.duration_ticks) --k;
      for (const auto& hn : notes) {
        if (k < hn.note.start_tick || k >= hn.note.start_tick + hn.note.duration_ticks) continue;
        const double v = p["ParameterValue"];
        const double amp = static_cast<double>(hn.note.amp_q16) / 65535.0;
        const double env = static_cast<double>(
            ex::note_envelope(l.w.haptic, l.opts, hn.note).at(static_cast<std::uint32_t>(k - hn.note.start_tick)));
        EXPECT_NEAR(v * v * amp, env, 1e-6) << "tick " << k;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 10);
}

TEST(HapticExport, AhapCurvesEndWhereTheEventsEnd) {
  // A passage of the demo (the last note cut by --to), and a window whose last note ends 1.5 s before --to.
  const Loaded demo = load(kDemo, "flute", 30.0, 40.0);
  const auto [demo_events, demo_curves] = event_and_curve_end(ex::ahap_json(demo.spec()));
  EXPECT_GT(demo_events, 9.0);
  EXPECT_NEAR(demo_curves, demo_events, 1e-9);

  midi_test::Events t;
  t.tempo(0, 500000).program(0, 0, 73).on(0, 0, 60).off(960, 0, 60).on(960 * 3, 0, 62).off(960, 0, 62).end();
  const std::string song = write_midi("hmp-export-gap.mid", midi_test::smf(0, 480, {t}));
  const Loaded l = load(song, "0", 0.0, 2.5);
  const json a = ex::ahap_json(l.spec());
  check_ahap(a);
  const auto [events, curves] = event_and_curve_end(a);
  EXPECT_NEAR(events, 1.0, 1e-9);  // the first note: 960 ticks at 480 per quarter, 120 bpm
  EXPECT_NEAR(curves, 1.0, 1e-9);
}

TEST(HapticExport, WindowWithoutNotesIsRefused) {
  midi_test::Events t;
  t.tempo(0, 500000).program(0, 0, 73).on(0, 0, 60).off(960, 0, 60).on(960 * 3, 0, 62).off(960, 0, 62).end();
  const std::string song = write_midi("hmp-export-gap.mid", midi_test::smf(0, 480, {t}));
  const Loaded l = load(song, "0", 1.5, 2.5);
  // The documents themselves stay valid (an empty pattern, a silent clip)…
  const json a = ex::ahap_json(l.spec());
  check_ahap(a);
  EXPECT_TRUE(a["Pattern"].empty());
  const json m = ex::meta_haptic_json(l.spec());
  check_meta(m);
  for (const json& p : m["signals"]["continuous"]["envelopes"]["amplitude"])
    EXPECT_EQ(p["amplitude"].get<double>(), 0.0);
  // …but writing one is refused with a message naming the window, and nothing is written.
  for (const char* ext : {".ahap", ".haptic"}) {
    const fs::path out = fs::temp_directory_path() / (std::string("hmp-export-silent") + ext);
    fs::remove(out);
    try {
      ex::write_haptic_export(out.string(), false, l.spec());
      ADD_FAILURE() << ext << ": a silent window was written";
    } catch (const hmp::BadInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("1.500–2.500 s"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    EXPECT_FALSE(fs::exists(out)) << ext;
  }
}

TEST(HapticExport, MetadataNamesTheSongFileNotItsPath) {
  midi_test::Events t;
  t.tempo(0, 500000).program(0, 0, 73).on(0, 0, 60).off(960, 0, 60).end();
  const std::string song = write_midi("hmp-export-meta.mid", midi_test::smf(0, 480, {t}));
  const Loaded l = load(song, "0");
  ex::ExportSpec spec = l.spec();
  for (const char* given : {"/home/someone/music/bwv1050.mid", "../music/bwv1050.mid", "bwv1050.mid"}) {
    spec.song = given;
    spec.title = "track 3 \"Flute\", mapping paper, envelope piano";
    const json m = ex::meta_haptic_json(spec);
    EXPECT_EQ(m["metadata"]["source"], "bwv1050.mid") << given;
    EXPECT_EQ(m["metadata"]["description"], "bwv1050.mid — track 3 \"Flute\", mapping paper, envelope piano") << given;
    EXPECT_EQ(m["metadata"]["editor"], "hmp render");
    check_meta(m);
    EXPECT_EQ(ex::ahap_json(spec)["Metadata"]["Description"], m["metadata"]["description"]);
  }
}

TEST(HapticExport, OneNoteAndOneTickWindowsAreValid) {
  midi_test::Events t;
  t.tempo(0, 500000).program(0, 0, 73).on(0, 0, 60).off(1, 0, 60).on(960, 0, 62).off(960, 0, 62).end();  // a 1-tick
                                                                                                         // note
  const std::string song = write_midi("hmp-export-tiny.mid", midi_test::smf(0, 480, {t}));
  for (const auto& [from, to] : {std::pair{0.0, 0.001}, {0.0, 3.0}, {1.5, 1.501}}) {
    const Loaded l = load(song, "0", from, to);
    check_ahap(ex::ahap_json(l.spec()));
    check_meta(ex::meta_haptic_json(l.spec()));
  }
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
    const std::string name = fs::path(kDemo).filename().string();
    if (std::string(ext) == "ahap") {
      check_ahap(j);
      EXPECT_EQ(j["Metadata"]["Description"].get<std::string>().rfind(name + " — track ", 0), 0u) << j["Metadata"];
    } else {
      check_meta(j);
      EXPECT_EQ(j["metadata"]["source"], name);
      EXPECT_EQ(j["metadata"]["description"].get<std::string>().rfind(name + " — track ", 0), 0u) << j["metadata"];
      EXPECT_EQ(j["metadata"]["description"].get<std::string>().find(HMP_REPO_DIR), std::string::npos) << "no path";
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
