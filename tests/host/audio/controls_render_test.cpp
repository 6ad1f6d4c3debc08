// The song's controllers in its sound (design §17): small songs written byte by byte here, read
// by the SMF reader and rendered offline by FluidSynth with the GM SoundFont, measured against references
// that do not come from the code under test:
//  - the sustain pedal: a note released under the pedal sounds as the same note held until the pedal lifts
//    (envelope within 1.5 dB), and far louder than the note without the pedal;
//  - volume (CC7) and expression (CC11): each step of a crescendo is 40·log10(v/127) dB (the GM level
//    law, which FluidSynth's default modulators implement) from full volume;
//  - pitch bend with its RPN 0 range: the measured pitch ratio is the SoundFont 2.04 default modulator's;
//  - pan (CC10): hard left and right strongly one-sided and mirrored, 64 the default, monotonic between;
//  - a seek: rendering from a position equals the full render's tail there (controllers set before the
//    position restored: pedal down, volume, bend range, pan).
// Skipped when no GM SoundFont is installed.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "host/audio/audio_backend.hpp"
#include "host/audio/audio_events.hpp"
#include "host/audio/offline_render.hpp"
#include "host/audio/soundfont.hpp"
#include "host/midi/smf_reader.hpp"
#include "tests/support/midi_builder.hpp"

namespace {

using namespace hmp;
using midi_test::Events;

constexpr int kRate = 44100;

// Format 1, 500 ticks a quarter at 120 bpm: a tick is a millisecond.
midi::Song song_of(Events track) {
  Events conductor;
  conductor.tempo(0, 500000).end();
  const midi::ReadResult r = midi::read_smf(midi_test::smf(1, 500, {conductor, track.end()}));
  return r.song;
}

audio::RenderedAudio render(const midi::Song& song, double from_s, double to_s) {
  audio::AudioOptions options;
  options.synth.sample_rate = kRate;
  return audio::render_offline(audio::audio_events(song), static_cast<std::int64_t>(from_s * 1e6),
                               static_cast<std::int64_t>(to_s * 1e6), options, [](const std::string&) {});
}

// RMS level in dB of both channels over song time [t0, t1) of a render that starts at `start_s`.
double level_db(const audio::RenderedAudio& a, double t0, double t1, double start_s = 0, int which = 2) {
  const auto i0 = static_cast<std::size_t>((t0 - start_s) * kRate),
             i1 = static_cast<std::size_t>((t1 - start_s) * kRate);
  double sum = 0;
  for (std::size_t i = i0; i < i1 && i < a.left.size(); ++i) {
    const auto l = static_cast<double>(a.left[i]), r = static_cast<double>(a.right[i]);
    sum += which == 0 ? l * l : which == 1 ? r * r : l * l + r * r;
  }
  return 10 * std::log10(sum / static_cast<double>(i1 - i0) + 1e-30);
}

// The fundamental over [t0, t1): the autocorrelation peak between 0.55 and 1.8 periods of `guess_hz`,
// refined by a parabola through the peak and its neighbours.
double pitch_hz(const audio::RenderedAudio& a, double t0, double t1, double guess_hz) {
  const auto i0 = static_cast<std::size_t>(t0 * kRate), n = static_cast<std::size_t>((t1 - t0) * kRate);
  auto corr = [&](std::size_t lag) {
    double s = 0;
    for (std::size_t i = 0; i + lag < n; ++i)
      s += static_cast<double>(a.left[i0 + i]) * static_cast<double>(a.left[i0 + i + lag]);
    return s / static_cast<double>(n - lag);
  };
  const auto lo = static_cast<std::size_t>(kRate / guess_hz / 1.8),
             hi = static_cast<std::size_t>(kRate / guess_hz / 0.55);
  std::size_t best = lo;
  double best_c = -1e300;
  for (std::size_t lag = lo; lag <= hi; ++lag) {
    if (const double c = corr(lag); c > best_c) {
      best_c = c;
      best = lag;
    }
  }
  const double y0 = corr(best - 1), y1 = best_c, y2 = corr(best + 1);
  const double shift = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2);
  return kRate / (static_cast<double>(best) + shift);
}

class ControlsRender : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!audio::find_soundfont("")) GTEST_SKIP() << "no GM SoundFont installed (fluid-soundfont-gm)";
  }
};

