// The tests' SoundFont writer (tests/support/sf2_writer.hpp):
//  - its layout follows the SoundFont 2.04 rules (chunk sizes, terminal records, the sample's guard
//    points and seamless loop, timecent conversion);
//  - FluidSynth, through the audio module's offline renderer, loads the file and plays each preset
//    with the sample's pitch and the envelope the file holds: a 200 ms attack reaches half its peak
//    halfway through the attack, a percussive 0.3 s decay to 1000 cB falls below 1 % while held.
//    Wrong generator order (FluidSynth ignores generators after sampleID), a wrong timecent
//    conversion or a wrong originalPitch would fail these.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "host/audio/audio_events.hpp"
#include "host/audio/offline_render.hpp"
#include "host/audio/soundfont.hpp"
#include "tests/support/sf2_writer.hpp"

namespace {

using hmp::audio::AudioEvent;
using hmp::test::Sf2Preset;
using hmp::test::timecent_seconds;
using hmp::test::timecents;
using Bytes = std::vector<std::uint8_t>;

std::uint32_t le32(const Bytes& b, std::size_t at) {
  return b[at] | b[at + 1] << 8 | b[at + 2] << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}

// Where the first chunk with this id starts (searched as bytes; ids are unique in the test's files).
std::size_t chunk_at(const Bytes& b, const char* id) {
  for (std::size_t i = 0; i + 8 <= b.size(); ++i) {
    if (std::memcmp(&b[i], id, 4) == 0) return i;
  }
  ADD_FAILURE() << "no chunk " << id;
  return 0;
}
std::uint32_t chunk_size(const Bytes& b, const char* id) { return le32(b, chunk_at(b, id) + 4); }

// The amount of generator `op` in instrument `inst`'s zone, as the file holds it (igen records of
// 4 bytes, the zone's first one from ibag).
std::int16_t igen_amount(const Bytes& b, std::size_t inst, unsigned op) {
  const std::size_t ibag = chunk_at(b, "ibag") + 8, igen = chunk_at(b, "igen") + 8;
  const auto at = [&](std::size_t i) { return static_cast<unsigned>(b[i] | b[i + 1] << 8); };
  for (std::size_t g = at(ibag + 4 * inst); g < at(ibag + 4 * (inst + 1)); ++g) {
    if (at(igen + 4 * g) == op) return static_cast<std::int16_t>(at(igen + 4 * g + 2));
  }
  ADD_FAILURE() << "instrument " << inst << " has no generator " << op;
  return 0;
}

const Sf2Preset kSlow{3, "slow attack", {0, 0.2, 0, 0, 0, 0.1}};    // 200 ms attack, full sustain
const Sf2Preset kPerc{7, "percussive", {0, 0, 0, 0.3, 1000, 0.1}};  // 0.3 s decay to 1000 cB

TEST(Sf2Writer, LayoutFollowsTheSpec) {
  const hmp::test::Sf2Sample s = hmp::test::sine_sample(48000, 440.0, 11);
  EXPECT_EQ(s.loop_end - s.loop_start, 1200u);  // 11 periods of 440 Hz at 48 kHz, exactly
  EXPECT_DOUBLE_EQ(s.freq_hz, 440.0);
  EXPECT_EQ(s.key, 69);
  EXPECT_EQ(s.correction, 0);
  EXPECT_EQ(s.loop_start, 8u);  // ≥ 8 valid points before the loop and after it
  EXPECT_EQ(s.data.size(), s.loop_end + 8);
  EXPECT_EQ(s.data[s.loop_end], s.data[s.loop_start]);  // seamless: the point after the loop is its start
  EXPECT_EQ(s.data[s.loop_end - 1], s.data[s.loop_start - 1]);

  EXPECT_EQ(timecents(0), -12000);
  EXPECT_EQ(timecents(1e-6), -12000);
  EXPECT_EQ(timecents(1.0), 0);
  EXPECT_EQ(timecents(0.3), -2084);  // 1200·log2(0.3) = −2084.4
  EXPECT_NEAR(timecent_seconds(timecents(0.3)), 0.3, 1e-4);

  const Bytes f = hmp::test::build_sf2({kSlow, kPerc}, s);
  ASSERT_GE(f.size(), 12u);
  EXPECT_EQ(std::string(f.begin(), f.begin() + 4), "RIFF");
  EXPECT_EQ(std::string(f.begin() + 8, f.begin() + 12), "sfbk");
  EXPECT_EQ(le32(f, 4), f.size() - 8);
  EXPECT_EQ(chunk_size(f, "ifil"), 4u);
  EXPECT_EQ(chunk_size(f, "smpl"), 2 * (s.data.size() + 46));
  EXPECT_EQ(chunk_size(f, "phdr"), 38u * 3);  // two presets + EOP
  EXPECT_EQ(chunk_size(f, "pbag"), 4u * 3);
  EXPECT_EQ(chunk_size(f, "pmod"), 10u);
  EXPECT_EQ(chunk_size(f, "pgen"), 4u * 3);
  EXPECT_EQ(chunk_size(f, "inst"), 22u * 3);
  EXPECT_EQ(chunk_size(f, "ibag"), 4u * 3);
  EXPECT_EQ(chunk_size(f, "imod"), 10u);
  EXPECT_EQ(chunk_size(f, "igen"), 4u * (2 * 11 + 1));
  EXPECT_EQ(chunk_size(f, "shdr"), 46u * 2);
}

// One held note of `preset` (channel 0, key 69, from 0.1 s to 1.6 s), rendered dry: the left channel.
constexpr std::int64_t kOnUs = 100'000, kOffUs = 1'600'000, kEndUs = 2'000'000;
std::vector<float> play(const std::string& sf2, const Sf2Preset& preset) {
  hmp::audio::AudioOptions options;
  options.soundfont = sf2;
  options.synth.reverb = false;
  options.synth.chorus = false;
  options.synth.onset_compensation = false;
  const auto program = static_cast<std::uint8_t>(preset.program);
  const std::vector<AudioEvent> ev = {{kOnUs, AudioEvent::Kind::note_on, 0, 69, 127, program},
                                      {kOffUs, AudioEvent::Kind::note_off, 0, 69, 0, program}};
  int warnings = 0;
  const auto audio = hmp::audio::render_offline(ev, 0, kEndUs, options, [&](const std::string& w) {
    ++warnings;
    ADD_FAILURE() << "warning: " << w;
  });
  EXPECT_EQ(warnings, 0);
  EXPECT_FALSE(audio.silent_fallback);
  EXPECT_EQ(audio.sample_rate, 48000);
  return audio.left;
}

constexpr int kRate = 48000;
std::size_t frame(double s) { return static_cast<std::size_t>(std::lround(s * kRate)); }

// Frequency from the rising zero crossings in [from_s, to_s), each placed between its two frames.
double frequency(const std::vector<float>& x, double from_s, double to_s) {
  double first = -1, last = -1;
  int crossings = 0;
  for (std::size_t i = frame(from_s); i + 1 < frame(to_s) && i + 1 < x.size(); ++i) {
    if (x[i] < 0 && x[i + 1] >= 0) {
      const double t = static_cast<double>(i) + static_cast<double>(x[i] / (x[i] - x[i + 1]));
      if (first < 0) first = t;
      last = t, ++crossings;
    }
  }
  return crossings < 2 ? 0 : (crossings - 1) * kRate / (last - first);
}

std::vector<float> span(const std::vector<float>& x, double from_s, double to_s) {
  const auto at = [&](double s) { return x.begin() + static_cast<std::ptrdiff_t>(frame(s)); };
  return {at(from_s), at(to_s)};
}

float peak(const std::vector<float>& x) {
  float p = 0;
  for (float v : x) p = std::max(p, std::fabs(v));
  return p;
}

TEST(Sf2Writer, FluidSynthPlaysEachPresetWithItsEnvelope) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("hmp_sf2_writer_test_" + std::to_string(::getpid()) + ".sf2"))
          .string();
  hmp::test::write_sf2(path, {kSlow, kPerc});
  // The envelope times the file holds (attackVolEnv 34, decayVolEnv 36): the callers' within 0.1 %.
  const Bytes file = hmp::test::build_sf2({kSlow, kPerc});
  const double attack = timecent_seconds(igen_amount(file, 0, 34));
  const double decay = timecent_seconds(igen_amount(file, 1, 36));
  EXPECT_NEAR(attack, kSlow.env.attack_s, 1e-3 * kSlow.env.attack_s);
  EXPECT_NEAR(decay, kPerc.env.decay_s, 1e-3 * kPerc.env.decay_s);
  EXPECT_EQ(igen_amount(file, 1, 37), 1000);  // sustainVolEnv, cB
  EXPECT_EQ(hmp::audio::soundfont_format_problem(path), "");
  const std::vector<float> slow = play(path, kSlow);
  const std::vector<float> perc = play(path, kPerc);
  std::filesystem::remove(path);
  ASSERT_EQ(slow.size(), frame(2.0));
  ASSERT_EQ(perc.size(), frame(2.0));
  const double on_s = static_cast<double>(kOnUs) * 1e-6;

  // Silent before the note, and sounding at the sample's pitch (key 69 = its originalPitch: 440 Hz).
  const float slow_peak = peak(slow), perc_peak = peak(perc);
  ASSERT_GT(slow_peak, 1e-3f);
  ASSERT_GT(perc_peak, 1e-3f);
  EXPECT_EQ(peak(span(slow, 0, on_s)), 0.0f);
  EXPECT_NEAR(frequency(slow, 0.5, 1.5), 440.0, 0.5);
  EXPECT_NEAR(frequency(perc, on_s + 0.005, on_s + 0.08), 440.0, 1.0);

  // Slow attack: linear in amplitude (spec §8.1.3), so half the peak about halfway through the attack
  // the file holds; later than 50 ms in any case. Full sustain (0 cB): still at its peak when released.
  std::size_t i = frame(on_s);
  while (i < slow.size() && std::fabs(slow[i]) < 0.5f * slow_peak) ++i;
  const double half_s = static_cast<double>(i) / kRate - on_s;
  EXPECT_GT(half_s, 0.050) << "half of the peak " << half_s << " s after the note-on";
  EXPECT_GT(half_s, 0.35 * attack);
  EXPECT_LT(half_s, 0.65 * attack);
  EXPECT_GT(peak(span(slow, 1.5, 1.6)), 0.9f * slow_peak);

  // Percussive: the decay runs linearly in dB towards 1000 cB (full attenuation) over the decay time,
  // so −40 dB (1 %) comes after ~40 % of it (FluidSynth scales to 96 dB: 41.7 %), well within 1 s,
  // while the key is still held.
  std::size_t last = frame(on_s);
  for (std::size_t k = frame(on_s); k < frame(1.6); ++k) {
    if (std::fabs(perc[k]) >= 0.01f * perc_peak) last = k;
  }
  const double below_s = static_cast<double>(last + 1) / kRate - on_s;
  EXPECT_LT(below_s, 1.0) << "under 1 % from " << below_s << " s after the note-on";
  EXPECT_GT(below_s, 0.30 * decay);
  EXPECT_LT(below_s, 0.55 * decay);
}

}  // namespace
