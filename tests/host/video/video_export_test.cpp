// The video export (hmp render --out FILE.mp4) checked from the outside: ffprobe says what the file holds
// (streams, codecs, size, rate, colour tags, frame count, duration), ffmpeg decodes it, and the decoded
// pictures and sound are compared with references made here without the encoder: a frame with the
// off-screen painter's frame for the same time and with where RollLayout puts a sounding note; the sound
// with FluidSynth's offline render of the song, and the haptic stream with the shared engine's signal,
// both by cross-correlation: the lag must be zero (locked sample for sample).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "host/audio/offline_render.hpp"
#include "host/common/error.hpp"
#include "host/haptics/signal_renderer.hpp"
#include "host/audio/wav_file.hpp"
#include "host/video/video_export.hpp"
#include "host/view/roll_layout.hpp"
#include "tests/e2e/play_harness.hpp"
#include "tests/support/midi_builder.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hmp;
using test::run_command;

// 500 ticks a quarter at 120 bpm: a tick is 1 ms. Track 0 a flute (the haptic track): key 72 at 1.0 s for
// 0.5 s and key 76 at 2.0 s for 0.3 s; track 1 a piano: key 48 from 1.5 s for 1 s.
midi_test::Bytes song_bytes() {
  midi_test::Events flute, piano;
  flute.name(0, "flute")
      .tempo(0, 500000)
      .program(0, 0, 73)
      .on(1000, 0, 72)
      .off(500, 0, 72)
      .on(500, 0, 76)
      .off(300, 0, 76)
      .end();
  piano.name(0, "piano").program(0, 1, 0).on(1500, 1, 48).off(1000, 1, 48).end();
  return midi_test::smf(1, 500, {flute, piano});
}

struct Fixture {
  fs::path dir = fs::temp_directory_path() / ("hmp-video-test-" + std::to_string(::getpid()));
  fs::path midi = dir / "song.mid";
  Fixture() {
    fs::create_directories(dir);
    const midi_test::Bytes b = song_bytes();
    std::ofstream(midi, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  }
  ~Fixture() { fs::remove_all(dir); }
};

nlohmann::json probe(const fs::path& file) {
  const test::CommandResult r =
      run_command("ffprobe -v error -count_frames -show_streams -show_format -of json '" + file.string() + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  return nlohmann::json::parse(r.out, nullptr, false);
}

std::vector<float> decode_audio(const fs::path& file, int stream, int channels) {
  const test::CommandResult r =
      run_command("ffmpeg -v error -i '" + file.string() + "' -map 0:a:" + std::to_string(stream) + " -f f32le -ac " +
                  std::to_string(channels) + " -ar 44100 -");
  EXPECT_EQ(r.status, 0) << r.err;
  std::vector<float> s(r.out.size() / sizeof(float));
  std::memcpy(s.data(), r.out.data(), s.size() * sizeof(float));
  return s;
}

std::vector<std::uint8_t> decode_frame(const fs::path& file, int n) {
  // Back to full-range RGB with the matrix and range the stream is tagged with (BT.709, limited).
  const test::CommandResult r = run_command(
      "ffmpeg -v error -i '" + file.string() + "' -vf 'select=eq(n\\," + std::to_string(n) +
      "),scale=in_color_matrix=bt709:in_range=tv:out_range=pc:flags=bicubic+accurate_rnd+full_chroma_int' -vsync 0 "
      "-frames:v 1 -f rawvideo -pix_fmt rgb24 -");
  EXPECT_EQ(r.status, 0) << r.err;
  return {r.out.begin(), r.out.end()};
}

// The lag (in samples, |lag| ≤ max_lag) at which `b` best matches `a` over a[from, to): the normalised
// cross-correlation, so that a growing note (an attack) does not pull the match towards the louder side.
long best_lag(const std::vector<float>& a, const std::vector<float>& b, std::size_t from, std::size_t to,
              long max_lag) {
  long best = 0;
  double best_score = -2;
  for (long lag = -max_lag; lag <= max_lag; ++lag) {
    double ab = 0, aa = 0, bb = 0;
    for (std::size_t i = from; i < to; ++i) {
      const long j = static_cast<long>(i) + lag;
      if (j < 0 || static_cast<std::size_t>(j) >= b.size()) continue;
      const auto x = static_cast<double>(a[i]), y = static_cast<double>(b[static_cast<std::size_t>(j)]);
      ab += x * y;
      aa += x * x;
      bb += y * y;
    }
    const double score = aa > 0 && bb > 0 ? ab / std::sqrt(aa * bb) : -2;
    if (score > best_score) {
      best_score = score;
      best = lag;
    }
  }
  return best;
}

// One channel of interleaved samples.
std::vector<float> channel(const std::vector<float>& interleaved, int channels, int c) {
  std::vector<float> out;
  for (std::size_t i = static_cast<std::size_t>(c); i < interleaved.size(); i += static_cast<std::size_t>(channels))
    out.push_back(interleaved[i]);
  return out;
}

class VideoExport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fixture_ = new Fixture;
    read_ = midi::load_song(fixture_->midi);
    spec_.song = &read_.song;
    spec_.haptic = std::make_shared<const haptics::HapticTrack>(haptics::build_haptic_track(read_.song, 0, options_));
    spec_.haptic_options = options_;
    spec_.from_us = 0;
    spec_.to_us = 3'000'000;
    spec_.haptic_audio = true;
    spec_.legend_labels = {"0 flute (Flute)", "1 piano (Piano)"};
    spec_.overlay_prefix = "video test";
    file_ = fixture_->dir / "song.mp4";
    result_ = video::export_video(file_.string(), spec_, {}, [](const std::string& w) { ADD_FAILURE() << w; });
  }
  static void TearDownTestSuite() { delete fixture_; }