TEST_F(ControlsRender, APedalledNoteSoundsAsIfHeldUntilThePedalLifts) {
  // Piano middle C from 0.2 s, released at 0.4 s; pedal down at 0.1 s, up at 1.5 s.
  Events pedalled, held, dry;
  pedalled.program(0, 0, 0).raw(100, {0xB0, 64, 127}).on(100, 0, 60).off(200, 0, 60).raw(1100, {0xB0, 64, 0});
  held.program(0, 0, 0).on(200, 0, 60).off(1300, 0, 60);  // the reference: no pedal, the key held to 1.5 s
  dry.program(0, 0, 0).on(200, 0, 60).off(200, 0, 60);
  const auto p = render(song_of(pedalled), 0, 2.5), h = render(song_of(held), 0, 2.5), d = render(song_of(dry), 0, 2.5);
  for (double t = 0.5; t < 1.45; t += 0.1) {
    EXPECT_NEAR(level_db(p, t, t + 0.1), level_db(h, t, t + 0.1), 1.5) << "at " << t << " s";
  }
  EXPECT_GT(level_db(p, 0.8, 1.2) - level_db(d, 0.8, 1.2), 30.0) << "the pedal did not hold the note";
  // After the pedal lifts, the note dies as the released one does.
  EXPECT_NEAR(level_db(p, 1.9, 2.1), level_db(h, 1.9, 2.1), 3.0);
}

TEST_F(ControlsRender, VolumeAndExpressionFollowTheGmLevelLaw) {
  // Church organ (steady, no vibrato) on A3 with the reverb and chorus sends off (their returns are not
  // scaled per channel the same way), one render per value of CC7, then of CC11, each held from the start.
  auto level = [](int cc, int v) {
    Events e;
    e.program(0, 0, 19)
        .raw(0, {0xB0, 91, 0})
        .raw(0, {0xB0, 93, 0})
        .raw(0, {0xB0, static_cast<std::uint8_t>(cc), static_cast<std::uint8_t>(v)});
    e.on(0, 0, 57).off(1000, 0, 57);
    return level_db(render(song_of(e), 0, 1.2), 0.4, 0.9);
  };
  for (const int cc : {7, 11}) {
    const double full = level(cc, 127);
    for (const int v : {100, 90, 64, 40, 20}) {
      EXPECT_NEAR(level(cc, v) - full, 40 * std::log10(v / 127.0), 0.5) << "CC" << cc << " = " << v;
    }
  }
  // A crescendo within one note: each step's level against the same note at full volume over the same
  // window (the organ's own swell cancels), measured after the step settles.
  auto crescendo = [](bool ramp) {
    Events e;
    e.program(0, 0, 19)
        .raw(0, {0xB0, 91, 0})
        .raw(0, {0xB0, 93, 0})
        .raw(0, {0xB0, 7, static_cast<std::uint8_t>(ramp ? 40 : 127)})
        .on(0, 0, 57);
    if (ramp) e.raw(500, {0xB0, 7, 64}).raw(500, {0xB0, 7, 90}).raw(500, {0xB0, 7, 127}).off(500, 0, 57);
    if (!ramp) e.off(2000, 0, 57);
    return render(song_of(e), 0, 2.2);
  };
  const auto ramped = crescendo(true), constant = crescendo(false);
  const int values[] = {40, 64, 90, 127};
  for (int k = 0; k < 4; ++k) {
    const double t = 0.5 * k;
    EXPECT_NEAR(level_db(ramped, t + 0.2, t + 0.45) - level_db(constant, t + 0.2, t + 0.45),
                40 * std::log10(values[k] / 127.0), 0.5)
        << "step " << values[k];
  }
}

