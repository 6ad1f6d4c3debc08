// The window from the command line: `hmp play` opens it where there is a display and plays on without
// it (one warning) where there is none or where OpenGL 3.3 cannot be had; `hmp view SONG` plays the
// animation with the song's audio to the end of the passage, and says in one line when it cannot open.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>

#include "tests/e2e/play_harness.hpp"
#include "tests/support/xvfb.hpp"

namespace {

namespace test = hmp::test;

std::size_t lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

const std::string kPassage = " --device sim --audio-driver virtual --from 30 --to 31";

TEST(ViewCli, PlayWithoutADisplayWarnsOnceAndPlaysOn) {
  const test::CommandResult r =
      test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + test::kHmp + " play '" + test::kDemo + "'" + kPassage);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("warning: no animation window: no display"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("warning:", r.err.find("warning:") + 1), std::string::npos)
      << "more than one warning: " << r.err;
  EXPECT_NE(r.out.find("played "), std::string::npos) << r.out;
}

TEST(ViewCli, PlayWithoutOpenGL33WarnsOnceAndPlaysOn) {
  ASSERT_TRUE(hmp::test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  // Mesa made to offer OpenGL 3.0 only: no 3.3 core context (an old driver, a VM, WSL).
  const test::CommandResult r =
      test::run_command("MESA_GL_VERSION_OVERRIDE=3.0 " + test::kHmp + " play '" + test::kDemo + "'" + kPassage);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("warning: no animation window: no OpenGL 3.3"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("played "), std::string::npos) << r.out;
}

TEST(ViewCli, PlayWithADisplayOpensTheWindowWithoutWarnings) {
  ASSERT_TRUE(hmp::test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  const test::CommandResult r = test::run_command(test::kHmp + " play '" + test::kDemo + "'" + kPassage);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("played "), std::string::npos) << r.out;
}

TEST(ViewCli, ViewPlaysThePassageAndEnds) {
  ASSERT_TRUE(hmp::test::xvfb().running()) << "Xvfb did not start (package xvfb)";
  const auto t0 = std::chrono::steady_clock::now();
  const test::CommandResult r =
      test::run_command(test::kHmp + " view '" + test::kDemo + "' --audio-driver virtual --from 30 --to 31.5");
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("view: "), std::string::npos) << r.err;
  EXPECT_GE(s, 1.4) << "ended before the passage did";
  EXPECT_LT(s, 10.0);
}

TEST(ViewCli, ViewWithoutADisplayFailsInOneLine) {
  const test::CommandResult r =
      test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + test::kHmp + " view '" + test::kDemo + "' --no-audio");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_EQ(r.err.rfind("error: no animation window: no display", 0), 0u) << r.err;
}

TEST(ViewCli, ViewRefusesAnEmptyPassage) {
  const test::CommandResult r =
      test::run_command(test::kHmp + " view '" + test::kDemo + "' --no-audio --from 40 --to 30");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
}

}  // namespace
