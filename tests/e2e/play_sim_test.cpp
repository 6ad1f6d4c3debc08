// `hmp play` on the simulated device, end to end (design §3, §10): a 10 s passage of the demo's flute
// through the hmp binary, headless, with --log; every note of the passage (counted independently from
// `hmp info --json --notes`) starts on its scheduled tick, spaced like the song; nothing late, stolen or
// rejected. Then, at the library level on the real-time simulated device: pause, seek and quit leave no
// voice sounding and no note queued.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "play_harness.hpp"
#include "host/audio/synth_settings.hpp"
#include "host/transport/sim_transport.hpp"

namespace {

using namespace std::chrono_literals;
using hmp::player::Command;
namespace test = hmp::test;

constexpr std::uint32_t kFlute = 1;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("hmp-e2e-" + std::to_string(::getpid()) + "-" + name)).string();
}

// Every note of the log started on its scheduled tick, and the ticks are spaced as the song's times
// (1 kHz: 1 tick per ms) within `spacing_ticks`.
void expect_on_tick_and_spaced(const test::ParsedLog& log, double spacing_ticks) {
  ASSERT_FALSE(log.notes.empty());
  const test::LogEntry* first = &log.notes.front();
  for (const test::LogEntry& e : log.notes) {
    if (e.start_s < first->start_s) first = &e;
  }
  for (const test::LogEntry& e : log.notes) {
    EXPECT_EQ(e.actual, e.scheduled) << "key " << e.key << " at " << e.start_s;
    const double song_ms = (e.start_s - first->start_s) * 1000.0;
    EXPECT_LE(std::fabs(static_cast<double>(e.scheduled - first->scheduled) - song_ms), spacing_ticks) << e.start_s;
  }
}

template <class F>
bool wait_until(F done, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(5ms);
  }
  return true;
}

TEST(PlaySim, FlutePassageEveryNoteOnItsTick) {
  const double from = 130, to = 140;
  const auto expected = test::passage_notes(kFlute, from, to);
  ASSERT_GT(expected.size(), 40u) << "the reference count from hmp info failed";
  const std::string log_path = temp_path("flute.jsonl");
  std::filesystem::remove(log_path);
  const test::CommandResult r = test::run_command(test::kHmp + " play '" + test::kDemo +
                                                  "' --track flute --no-audio --device sim --from 130 --to 140 --log " +
                                                  log_path + " </dev/null");
  ASSERT_EQ(r.status, 0) << r.err;
  const test::ParsedLog log = test::parse_log(log_path);
  std::filesystem::remove(log_path);

  // The same notes as the file has in the window (key and start), none twice, none missing.
  std::vector<std::pair<int, double>> got;
  for (const test::LogEntry& e : log.notes) {
    EXPECT_EQ(e.track, kFlute);
    got.emplace_back(e.key, e.start_s);
  }
  auto by_time = [](const auto& a, const auto& b) { return std::tie(a.second, a.first) < std::tie(b.second, b.first); };
  std::vector<std::pair<int, double>> want = expected;
  std::sort(got.begin(), got.end(), by_time);
  std::sort(want.begin(), want.end(), by_time);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].first, want[i].first) << i;
    EXPECT_NEAR(got[i].second, want[i].second, 1e-9) << i;
  }

  // On its tick, and the ticks spaced as the song's times (the sync may put the whole passage a
  // rounding away, never a note on its own).
  expect_on_tick_and_spaced(log, 1.0);

  ASSERT_TRUE(log.summary.has_value());
  EXPECT_EQ(log.lines_after_summary, 0);
  const auto& s = *log.summary;
  EXPECT_EQ(s.at("notes_sent").get<std::size_t>(), expected.size());
  EXPECT_EQ(s.at("notes_played").get<std::size_t>(), expected.size());
  EXPECT_EQ(s.at("late").get<int>(), 0);
  EXPECT_EQ(s.at("stolen").get<int>(), 0);
  EXPECT_EQ(s.at("rejected").get<int>(), 0);
  // Headless (no terminal): no status line, one summary on stdout.
  EXPECT_EQ(r.err.find('\r'), std::string::npos);
  EXPECT_NE(r.out.find("played " + std::to_string(expected.size())), std::string::npos) << r.out;
}

TEST(PlaySim, ExistingLogIsNeverOverwrittenWithoutForce) {
  const std::string log_path = temp_path("keep.jsonl");
  { std::ofstream(log_path) << "precious\n"; }
  const test::CommandResult r =
      test::run_command(test::kHmp + " play '" + test::kDemo + "' --no-audio --device sim --from 1 --to 2 --log " +
                        log_path + " </dev/null");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
  std::ifstream in(log_path);
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "precious\n");
  std::filesystem::remove(log_path);
}

TEST(PlaySim, BadWindowIsBadInput) {
  for (const std::string window : {"--from 400", "--from 10 --to 5", "--from -1"}) {
    const test::CommandResult r =
        test::run_command(test::kHmp + " play '" + test::kDemo + "' --no-audio --device sim " + window + " </dev/null");
    EXPECT_EQ(r.status, 2) << window << ": " << r.err;
  }
}

TEST(PlaySim, BadAudioOptionsAreBadInput) {
  for (const std::string option : {"--audio-driver bogus", "--soundfont /nonexistent/hmp-test.sf2"}) {
    const test::CommandResult r =
        test::run_command(test::kHmp + " play '" + test::kDemo + "' --device sim --to 1 " + option + " </dev/null");
    EXPECT_EQ(r.status, 2) << option << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << option << ": " << r.err;
  }
}

