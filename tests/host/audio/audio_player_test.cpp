// AudioPlayer without sound: `--no-audio` creates no driver (counted), a machine without a sound card
// (CI) falls back to silence with exactly one warning and nothing on stderr, a missing SoundFont does
// not even try a driver, and the player's clock runs, pauses, resumes and seeks on the host clock.
// On a machine that does have audio, the fallback test checks the latency estimate instead.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include "host/audio/audio_player.hpp"
#include "host/audio/audio_backend.hpp"
#include "host/audio/soundfont.hpp"

namespace {

using namespace std::chrono_literals;
using hmp::audio::AudioOptions;
using hmp::audio::AudioPlayer;

struct Warnings {
  std::vector<std::string> list;
  hmp::audio::WarningSink sink() {
    return [this](const std::string& w) { list.push_back(w); };
  }
};

TEST(AudioPlayer, NoAudioNeverTouchesAnAudioDevice) {
  const std::uint64_t attempts = hmp::audio::audio_driver_attempts();
  AudioOptions options;
  options.enabled = false;
  Warnings w;
  testing::internal::CaptureStderr();
  AudioPlayer player(options, w.sink());
  player.set_events({});
  player.start(0);
  player.pause();
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(hmp::audio::audio_driver_attempts(), attempts);
  EXPECT_TRUE(w.list.empty());  // the user asked for it: nothing to warn about
  EXPECT_FALSE(player.audible());
  EXPECT_EQ(player.driver_name(), "none");
  EXPECT_EQ(player.output_latency_s(), 0.0);
  EXPECT_EQ(player.callbacks(), 0u);
  EXPECT_FALSE(player.wait_for_first_callback(1ms));
}

// A driver may choose its own period (JACK's, PipeWire's quantum): once it has called back, the latency
// estimate is the chosen period's, not the one asked for (`hmp live --sync-sound` waits for that callback
// before it sets the vibration's delay).
TEST(AudioPlayer, LatencyIsThePeriodTheDriverChoseFromItsFirstCallback) {
  ASSERT_TRUE(hmp::audio::find_soundfont().has_value()) << "no GM SoundFont (fluid-soundfont-gm)";
  AudioOptions options;
  options.drivers = {"virtual"};
  options.period_frames = 256;
  options.virtual_period_frames = 1024;
  AudioPlayer player(options);
  ASSERT_NE(player.virtual_card(), nullptr) << player.silence_reason();
  player.set_events({});
  player.start(0);
  ASSERT_TRUE(player.wait_for_first_callback(2s)) << "the virtual card never asked for a period";
  EXPECT_GT(player.callbacks(), 0u);
  const double rate = options.synth.sample_rate;
  EXPECT_DOUBLE_EQ(player.output_latency_s(), 1024.0 * options.periods / rate);
  EXPECT_DOUBLE_EQ(player.output_latency_s(), player.virtual_card()->latency_s());
  player.stop();
}

TEST(AudioPlayer, WithoutASoundDeviceFallsBackToSilenceWithOneWarning) {
  if (!hmp::audio::find_soundfont()) GTEST_SKIP() << "no GM SoundFont installed";
  const std::uint64_t attempts = hmp::audio::audio_driver_attempts();
  AudioOptions options;
  Warnings w;
  testing::internal::CaptureStderr();
  {
    AudioPlayer player(options, w.sink());
    if (player.audible()) {
      // A machine with sound: the estimate follows the settings (256 × 4 / 48000 = 21.3 ms) or the
      // period the driver chose; either way a plausible buffer.
      EXPECT_GT(player.output_latency_s(), 0.0);
      EXPECT_LT(player.output_latency_s(), 0.5);
      EXPECT_TRUE(w.list.empty());
    } else {
      ASSERT_EQ(w.list.size(), 1u);
      EXPECT_NE(w.list[0].find("no audio output could be opened"), std::string::npos) << w.list[0];
      EXPECT_NE(w.list[0].find("pulseaudio"), std::string::npos) << w.list[0];
      EXPECT_EQ(player.driver_name(), "none");
      EXPECT_EQ(player.output_latency_s(), 0.0);
      EXPECT_EQ(hmp::audio::audio_driver_attempts(), attempts + options.drivers.size());
    }
    player.start(0);
    std::this_thread::sleep_for(20ms);
    player.stop();
  }
  // FluidSynth's and ALSA's own messages are captured, not printed.
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(AudioPlayer, MissingSoundFontWarnsOnceAndTriesNoDriver) {
  const std::uint64_t attempts = hmp::audio::audio_driver_attempts();
  AudioOptions options;
  options.soundfont = "/nonexistent/FluidR3_GM.sf2";
  Warnings w;
  AudioPlayer player(options, w.sink());
  ASSERT_EQ(w.list.size(), 1u);
  EXPECT_NE(w.list[0].find("/nonexistent/FluidR3_GM.sf2"), std::string::npos) << w.list[0];
  EXPECT_FALSE(player.audible());
  EXPECT_EQ(hmp::audio::audio_driver_attempts(), attempts);
  EXPECT_FALSE(player.silence_reason().empty());
}

// A file FluidSynth cannot load: the warning says so in full. Its text was the synthesizer's own, and was
// read after the synthesizer had gone (bytes of freed memory, different every run).
TEST(AudioPlayer, ABrokenSoundFontIsNamedInItsWarning) {
  const auto path = std::filesystem::temp_directory_path() / ("hmp-broken-" + std::to_string(::getpid()) + ".sf2");
  std::ofstream(path) << "RIFF this is not a SoundFont";
  AudioOptions options;
  options.soundfont = path.string();
  options.drivers = {"virtual"};
  Warnings w;
  {
    AudioPlayer player(options, w.sink());
    EXPECT_FALSE(player.audible());
    EXPECT_EQ(player.silence_reason(), "cannot load SoundFont " + path.string() + " (not a SoundFont 2 file)");
  }
  std::filesystem::remove(path);
  ASSERT_EQ(w.list.size(), 1u);
  EXPECT_EQ(w.list[0],
            "audio: cannot load SoundFont " + path.string() + " (not a SoundFont 2 file): playing without sound");
}

TEST(AudioPlayer, SilentClockRunsPausesResumesAndSeeks) {
  AudioOptions options;
  options.enabled = false;
  AudioPlayer player(options, [](const std::string&) {});
  EXPECT_EQ(player.song_time_us(), 0);
  EXPECT_FALSE(player.playing());

  const auto t0 = std::chrono::steady_clock::now();
  player.start(2'000'000);
  std::this_thread::sleep_for(100ms);
  const auto t1 = std::chrono::steady_clock::now();
  const std::int64_t at = player.song_time_us(t1);
  // Exactly the host time elapsed since start (within the start call's own duration).
  const auto elapsed = std::chrono::duration_cast<std::chrono::microseconds>(t1 - t0).count();
  EXPECT_LE(at, 2'000'000 + elapsed + 1);  // +1: whole-µs rounding
  EXPECT_GE(at, 2'000'000 + elapsed - 5'000);
  EXPECT_NEAR(static_cast<double>((player.heard_at(at) - t1).count()), 0.0, 2e3);  // inverse, ns

  player.pause();
  const std::int64_t paused = player.song_time_us();
  std::this_thread::sleep_for(30ms);
  EXPECT_EQ(player.song_time_us(), paused);
  EXPECT_FALSE(player.playing());

  player.resume();
  std::this_thread::sleep_for(30ms);
  EXPECT_GE(player.song_time_us(), paused + 25'000);

  player.seek(10'000'000);  // while playing: keeps playing from there
  EXPECT_TRUE(player.playing());
  EXPECT_GE(player.song_time_us(), 10'000'000);
  EXPECT_LT(player.song_time_us(), 10'500'000);

  player.stop();
  const std::int64_t stopped = player.song_time_us();
  player.seek(1'000'000);  // while stopped: only moves the position
  EXPECT_FALSE(player.playing());
  EXPECT_EQ(player.song_time_us(), 1'000'000);
  EXPECT_GE(stopped, 10'000'000);
}

}  // namespace
