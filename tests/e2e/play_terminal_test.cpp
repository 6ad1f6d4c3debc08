// `hmp play` on a terminal (design §3, §14): the hmp binary runs on a pseudo-terminal; the live keys
// (space, →, t, n, p, q, Esc, Ctrl-C; other escape sequences do nothing) act and the one-line status shows it; the
// terminal's settings come back when hmp ends.
#include <gtest/gtest.h>

#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "play_harness.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
namespace test = hmp::test;

class PtySession {
 public:
  // hmp play SONGS… --no-audio --device sim (the demo's flute from 130 s to 170 s by default).
  explicit PtySession(std::vector<std::string> args = {test::kDemo, "--track", "flute", "--from", "130", "--to",
                                                       "170"}) {
    args.insert(args.begin(), {"hmp", "play", "--no-audio", "--device", "sim"});
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    winsize ws{};
    ws.ws_row = 24;
    ws.ws_col = 220;
    pid_ = ::forkpty(&master_, nullptr, nullptr, &ws);
    if (pid_ == 0) {
      ::execv(test::kHmp.c_str(), argv.data());
      ::_exit(127);
    }
  }
  ~PtySession() {
    if (pid_ > 0 && !status_) {
      ::kill(pid_, SIGKILL);  // the child this test started
      ::waitpid(pid_, nullptr, 0);
    }
    if (master_ >= 0) ::close(master_);
  }
  bool started() const { return pid_ > 0 && master_ >= 0; }
  void type(const std::string& keys) {
    ASSERT_EQ(::write(master_, keys.data(), keys.size()), static_cast<ssize_t>(keys.size()));
  }

  // Reads output until `done(latest status line)` holds or the time is up.
  template <class F>
  bool wait_status(F done, std::chrono::milliseconds limit) {
    const auto deadline = Clock::now() + limit;
    for (;;) {
      read_some(20ms);
      if (done(status())) return true;
      if (Clock::now() > deadline) return false;
    }
  }
  // The last status line drawn (text after the last "\r\x1b[K").
  std::string status() const {
    const std::string mark = "\r\x1b[K";
    const auto at = output_.rfind(mark);
    if (at == std::string::npos) return "";
    std::string line = output_.substr(at + mark.size());
    return line.substr(0, line.find_first_of("\r\n"));
  }
  std::optional<int> wait_exit(std::chrono::milliseconds limit) {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      read_some(20ms);
      int st = 0;
      if (::waitpid(pid_, &st, WNOHANG) == pid_) {
        status_ = st;
        read_some(50ms);
        return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
      }
    }
    return std::nullopt;
  }
  bool terminal_restored() const {
    termios t{};
    if (::tcgetattr(master_, &t) != 0) return false;
    return (t.c_lflag & ICANON) != 0 && (t.c_lflag & ECHO) != 0;
  }
  const std::string& output() const { return output_; }

 private:
  void read_some(std::chrono::milliseconds wait) {
    pollfd p{master_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(wait.count())) != 1) return;
    char buf[4096];
    const ssize_t n = ::read(master_, buf, sizeof buf);
    if (n > 0) output_.append(buf, static_cast<std::size_t>(n));
  }
  pid_t pid_ = -1;
  int master_ = -1;
  std::optional<int> status_;
  std::string output_;
};

// "playing 2:13.4 / …" → song seconds.
std::optional<double> song_time(const std::string& status) {
  static const std::regex time(R"((playing|paused) +(\d+):(\d+)\.(\d))");
  std::smatch m;
  if (!std::regex_search(status, m, time)) return std::nullopt;
  return std::stod(m[2]) * 60 + std::stod(m[3]) + std::stod(m[4]) / 10;
}

bool playing_after(const std::string& status, double seconds) {
  const auto t = song_time(status);
  return status.rfind("playing", 0) == 0 && t && *t >= seconds;
}