TEST(PlaySim, WithSoundOnTheVirtualCardEveryNoteIsOnItsTick) {
  // The whole audio path (FluidSynth, the audio clock, haptic notes placed where their sound starts)
  // on the simulated sound card: the notes still all start on their scheduled ticks, spaced as the song.
  const double from = 130, to = 134;
  const auto expected = test::passage_notes(kFlute, from, to);
  ASSERT_GT(expected.size(), 10u);
  const std::string log_path = temp_path("virtual.jsonl");
  std::filesystem::remove(log_path);
  const test::CommandResult r = test::run_command(
      test::kHmp + " play '" + test::kDemo +
      "' --track flute --audio-driver virtual --device sim --from 130 --to 134 --log " + log_path + " </dev/null");
  ASSERT_EQ(r.status, 0) << r.err;
  const test::ParsedLog log = test::parse_log(log_path);
  std::filesystem::remove(log_path);
  ASSERT_EQ(log.notes.size(), expected.size());
  // Each note follows its own sound, which starts on FluidSynth's block boundary nearest the note's time
  // (64 frames at 48 kHz: ±0.67 ms; the onset lead is taken off and put back, so it cancels), and is
  // then rounded to a tick: two notes' spacing is off the song's by less than a block plus a tick
  // (2.33 ms; a fresh machine measured 2.333), and by 0.05 ms more for the audio clock's learnt rate
  // over the 4 s.
  constexpr int kFluidSynthBlockFrames = 64;  // FluidSynth renders and starts notes in blocks of 64 frames
  const double block_ms = kFluidSynthBlockFrames * 1000.0 / hmp::audio::SynthSettings{}.sample_rate;
  expect_on_tick_and_spaced(log, 1.0 + block_ms + 0.05);
  ASSERT_TRUE(log.summary.has_value());
  EXPECT_EQ(log.summary->at("late").get<int>(), 0);
}

// The device state, read with its clock held still.
struct DeviceView {
  hmp::protocol::State state;
  int voices;
  float output;
  int queued;
};

DeviceView view(hmp::transport::SimTransport& sim) {
  return sim.with_device([](hmp::sim::SimDevice& d) {
    return DeviceView{d.core().state(), d.core().engine().active_voices(), d.last_output(), d.core().queued_notes()};
  });
}

TEST(PlaySim, PauseSeekAndQuitLeaveNothingSounding) {
  hmp::transport::SimTransport sim;  // real time, as `--device sim`
  test::Session s(sim, test::passage(kFlute, 130, 160));
  s.start();
  auto played = [&] { return s.player().snapshot().counters.notes_played; };
  ASSERT_TRUE(wait_until([&] { return played() >= 4; }, 5s));

  // Pause: the device fades out within 15 ms and flushes its queue; nothing starts while paused.
  s.player().post(Command::toggle_pause);
  ASSERT_TRUE(wait_until([&] { return view(sim).state == hmp::protocol::State::paused; }, 1s));
  std::this_thread::sleep_for(40ms);
  DeviceView v = view(sim);
  EXPECT_EQ(v.voices, 0);
  EXPECT_EQ(v.output, 0.0f);
  EXPECT_EQ(v.queued, 0);
  const auto at_pause = played();
  std::this_thread::sleep_for(400ms);  // longer than the device's 250 ms watchdog: it must not trip
  EXPECT_EQ(played(), at_pause);
  v = view(sim);
  EXPECT_EQ(v.state, hmp::protocol::State::paused);
  EXPECT_EQ(v.voices, 0);

  // Resume: notes play again.
  s.player().post(Command::toggle_pause);
  ASSERT_TRUE(wait_until([&] { return played() > at_pause + 1; }, 5s));

  // Seek +5 s: the notes in between are never played; the position moves on.
  const std::int64_t before = s.player().snapshot().song_us;
  s.player().post(Command::seek_forward);
  ASSERT_TRUE(wait_until([&] { return s.player().snapshot().song_us >= before + 4'500'000; }, 1s));
  const double skipped_from = static_cast<double>(before) * 1e-6 + 0.5;  // beyond what was already sent
  const double target = static_cast<double>(before) * 1e-6 + 5.0;
  const auto after_seek = played();
  ASSERT_TRUE(wait_until([&] { return played() > after_seek + 1; }, 5s));
  for (const hmp::player::StartedNote& n : s.started()) {
    EXPECT_FALSE(n.origin.start_s > skipped_from && n.origin.start_s < target - 0.06) << n.origin.start_s;
  }

  // Quit: the device is stopped, silent and empty.
  s.player().post(Command::quit);
  s.join();
  ASSERT_EQ(s.outcome(), hmp::player::Outcome::quit) << s.error();
  std::this_thread::sleep_for(30ms);
  v = view(sim);
  EXPECT_EQ(v.state, hmp::protocol::State::stopped);
  EXPECT_EQ(v.voices, 0);
  EXPECT_EQ(v.output, 0.0f);
  EXPECT_EQ(v.queued, 0);
  for (const hmp::player::StartedNote& n : s.started()) EXPECT_EQ(n.actual_tick, n.scheduled_tick) << n.origin.start_s;
}

}  // namespace