  static inline Fixture* fixture_ = nullptr;
  static inline midi::ReadResult read_;
  static inline haptics::HapticOptions options_;
  static inline video::VideoExportSpec spec_;
  static inline fs::path file_;
  static inline video::VideoExportResult result_;
};

TEST_F(VideoExport, FfprobeSeesTheStreamsFramesAndDuration) {
  ASSERT_TRUE(fs::exists(file_));
  EXPECT_FALSE(fs::exists(file_.string() + ".part")) << "the temporary file stayed";
  const nlohmann::json j = probe(file_);
  ASSERT_TRUE(j.is_object());
  ASSERT_EQ(j["streams"].size(), 3u);
  const nlohmann::json& v = j["streams"][0];
  EXPECT_EQ(v["codec_name"], "h264");
  EXPECT_EQ(v["width"], 1280);
  EXPECT_EQ(v["height"], 720);
  EXPECT_EQ(v["r_frame_rate"], "60/1");
  EXPECT_EQ(v["pix_fmt"], "yuv420p");
  EXPECT_EQ(v["color_space"], "bt709");
  EXPECT_EQ(v["color_range"], "tv");
  EXPECT_EQ(std::stoi(v["nb_read_frames"].get<std::string>()), 180);  // 3 s at 60 fps, counted by decoding
  EXPECT_EQ(result_.frames, 180u);
  EXPECT_NEAR(std::stod(v["duration"].get<std::string>()), 3.0, 1e-6);
  for (const int a : {1, 2}) {
    const nlohmann::json& s = j["streams"][a];
    EXPECT_EQ(s["codec_name"], "aac");
    EXPECT_EQ(s["sample_rate"], "44100");
    EXPECT_EQ(s["channels"], a == 1 ? 2 : 1);
    EXPECT_NEAR(std::stod(s["duration"].get<std::string>()), 3.0, 1e-6) << "audio " << a;
  }
  EXPECT_EQ(j["streams"][1]["tags"]["handler_name"], "song");
  EXPECT_EQ(j["streams"][2]["tags"]["handler_name"], "haptic signal");
  // The edit list gives the audio's exact length: 735 samples a frame (the encoder's priming before and
  // padding after are outside it).
  EXPECT_EQ(j["streams"][1]["duration_ts"], 180 * 735);
  EXPECT_EQ(j["streams"][2]["duration_ts"], 180 * 735);
  EXPECT_NEAR(std::stod(j["format"]["duration"].get<std::string>()), 3.0, 1e-3);
}

