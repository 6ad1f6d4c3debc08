// `hmp study` in the animation window (2015 §6.1: the complete environment) on a private Xvfb display,
// driven by X key events (xdotool, as a keyboard would type into the window): a participant's practice
// and experiment-1 rounds end in the same rows as the same participant and seed typed in the terminal,
// all but the times. A screenshot of the first main round (the flute's) shows the felt track's blue bars
// and the prompt's line. HMP_STUDY_SHOT=FILE.png keeps it (the picture in docs/study.md). Without a display, --window
// is one line and exit 2, nothing written; without --window, one warning and the terminal. Ctrl+C in the
// window stops the session as in the terminal, and no chord or arrow key ranks.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "host/view/palette.hpp"
#include "play_harness.hpp"
#include "study_keys.hpp"
#include "tests/support/xvfb.hpp"
#include "window_keys.hpp"

namespace {

namespace fs = std::filesystem;
namespace test = hmp::test;

constexpr const char* kParticipant = "wendy";

// A seed whose first main round is the flute's, which the demo opens with: its bars are on screen.
std::uint64_t flute_first_seed() {
  std::uint64_t seed = 1;
  while (hmp::study::make_plan(kParticipant, seed, {1})[2].instrument != "flute") ++seed;
  return seed;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The rows without the columns that hold times (seconds_felt, round_started_utc, ranked_utc,
// round_ended_utc): what the keys decide.
std::vector<std::string> rows_without_times(const std::string& csv) {
  std::vector<std::string> rows;
  std::istringstream in(csv);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::size_t start = 0;
    for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1) {
      f.push_back(line.substr(start, comma - start));
    }
    f.push_back(line.substr(start));
    std::string kept;
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (i == 9 || (i >= 11 && i <= 13)) continue;
      kept += f[i] + ",";
    }
    rows.push_back(kept);
  }
  return rows;
}

// The screen as 8-bit RGB (ffmpeg's X11 grabber): width × height × 3 bytes.
std::vector<std::uint8_t> grab_screen(int width, int height) {
  const fs::path raw = fs::temp_directory_path() / ("hmp-study-shot-" + std::to_string(::getpid()) + ".rgb");
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  test::run_command("ffmpeg -loglevel error -y -f x11grab -video_size " + size + " -i '" + std::getenv("DISPLAY") +
                    "' -vframes 1 -f rawvideo -pix_fmt rgb24 '" + raw.string() + "'");
  if (const char* keep = std::getenv("HMP_STUDY_SHOT")) {
    test::run_command("ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgb24 -video_size " + size + " -i '" +
                      raw.string() + "' '" + keep + "'");
  }
  const std::string bytes = slurp(raw);
  fs::remove(raw);
  return {bytes.begin(), bytes.end()};
}

// The child's wait status once it ends, or after `limit` (then killed: the status says so).
int wait_or_kill(pid_t pid, std::chrono::seconds limit) {
  int status = -1;
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return status;
}

bool near(const std::uint8_t* p, const hmp::view::Rgb& c) {
  return std::abs(p[0] - c.r * 255) < 8 && std::abs(p[1] - c.g * 255) < 8 && std::abs(p[2] - c.b * 255) < 8;
}

