// Envelopes measured from FluidSynth's render of a SoundFont built here (tests/support/sf2_writer.hpp):
// a looped sine whose volume-envelope generators are known, so the truth is the generators' values as
// FluidSynth renders them (its voice code, read for docs/envelopes.md): stage lengths counted in whole
// 64-frame blocks (delay: floor; attack, release: 1 + floor; hold, decay: nearest), the attack linear in
// amplitude, decay and release linear in dB at 96 dB per their time, the sustain attenuation × 0.96.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "host/audio/soundfont.hpp"
#include "host/measure/measure.hpp"
#include "tests/support/sf2_writer.hpp"

namespace {

using hmp::test::Sf2Preset;
using hmp::test::VolumeEnvelope;

constexpr double kBlock = 64.0 / 48000.0;

double file_seconds(double s) { return hmp::test::timecent_seconds(hmp::test::timecents(s)); }
double blocks_floor(double s) { return std::floor(file_seconds(s) / kBlock) * kBlock; }
double blocks_nearest(double s) { return std::floor(file_seconds(s) / kBlock + 0.5) * kBlock; }

struct Expected {
  double delay, attack, hold, decay, sustain, release;
};

Expected rendered(const VolumeEnvelope& e) {
  return {blocks_floor(e.delay_s),
          blocks_floor(e.attack_s) + kBlock,
          blocks_nearest(e.hold_s),
          blocks_nearest(e.decay_s),
          std::pow(10.0, -0.96 * e.sustain_cb / 200.0),
          blocks_floor(e.release_s) + kBlock};
}

// Fast, slow and percussive (its sustain is 96 dB down: it dies away while held).
const Sf2Preset kPresets[] = {
    {0, "fast", {0.0, 0.05, 0.05, 0.4, 120, 0.3}, 0},
    {1, "slow", {0.1, 0.4, 0.2, 3.0, 60, 1.5}, 0},
    {2, "percussive", {0.0, 0.03, 0.0, 1.2, 1000, 0.5}, 0},
};

class MeasureTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One file per process: ctest runs each test of this file as its own process, side by side.
    path_ = new std::string(
        (std::filesystem::temp_directory_path() / ("hmp-measure-test-" + std::to_string(getpid()) + ".sf2")).string());
    hmp::test::write_sf2(*path_, std::vector<Sf2Preset>(std::begin(kPresets), std::end(kPresets)));
  }
  static void TearDownTestSuite() {
    std::filesystem::remove(*path_);
    delete path_;
  }
  static std::vector<hmp::measure::Measured> measure(std::vector<std::uint8_t> programs) {
    hmp::measure::MeasureOptions o;
    o.soundfont = *path_;
    o.programs = std::move(programs);
    o.key = 69;  // the sample's own key: 440 Hz
    o.key_fallback = false;
    return hmp::measure::measure_programs(o);
  }
  static std::string* path_;
};
std::string* MeasureTest::path_ = nullptr;

// Within 5 % of a stage's length; a stage FluidSynth renders as at most a block or two is within 3 ms.
void expect_time(double measured, double truth, const char* what, const char* preset) {
  const double tolerance = truth < 0.01 ? 0.003 : 0.05 * truth;
  EXPECT_NEAR(measured, truth, tolerance) << preset << ": " << what;
}

TEST_F(MeasureTest, EachStageOfFastSlowAndPercussiveEnvelopesIsRecovered) {
  const auto ms = measure({0, 1, 2});
  ASSERT_EQ(ms.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const Sf2Preset& p = kPresets[i];
    const Expected x = rendered(p.env);
    const hmp::measure::Stages& s = ms[i].stages;
    ASSERT_TRUE(s.sounded) << p.name;
    expect_time(s.delay_s, x.delay, "delay", p.name.c_str());
    expect_time(s.attack_s, x.attack, "attack", p.name.c_str());
    expect_time(s.hold_s, x.hold, "hold", p.name.c_str());
    expect_time(s.decay_s, x.decay, "decay (96 dB)", p.name.c_str());
    expect_time(s.release_s, x.release, "release (96 dB)", p.name.c_str());
    const double sustain = p.env.sustain_cb >= 960 ? 0.0 : x.sustain;  // 96 dB down is silence
    EXPECT_NEAR(s.sustain, sustain, 0.02) << p.name << ": sustain level";
  }
  EXPECT_TRUE(ms[2].release_from_second_render) << "the percussive note is silent at its note-off";
  EXPECT_FALSE(ms[0].release_from_second_render);
}