TEST_F(VideoExport, TheSongsSoundIsLockedToTheFrames) {
  const std::vector<float> decoded = channel(decode_audio(file_, 0, 2), 2, 0);
  // The priming is skipped (lag 0 below); ffmpeg's decoder keeps the padding of the last AAC frame, so the
  // decoded stream is the edit list's 735 samples a frame plus less than one frame of 1024.
  EXPECT_GE(decoded.size(), result_.frames * 735);
  EXPECT_LT(decoded.size(), result_.frames * 735 + 1024);
  audio::AudioOptions options;
  options.synth.sample_rate = 44100;
  const audio::RenderedAudio reference = audio::render_offline(audio::audio_events(read_.song), 0, 3'000'000, options);
  ASSERT_FALSE(reference.silent_fallback) << "no SoundFont (fluid-soundfont-gm)";
  // Around the flute's entry at 1.0 s: the decoded sound matches the reference at lag 0, to the sample.
  EXPECT_EQ(best_lag(reference.left, decoded, 44100 * 95 / 100, 44100 * 14 / 10, 400), 0);
  // And it is the song's sound, not silence: the same level within AAC's loss.
  double e_ref = 0, e_dec = 0;
  for (std::size_t i = 44100; i < 66150; ++i) {
    e_ref += static_cast<double>(reference.left[i]) * static_cast<double>(reference.left[i]);
    e_dec += static_cast<double>(decoded[i]) * static_cast<double>(decoded[i]);
  }
  EXPECT_NEAR(10 * std::log10(e_dec / e_ref), 0.0, 0.5) << "level in dB against FluidSynth's own render";
}

TEST_F(VideoExport, TheHapticStreamIsTheTracksSignal) {
  const std::vector<float> decoded = decode_audio(file_, 1, 1);
  EXPECT_GE(decoded.size(), result_.frames * 735);
  haptics::RenderSettings settings;  // written out here: the test's own reading of the options
  settings.synth.tick_hz = options_.tick_hz;
  settings.synth.end_fade_ms = static_cast<float>(options_.end_fade_ms);
  settings.polyphony = options_.polyphony;
  const auto notes = spec_.haptic->device_notes();
  const std::vector<float> signal =
      haptics::render_signal(notes, spec_.haptic->uploads, settings, 0, 3 * options_.tick_hz);
  const std::vector<float> reference = audio::resample(signal, static_cast<int>(options_.tick_hz), 44100);
  EXPECT_EQ(best_lag(reference, decoded, 44100 * 95 / 100, 44100 * 16 / 10, 400), 0);
}