class StudyWindowE2e : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hmp-study-window-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "terminal");
    fs::create_directories(dir_ / "window");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(StudyWindowE2e, KeysTypedInTheWindowGiveTheTerminalsRows) {
  ASSERT_TRUE(test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  ASSERT_EQ(std::system("command -v xdotool >/dev/null 2>&1"), 0) << "xdotool is missing (package xdotool)";
  const std::uint64_t kSeed = flute_first_seed();
  const std::string practice =
      test::session_keys(kParticipant, kSeed, 0, 2, test::kAnalogueFirst, test::kTriangleFirst, {1});
  const std::string main =
      test::session_keys(kParticipant, kSeed, 2, 6, test::kAnalogueFirst, test::kTriangleFirst, {1});
  const std::string common = std::string(" study --participant ") + kParticipant + " --seed " + std::to_string(kSeed) +
                             " --experiment 1 --device sim --no-audio";

  // The terminal's run.
  std::ofstream(dir_ / "keys") << practice + main;
  const test::CommandResult terminal =
      test::run_command(test::kHmp + common + " --no-view --out '" + (dir_ / "terminal").string() + "' < '" +
                        (dir_ / "keys").string() + "'");
  ASSERT_EQ(terminal.status, 0) << terminal.err;

  // The window's: the practice song's window first, then the main song's.
  const auto [pid, keyboard] = test::start_hmp_with_keyboard(
      {"study", "--participant", kParticipant, "--seed", std::to_string(kSeed), "--experiment", "1", "--device", "sim",
       "--no-audio", "--window", "--out", (dir_ / "window").string()},
      (dir_ / "window.err").string());
  ASSERT_GT(pid, 0);
  const std::string practice_window = test::window_named("bach-bwv1079-trio-sonata-largo");
  ASSERT_FALSE(practice_window.empty()) << slurp(dir_ / "window.err");
  test::type_into(practice_window, practice);
  const std::string main_window = test::window_named("bach-bwv1050-brandenburg5");
  ASSERT_FALSE(main_window.empty()) << slurp(dir_ / "window.err");
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // a few frames of the first main round
  const std::vector<std::uint8_t> screen = grab_screen(1600, 1000);
  test::type_into(main_window, main);
  const int status = wait_or_kill(pid, std::chrono::seconds(60));
  ::close(keyboard);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status << "\n" << slurp(dir_ / "window.err");

  const auto window_rows = rows_without_times(slurp(dir_ / "window" / "study-results.csv"));
  const auto terminal_rows = rows_without_times(slurp(dir_ / "terminal" / "study-results.csv"));
  EXPECT_EQ(window_rows.size(), 1u + 6u * 3u);
  EXPECT_EQ(window_rows, terminal_rows);

  // The screenshot: the felt track's blue bars, and the top line's text (the prompt) light on dark.
  ASSERT_EQ(screen.size(), 1600u * 1000u * 3u);
  int blue = 0, text = 0;
  for (std::size_t i = 0; i + 2 < screen.size(); i += 3) {
    blue += near(&screen[i], hmp::view::kHapticBlue);
    text += screen[i] > 200 && screen[i + 1] > 200 && screen[i + 2] > 200;
  }
  EXPECT_GT(blue, 1000);
  EXPECT_GT(text, 300);
}

// Ctrl+C in the window stops the session as in the terminal (exit 130, resumable, no row written): it was
// read as c, rank C, and the session went on. (Alt+a and the arrows typed before it must not stop it; that
// they rank nothing is the key mapping's test, tests/host/player/key_decoder_test.cpp for the terminal.)
TEST_F(StudyWindowE2e, CtrlCInTheWindowStopsAndRanksNothing) {
  ASSERT_TRUE(test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  ASSERT_EQ(std::system("command -v xdotool >/dev/null 2>&1"), 0) << "xdotool is missing (package xdotool)";
  const auto [pid, keyboard] =
      test::start_hmp_with_keyboard({"study", "--participant", kParticipant, "--seed", "7", "--experiment", "1",
                                     "--device", "sim", "--no-audio", "--window", "--out", (dir_ / "window").string()},
                                    (dir_ / "window.err").string());
  ASSERT_GT(pid, 0);
  const std::string practice_window = test::window_named("bach-bwv1079-trio-sonata-largo");
  ASSERT_FALSE(practice_window.empty()) << slurp(dir_ / "window.err");
  test::run_command("xdotool windowfocus --sync " + practice_window);
  for (const char* chord : {"alt+a", "Up", "Down", "Right", "ctrl+c"}) {
    test::run_command(std::string("xdotool key ") + chord);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const int status = wait_or_kill(pid, std::chrono::seconds(10));
  ::close(keyboard);
  const std::string err = slurp(dir_ / "window.err");
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << status << "\n" << err;
  EXPECT_EQ(rows_without_times(slurp(dir_ / "window" / "study-results.csv")).size(), 1u);  // the header alone
  EXPECT_NE(err.find("Run the same command again to resume"), std::string::npos) << err;
}

TEST_F(StudyWindowE2e, WindowWithoutADisplayIsOneLineAndNothingWritten) {
  const test::CommandResult r = test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + test::kHmp +
                                                  " study --participant nod --device sim --no-audio --window --out '" +
                                                  (dir_ / "window").string() + "' </dev/null");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("--window"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(dir_ / "window"));
  const test::CommandResult both = test::run_command(
      test::kHmp + " study --participant nod --window --no-view --out '" + (dir_ / "window").string() + "' </dev/null");
  EXPECT_EQ(both.status, 2) << both.err;
  EXPECT_TRUE(fs::is_empty(dir_ / "window"));
  // Without --window: one warning, and the terminal's session (its input ends at once: stopped, resumable).
  const test::CommandResult plain = test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + test::kHmp +
                                                      " study --participant nod --device sim --no-audio --out '" +
                                                      (dir_ / "window").string() + "' </dev/null");
  EXPECT_EQ(plain.status, 130) << plain.err;
  std::size_t warnings = 0;
  for (std::size_t at = plain.err.find("warning: no animation window"); at != std::string::npos;
       at = plain.err.find("warning: no animation window", at + 1)) {
    ++warnings;
  }
  EXPECT_EQ(warnings, 1u) << plain.err;
  EXPECT_TRUE(fs::exists(dir_ / "window" / "study-nod.journal"));
}

}  // namespace