TEST_F(MeasureTest, TheEq9to10PresetIsTheLeastSquaresFitNearTheStages) {
  const auto ms = measure({0, 1, 2});
  for (const auto& m : ms) {
    const auto& s = m.stages;
    // Release: Eq. 10's curve is FluidSynth's, so it is taken, not fitted: R = the time to fall 40 dB.
    EXPECT_NEAR(m.preset.release_ms, s.release_s * 1e3 * 40.0 / 96.0, 0.01) << "R: the time to fall 40 dB";
    EXPECT_NEAR(m.preset.final_ratio, 0.01, 1e-7);
    // Where the sound follows FluidSynth's model, the least-squares A and S stay near its stages.
    EXPECT_NEAR(m.preset.attack_ms, s.attack_s * 1e3, 0.1 * s.attack_s * 1e3 + 1.0);
    EXPECT_NEAR(m.preset.sustain, s.sustain, 0.03);
    // A least-squares fit: moving any of A, Dc, S away from it costs error.
    const double d = m.held.note_off_s - s.delay_s + double(m.preset.release_ms) * 1e-3;
    const auto error_with = [&](auto change) {
      hmp::envelope::Adsr t = m.preset;
      change(t);
      return hmp::measure::rms_error(m.held, s, t, d);
    };
    EXPECT_NEAR(hmp::measure::rms_error(m.held, s, m.preset, d), m.rms_error, 1e-12);
    EXPECT_LT(m.rms_error, error_with([](auto& t) { t.attack_ms *= 0.8f; }));
    EXPECT_LT(m.rms_error, error_with([](auto& t) { t.attack_ms *= 1.25f; }));
    EXPECT_LT(m.rms_error, error_with([](auto& t) { t.decay_ms *= 0.5f; }));
    EXPECT_LT(m.rms_error, error_with([](auto& t) { t.decay_ms *= 2.0f; }));
    if (m.preset.sustain < 0.95f) {
      EXPECT_LT(m.rms_error, error_with([](auto& t) { t.sustain += 0.05f; }));
    }
    if (m.preset.sustain > 0.05f) {
      EXPECT_LT(m.rms_error, error_with([](auto& t) { t.sustain -= 0.05f; }));
    }
    // Linear decays cannot follow dB-linear ones exactly, but closely.
    EXPECT_LT(m.rms_error, 0.05);
  }
}

TEST_F(MeasureTest, TheSoundFontsProgramsAreReadFromItsPresetHeaders) {
  EXPECT_EQ(hmp::audio::soundfont_programs(*path_), (std::set<std::uint8_t>{0, 1, 2}));
  EXPECT_TRUE(hmp::audio::soundfont_programs(*path_, 128).empty());
  EXPECT_TRUE(hmp::audio::soundfont_programs(HMP_REPO_DIR "/README.md").empty());
}

// The command line: bad input is one line on stderr, exit 2, nothing written.
int hmp(const std::string& args, std::string* err = nullptr) {
  const std::string errfile =
      (std::filesystem::temp_directory_path() / ("hmp-measure-test-" + std::to_string(getpid()) + ".err")).string();
  const int rc =
      std::system((std::string(HMP_BIN_DIR) + "/hmp envelope measure " + args + " >/dev/null 2>" + errfile).c_str());
  if (err) {
    std::ifstream f(errfile);
    err->assign(std::istreambuf_iterator<char>(f), {});
  }
  std::filesystem::remove(errfile);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST_F(MeasureTest, TheCommandRefusesBadInputAndWritesNothing) {
  const auto dir = std::filesystem::temp_directory_path() / ("hmp-measure-cli-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "presets.toml").string();
  std::filesystem::remove(out);
  const std::string text = (dir / "not-a-soundfont.sf2").string();
  std::ofstream(text) << "hello\n";
  std::string err;
  EXPECT_EQ(hmp("--soundfont " + text + " --out " + out, &err), 2);
  EXPECT_NE(err.find("not-a-soundfont.sf2"), std::string::npos) << err;
  EXPECT_EQ(hmp("--soundfont " + *path_ + " --program 128 --out " + out), 2);
  EXPECT_EQ(hmp("--soundfont " + *path_ + " --program 5 --key 69 --out " + out, &err), 2);
  EXPECT_NE(err.find("no preset for program 5"), std::string::npos) << err;
  EXPECT_EQ(hmp("--soundfont " + *path_ + " --program 1 --all --out " + out), 2);
  EXPECT_EQ(hmp("--soundfont " + *path_ + " --velocity 0"), 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  // A good run writes presets that --config reads, and --envelope measured uses.
  EXPECT_EQ(hmp("--soundfont " + *path_ + " --program 0 --key 69 --out " + out, &err), 0) << err;
  ASSERT_TRUE(std::filesystem::exists(out));
  const std::string tone = std::string(HMP_BIN_DIR) + "/hmp info " + HMP_REPO_DIR +
                           "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid --config " + out + " >/dev/null";
  EXPECT_EQ(std::system(tone.c_str()), 0);
  EXPECT_EQ(hmp("--soundfont " + *path_ + " --program 0 --key 69 --out " + out), 2) << "exists: needs --force";
  // --out -: the presets alone on standard output (the table goes to stderr), a config as they stand.
  const std::string piped = (dir / "piped.toml").string();
  EXPECT_EQ(std::system((std::string(HMP_BIN_DIR) + "/hmp envelope measure --soundfont " + *path_ +
                         " --program 0 --key 69 --out - >" + piped + " 2>/dev/null")
                            .c_str()),
            0);
  EXPECT_EQ(std::system((std::string(HMP_BIN_DIR) + "/hmp info " + HMP_REPO_DIR +
                         "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid --config " + piped + " >/dev/null")
                            .c_str()),
            0);
  std::filesystem::remove_all(dir);
}

}  // namespace
