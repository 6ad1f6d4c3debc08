// `hmp play` with two songs in the animation window, on a private Xvfb display, typed into with X key
// events (xdotool): the window's title names the song and its place in the list, `n` in the window moves
// to the next song (its window comes up with its own title), and `q` ends the run with the playlist's
// summary.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "play_harness.hpp"
#include "tests/support/xvfb.hpp"
#include "window_keys.hpp"

namespace {

namespace fs = std::filesystem;
namespace test = hmp::test;
using namespace std::chrono_literals;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(PlayWindowPlaylist, TitleNamesEachSongAndNMovesOn) {
  ASSERT_TRUE(test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  ASSERT_EQ(std::system("command -v xdotool >/dev/null 2>&1"), 0) << "xdotool is missing (package xdotool)";
  const std::string largo = std::string(HMP_REPO_DIR) + "/examples/bach-bwv1079-trio-sonata-largo.mid";
  const fs::path out = fs::temp_directory_path() / ("hmp-window-playlist-" + std::to_string(::getpid()));
  std::vector<std::string> args = {test::kHmp,   "play",   test::kDemo, largo,  "--device", "sim",
                                   "--no-audio", "--from", "20",        "--to", "60"};
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null_in = ::open("/dev/null", O_RDONLY);
    const int out_fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(null_in, 0);
    ::dup2(out_fd, 1);
    ::dup2(out_fd, 2);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  const std::string first = test::window_named("\\[1/2\\] bach-bwv1050-brandenburg5");
  EXPECT_FALSE(first.empty()) << "no window named after the first song: " << slurp(out);
  if (!first.empty()) test::type_into(first, "n");
  const std::string second = test::window_named("\\[2/2\\] bach-bwv1079-trio-sonata-largo");
  EXPECT_FALSE(second.empty()) << "n did not bring up the second song's window: " << slurp(out);
  if (!second.empty()) test::type_into(second, "q");
  int status = 0;
  bool exited = false;
  for (int i = 0; i < 100 && !exited; ++i) {
    exited = ::waitpid(pid, &status, WNOHANG) == pid;
    if (!exited) std::this_thread::sleep_for(100ms);
  }
  if (!exited) {
    ::kill(pid, SIGKILL);  // the child this test started
    ::waitpid(pid, &status, 0);
  }
  const std::string text = slurp(out);
  fs::remove(out);
  ASSERT_TRUE(exited) << "q in the window did not end the run: " << text;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  EXPECT_NE(text.find("playlist: 2 song(s) played, 0 file(s) skipped"), std::string::npos) << text;
}

}  // namespace