TEST_F(ControlsRender, PitchBendFollowsItsRpnRange) {
  // Church organ A4 (no vibrato); the bend range set to 7 semitones by RPN 0 (CC101 0, CC100 0, data entry 7), then
  // bent up fully (16383) and down by half (4096).
  Events e;
  e.program(0, 0, 19)
      .raw(0, {0xB0, 101, 0})
      .raw(0, {0xB0, 100, 0})
      .raw(0, {0xB0, 6, 7})
      .raw(0, {0xB0, 38, 0})
      .on(0, 0, 69)
      .raw(600, {0xE0, 0x7F, 0x7F})
      .raw(600, {0xE0, 0x00, 0x20})
      .off(600, 0, 69);
  const auto a = render(song_of(e), 0, 2.0);
  const double f0 = pitch_hz(a, 0.2, 0.55, 440);
  const double up = pitch_hz(a, 0.8, 1.15, 440 * 1.5), down = pitch_hz(a, 1.4, 1.75, 440 / 1.2);
  EXPECT_NEAR(f0, 440.0, 440 * 0.01);  // the organ's sample is tuned a few cents sharp
  // SoundFont 2.04 §8.4.10, the default modulator: pitch wheel (bipolar, (v − 8192)/8192) times pitch
  // wheel sensitivity (unipolar, semitones/128) times 12700 cents; 7 semitones of range are 694.5 cents.
  auto ratio = [](double sens, int bend) { return std::pow(2.0, 12700.0 * sens / 128 * (bend - 8192) / 8192 / 1200); };
  EXPECT_NEAR(up / f0, ratio(7, 16383), 0.002);
  EXPECT_NEAR(down / f0, ratio(7, 4096), 0.002);
  EXPECT_GT(std::abs(up / f0 - 1.0), 0.4) << "no bend at all";
}

TEST_F(ControlsRender, PanPutsTheNoteLeftRightOrCentre) {
  // Sends off: the reverb and chorus returns are stereo whatever the pan. CC10 adds to the pan the
  // SoundFont's zones already have (SF2 §8.4: a modulator offsets the generator), and the GM organ layers
  // stereo samples, so hard left and right are strongly one-sided, not silent on the other side.
  auto balance_db = [](int pan) {  // right minus left; pan < 0: no CC10 at all (the default)
    Events e;
    e.program(0, 0, 19).raw(0, {0xB0, 91, 0}).raw(0, {0xB0, 93, 0});
    if (pan >= 0) e.raw(0, {0xB0, 10, static_cast<std::uint8_t>(pan)});
    e.on(0, 0, 69).off(500, 0, 69);
    const auto a = render(song_of(e), 0, 0.6);
    return level_db(a, 0.1, 0.45, 0, 1) - level_db(a, 0.1, 0.45, 0, 0);
  };
  EXPECT_LT(balance_db(0), -15.0) << "hard left is not left";
  EXPECT_GT(balance_db(127), 15.0) << "hard right is not right";
  EXPECT_NEAR(balance_db(0), -balance_db(127), 2.0) << "left and right not mirrored";
  EXPECT_NEAR(balance_db(64), balance_db(-1), 0.1) << "CC10 64 is not the default centre";
  // In between, the balance moves monotonically from left to right.
  double previous = balance_db(0);
  for (const int pan : {16, 32, 48, 64, 80, 96, 112, 127}) {
    const double b = balance_db(pan);
    EXPECT_GT(b, previous) << pan;
    previous = b;
  }
}

TEST_F(ControlsRender, ASeekRestoresTheControllersOfItsPosition) {
  // Before 2 s only controllers: pedal down, volume 64, pan left, bend range 12 and a bend of +6
  // semitones. After it an organ note from 2.5 s, released at 2.8 s under the pedal, which lifts at 3.6 s.
  Events e;
  e.program(0, 0, 19)
      .raw(100, {0xB0, 64, 127})
      .raw(100, {0xB0, 7, 64})
      .raw(100, {0xB0, 10, 20})
      .raw(100, {0xB0, 101, 0})
      .raw(0, {0xB0, 100, 0})
      .raw(0, {0xB0, 6, 12})
      .raw(100, {0xE0, 0x00, 0x60})
      .on(2100, 0, 69)
      .off(300, 0, 69)
      .raw(800, {0xB0, 64, 0});
  const midi::Song song = song_of(e);
  const auto full = render(song, 0, 4.5);
  const auto from2 = render(song, 2.0, 4.5);
  for (double t = 2.6; t < 4.4; t += 0.2) {
    for (int ch = 0; ch < 2; ++ch) {
      EXPECT_NEAR(level_db(from2, t, t + 0.2, 2.0, ch), level_db(full, t, t + 0.2, 0, ch), 0.5)
          << t << " s, channel " << ch;
    }
  }
  // The bend survived the seek: the note sounds a tritone up (6 of 12 semitones at bend 12288).
  audio::RenderedAudio shifted = from2;
  shifted.left.insert(shifted.left.begin(), static_cast<std::size_t>(2 * kRate), 0.0f);
  const double expected = std::pow(2.0, 12700.0 * 12 / 128 * 4096 / 8192 / 1200);  // as in PitchBendFollowsItsRpnRange
  EXPECT_NEAR(pitch_hz(shifted, 2.55, 2.8, 622) / pitch_hz(full, 2.55, 2.8, 622), 1.0, 0.002)
      << "not the full render's pitch";
  EXPECT_NEAR(pitch_hz(full, 2.55, 2.8, 622) / 442.0, expected, 0.006);
}