TEST(PlayTerminal, LiveKeysActAndTheStatusLineFollows) {
  PtySession hmp;
  ASSERT_TRUE(hmp.started());
  ASSERT_TRUE(hmp.wait_status([](const std::string& s) { return playing_after(s, 130.3); }, 8s)) << hmp.output();
  EXPECT_NE(hmp.status().find("track 1 \"flute\""), std::string::npos) << hmp.status();

  hmp.type(" ");  // pause
  ASSERT_TRUE(hmp.wait_status([](const std::string& s) { return s.rfind("paused", 0) == 0; }, 2s)) << hmp.status();
  const double paused_at = *song_time(hmp.status());
  std::this_thread::sleep_for(300ms);
  hmp.wait_status([](const std::string&) { return false; }, 200ms);
  EXPECT_NEAR(*song_time(hmp.status()), paused_at, 0.11) << "the song went on while paused";

  hmp.type(" ");  // resume
  ASSERT_TRUE(hmp.wait_status([](const std::string& s) { return s.rfind("playing", 0) == 0; }, 2s)) << hmp.status();

  hmp.type("\x1b[C");  // → seek +5 s
  ASSERT_TRUE(hmp.wait_status([&](const std::string& s) { return playing_after(s, paused_at + 4.8); }, 2s))
      << hmp.status();
  const double after_seek = *song_time(hmp.status());
  EXPECT_LT(after_seek, paused_at + 6.5);

  hmp.type("t");  // next haptic track: 2 "violin"
  ASSERT_TRUE(
      hmp.wait_status([](const std::string& s) { return s.find("track 2 \"violin\"") != std::string::npos; }, 2s))
      << hmp.status();
  EXPECT_NE(hmp.output().find("haptic track 2 \"violin\""), std::string::npos);

  hmp.type("q");
  const std::optional<int> code = hmp.wait_exit(3s);
  ASSERT_TRUE(code.has_value()) << "hmp did not quit";
  EXPECT_EQ(*code, 0);
  EXPECT_NE(hmp.output().find("track 2 \"violin\" on sim"), std::string::npos) << hmp.output();
  EXPECT_TRUE(hmp.terminal_restored());
}

TEST(PlayTerminal, CtrlCStopsCleanlyAndRestoresTheTerminal) {
  PtySession hmp;
  ASSERT_TRUE(hmp.started());
  ASSERT_TRUE(hmp.wait_status([](const std::string& s) { return playing_after(s, 130.2); }, 8s)) << hmp.output();
  hmp.type("\x03");  // the terminal turns it into SIGINT for hmp
  const std::optional<int> code = hmp.wait_exit(3s);
  ASSERT_TRUE(code.has_value()) << "hmp did not stop on Ctrl-C";
  EXPECT_EQ(*code, 130);
  EXPECT_NE(hmp.output().find("played "), std::string::npos) << hmp.output();  // the summary still comes
  EXPECT_TRUE(hmp.terminal_restored());
}

// Escape sequences are keys as a whole: ↑ (ESC [ A) and Ctrl+→ (ESC [ 1 ; 5 C) do nothing, not even the
// letters in them; Esc alone quits, as in the window.
TEST(PlayTerminal, OtherEscapeSequencesDoNothingAndEscAloneQuits) {
  PtySession hmp;
  ASSERT_TRUE(hmp.started());
  ASSERT_TRUE(hmp.wait_status([](const std::string& s) { return playing_after(s, 130.2); }, 8s)) << hmp.output();
  const double before = *song_time(hmp.status());
  hmp.type("\x1b[A");
  hmp.type("\x1b[1;5C");
  hmp.wait_status([](const std::string&) { return false; }, 500ms);
  EXPECT_EQ(hmp.status().rfind("playing", 0), 0u) << hmp.status();
  EXPECT_LT(*song_time(hmp.status()), before + 2.0) << "a sequence that is not → seeked";
  EXPECT_FALSE(hmp.wait_exit(200ms).has_value()) << "a sequence quit";
  hmp.type("\x1b");
  const std::optional<int> code = hmp.wait_exit(3s);
  ASSERT_TRUE(code.has_value()) << "Esc did not quit";
  EXPECT_EQ(*code, 0);
  EXPECT_TRUE(hmp.terminal_restored());
}

}  // namespace

TEST(PlayTerminal, PlaylistKeysMoveBetweenSongs) {
  const std::string largo = std::string(HMP_REPO_DIR) + "/examples/bach-bwv1079-trio-sonata-largo.mid";
  PtySession hmp({test::kDemo, largo, "--from", "20", "--to", "60"});
  ASSERT_TRUE(hmp.started());
  const auto shows = [&](const std::string& label) {
    return hmp.wait_status(
        [&](const std::string& s) { return s.rfind(label, 0) == 0 && s.find("playing") != std::string::npos; }, 8s);
  };
  ASSERT_TRUE(shows("[1/2] bach-bwv1050")) << hmp.output();
  hmp.type("n");
  ASSERT_TRUE(shows("[2/2] bach-bwv1079")) << hmp.status();
  hmp.type("p");
  ASSERT_TRUE(shows("[1/2] bach-bwv1050")) << hmp.status();
  hmp.type("q");
  const std::optional<int> code = hmp.wait_exit(3s);
  ASSERT_TRUE(code.has_value()) << "hmp did not quit";
  EXPECT_EQ(*code, 0);
  EXPECT_NE(hmp.output().find("playlist: 3 song(s) played, 0 file(s) skipped"), std::string::npos) << hmp.output();
  EXPECT_TRUE(hmp.terminal_restored());
}