TEST_F(VideoExport, AFrameShowsWhatTheWindowWouldAtItsTime) {
  const int n = 72;  // 1.2 s: the flute's first note sounds, the piano's has not begun
  const std::vector<std::uint8_t> decoded = decode_frame(file_, n);
  ASSERT_EQ(decoded.size(), 1280u * 720u * 3u);
  // The painter's frame for that time (on a thread of its own: it makes its own GL context current).
  std::vector<std::uint8_t> painted;
  std::string error;
  std::thread([&] {
    view::ViewSetup setup;
    setup.song = &read_.song;
    auto frames = view::open_offscreen(setup, error);
    if (!frames) return;
    const haptics::SignalTail tail(spec_.haptic, spec_.haptic_options);
    const std::uint8_t* px = frames->draw(video::video_frame_state(spec_, tail, video::frame_time_us(0, n, 60)));
    painted.assign(px, px + 1280u * 720u * 4u);
  }).join();
  ASSERT_FALSE(painted.empty()) << error;
  double squared = 0;
  for (int y = 0; y < 720; ++y) {
    for (int x = 0; x < 1280; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double a = decoded[(static_cast<std::size_t>(y) * 1280 + static_cast<std::size_t>(x)) * 3 +
                                 static_cast<std::size_t>(c)];
        const double b = painted[(static_cast<std::size_t>(719 - y) * 1280 + static_cast<std::size_t>(x)) * 4 +
                                 static_cast<std::size_t>(c)];
        squared += (a - b) * (a - b);
      }
    }
  }
  const double psnr = 10 * std::log10(255.0 * 255.0 / (squared / (1280.0 * 720.0 * 3.0)));
  // H.264 at crf 20 with 4:2:0 chroma keeps flat graphics well above 35 dB; a frame of another time (bars
  // shifted by a frame's 1.8 pixels) or a wrong colour matrix falls far below.
  EXPECT_GT(psnr, 35.0);

  // Independently of the painter: the sounding flute note's bar centre is yellow where RollLayout puts it.
  view::LayoutParams p;
  std::tie(p.key_low, p.key_high) = view::key_range(read_.song);
  p = view::for_drawable(p, 1280, 720, 1.0f, spec_.seconds_across);
  const view::RollLayout layout(p, 2, 0);
  const std::int64_t now = video::frame_time_us(0, n, 60);
  const view::Rect r = layout.bar_rect(view::Bar{1'000'000, 1'500'000, 72, 100, 0}, now);
  const auto cx = static_cast<std::size_t>((r.x0 + r.x1) / 2), cy = static_cast<std::size_t>((r.y0 + r.y1) / 2);
  const std::uint8_t* centre = &decoded[(cy * 1280 + cx) * 3];
  EXPECT_NEAR(centre[0], view::kSoundingYellow.r * 255, 12);
  EXPECT_NEAR(centre[1], view::kSoundingYellow.g * 255, 12);
  EXPECT_NEAR(centre[2], view::kSoundingYellow.b * 255, 12);
}

TEST(VideoFrames, FrameTimesAndCountsAreExact) {
  for (const int fps : {25, 30, 50, 60}) {
    for (std::uint64_t i = 0; i < 100000; i += 7) {
      const double exact = 123456.0 + static_cast<double>(i) * 1e6 / fps;
      EXPECT_NEAR(static_cast<double>(video::frame_time_us(123456, i, fps)), exact, 0.5) << fps << " " << i;
    }
  }
  EXPECT_EQ(video::frame_count(0, 1'000'000, 60), 60u);
  EXPECT_EQ(video::frame_count(0, 1'000'001, 60), 61u);
  EXPECT_EQ(video::frame_count(5, 5, 60), 1u);                     // never no frame
  EXPECT_EQ(video::frame_count(0, 3'600'000'000LL, 60), 216000u);  // an hour: no overflow
}

TEST(VideoFrames, SpecsThatCannotWorkAreRefusedBeforeAnyWork) {
  midi::Song song;
  video::VideoExportSpec ok;
  ok.song = &song;
  ok.haptic = std::make_shared<const haptics::HapticTrack>();
  ok.to_us = 1'000'000;
  EXPECT_NO_THROW(video::check_video_spec(ok));
  auto refused = [&](auto change, const std::string& words) {
    video::VideoExportSpec s = ok;
    change(s);
    try {
      video::check_video_spec(s);
      ADD_FAILURE() << "accepted: " << words;
    } catch (const BadInput& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused([](auto& s) { s.encoding.fps = 24; }, "--fps 24");  // 44100 / 24 is not whole
  refused([](auto& s) { s.encoding.fps = 0; }, "--fps 0");
  refused([](auto& s) { s.encoding.fps = 1000; }, "--fps 1000");
  refused([](auto& s) { s.encoding.width = 1281; }, "--size 1281x720");
  refused([](auto& s) { s.encoding.height = 8; }, "--size 1280x8");
  refused([](auto& s) { s.encoding.crf = 52; }, "--crf 52");
  refused([](auto& s) { s.encoding.preset = "warp"; }, "--video-preset warp");
  refused([](auto& s) { s.to_us = 0; }, "empty passage");
}

}  // namespace