TEST_F(ControlsRender, ASeekBackUndoesControllersSetLater) {
  // One synthesizer plays past controllers set at 1.5 s (reverb and chorus sends up, volume down, pan
  // right, bend range 12 and a bend, pedal down), then seeks back to 0.5 s: the note at 1.0 s must sound
  // as it does from a fresh synthesizer seeking there (the controllers of 0.5 s are the defaults).
  Events e;
  e.program(0, 0, 19)
      .on(1000, 0, 69)
      .off(300, 0, 69)
      .raw(200, {0xB0, 91, 127})
      .raw(0, {0xB0, 93, 127})
      .raw(0, {0xB0, 7, 30})
      .raw(0, {0xB0, 10, 127})
      .raw(0, {0xB0, 101, 0})
      .raw(0, {0xB0, 100, 0})
      .raw(0, {0xB0, 6, 12})
      .raw(0, {0xE0, 0, 0x7F})
      .raw(0, {0xB0, 64, 127});
  const std::vector<audio::AudioEvent> events = audio::audio_events(song_of(e));
  audio::SynthSettings settings;
  settings.sample_rate = kRate;
  const audio::AudioBackend* backend = audio::audio_backend();
  ASSERT_NE(backend, nullptr);
  auto run = [&](bool played_past) {
    const std::unique_ptr<audio::Synth> synth = backend->make_synth(settings);
    EXPECT_TRUE(synth->load_soundfont(*audio::find_soundfont("")));
    synth->set_events(events);
    std::vector<float> l(static_cast<std::size_t>(kRate) * 2), r(l.size());
    if (played_past) synth->render(l.data(), r.data(), l.size());  // to 2.0 s
    synth->seek(500'000);
    audio::RenderedAudio out;
    out.left.resize(static_cast<std::size_t>(kRate)), out.right.resize(out.left.size());
    synth->render(out.left.data(), out.right.data(), out.left.size());  // 0.5 → 1.5 s
    return out;
  };
  const auto again = run(true), fresh = run(false);
  for (int ch = 0; ch < 2; ++ch) {
    EXPECT_NEAR(level_db(again, 1.0, 1.3, 0.5, ch), level_db(fresh, 1.0, 1.3, 0.5, ch), 0.2) << "channel " << ch;
    EXPECT_NEAR(level_db(again, 1.35, 1.5, 0.5, ch), level_db(fresh, 1.35, 1.5, 0.5, ch), 1.0)
        << "release, channel " << ch;
  }
  audio::RenderedAudio a = again, f = fresh;
  a.left.insert(a.left.begin(), static_cast<std::size_t>(kRate / 2), 0.0f);
  f.left.insert(f.left.begin(), static_cast<std::size_t>(kRate / 2), 0.0f);
  EXPECT_NEAR(pitch_hz(a, 1.05, 1.25, 440) / pitch_hz(f, 1.05, 1.25, 440), 1.0, 0.002) << "the bend stayed";
}

TEST_F(ControlsRender, ASeekSilencesANoteHeldByThePedal) {
  // An organ note released under the pedal rings at 1 s; a seek to 2 s, where the pedal is still down but
  // no note sounds, must leave silence (the seek stops every voice before the controllers come back).
  // Reverb and chorus off: their tails are not notes (a seek does not clear them; they fade in ~1 s).
  Events e;
  e.program(0, 0, 19).raw(0, {0xB0, 64, 127}).on(100, 0, 69).off(200, 0, 69).raw(3000, {0xB0, 64, 0}).end();
  const std::vector<audio::AudioEvent> events = audio::audio_events(song_of(e));
  audio::SynthSettings settings;
  settings.sample_rate = kRate;
  settings.reverb = settings.chorus = false;
  const std::unique_ptr<audio::Synth> synth = audio::audio_backend()->make_synth(settings);
  ASSERT_TRUE(synth->load_soundfont(*audio::find_soundfont("")));
  synth->set_events(events);
  audio::RenderedAudio a;
  a.left.resize(static_cast<std::size_t>(kRate)), a.right.resize(a.left.size());
  synth->render(a.left.data(), a.right.data(), a.left.size());
  ASSERT_GT(level_db(a, 0.7, 1.0), -60.0) << "the pedalled note does not ring before the seek";
  synth->seek(2'000'000);
  synth->render(a.left.data(), a.right.data(), a.left.size());
  EXPECT_LT(level_db(a, 0.0, 1.0), -120.0) << "a note held by the pedal rings on after a seek";
}

TEST(ControlsRead, InfoListsTheControllersOfEachTracksChannels) {
  // Track 1 on channel 0: sustain, volume (twice), a bend, a program set once then again the same; track 2
  // on channel 1: the RPN bend range, pan and a change to another program; track 3: notes only.
  Events a, b, c;
  a.program(0, 0, 0)
      .raw(0, {0xB0, 64, 127})
      .raw(0, {0xB0, 7, 90})
      .raw(0, {0xB0, 7, 100})
      .raw(0, {0xE0, 0, 0x50})
      .program(0, 0, 0)
      .on(0, 0, 60)
      .off(100, 0, 60)
      .end();
  b.program(0, 1, 0)
      .raw(0, {0xB1, 101, 0})
      .raw(0, {0xB1, 100, 0})
      .raw(0, {0xB1, 6, 12})
      .raw(0, {0xB1, 10, 0})
      .on(0, 1, 60)
      .off(100, 1, 60)
      .program(0, 1, 40)
      .on(0, 1, 62)
      .off(100, 1, 62)
      .end();
  c.on(0, 2, 60).off(100, 2, 60).end();
  Events conductor;
  conductor.tempo(0, 500000).end();
  const midi::Song song = midi::read_smf(midi_test::smf(1, 500, {conductor, a, b, c})).song;
  using V = std::vector<std::string>;
  EXPECT_EQ(midi::controllers_used(song, 1), (V{"volume", "sustain", "pitch bend"}));
  EXPECT_EQ(midi::controllers_used(song, 2), (V{"data entry", "pan", "RPN", "program changes"}));
  EXPECT_EQ(midi::controllers_used(song, 3), V{});
  EXPECT_EQ(midi::controllers_used(song, 99), V{});
}

TEST(ControlsRead, TheReaderKeepsTheSoundsControllersOnly) {
  Events e;
  e.raw(0, {0xB3, 64, 127})
      .raw(10, {0xB3, 20, 5})  // sustain kept; CC 20 (undefined) dropped
      .raw(10, {0xE3, 0x01, 0x40})
      .raw(10, {0xD3, 77})  // pitch bend 8193, channel pressure 77
      .raw(10, {0xC3, 42})
      .raw(10, {0xB3, 121, 0})
      .raw(10, {0xB3, 123, 0});
  const midi::Song song = song_of(e);
  using K = midi::Control::Kind;
  const std::vector<midi::Control> expected = {{0, K::controller, 3, 64, 127}, {20, K::pitch_bend, 3, 0, 8193},
                                               {30, K::pressure, 3, 0, 77},    {40, K::program, 3, 42, 0},
                                               {50, K::controller, 3, 121, 0}, {60, K::controller, 3, 123, 0}};
  ASSERT_EQ(song.controls.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(song.controls[i].tick, expected[i].tick) << i;
    EXPECT_EQ(song.controls[i].kind, expected[i].kind) << i;
    EXPECT_EQ(song.controls[i].channel, expected[i].channel) << i;
    EXPECT_EQ(song.controls[i].number, expected[i].number) << i;
    EXPECT_EQ(song.controls[i].value, expected[i].value) << i;
  }
}

}  // namespace
