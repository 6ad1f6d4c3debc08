// `hmp play --device qemu` and `qemu:net` (design §3, §10, §13): the hmp binary boots the qemu-an386
// firmware in qemu-system-arm, plays a 10 s passage of the demo's flute over the emulated UART (or its
// Ethernet controller), and every note of the passage (counted independently from `hmp info --json
// --notes`) starts on its scheduled tick.
// Skipped when the firmware image (the qemu-an386 tree next to this build tree, or $HMP_QEMU_ELF) or the
// emulator is missing.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "play_harness.hpp"
#include "tests/support/load_guard.hpp"
#include "tests/support/qemu_board.hpp"

namespace {

namespace test = hmp::test;
namespace fs = std::filesystem;

class PlayQemu : public testing::TestWithParam<const char*> {};

TEST_P(PlayQemu, FlutePassageEveryNoteOnItsTick) {
  if (const std::string missing = test::qemu_board_missing(); !missing.empty()) GTEST_SKIP() << missing;
  const auto expected = test::passage_notes(1, 130, 140);
  ASSERT_GT(expected.size(), 40u);
  const std::string log_path =
      (fs::temp_directory_path() / ("hmp-e2e-qemu-" + std::to_string(::getpid()) + ".jsonl")).string();
  const std::string device = GetParam();
  fs::remove(log_path);
  const test::LoadWatch load;
  const test::CommandResult r =
      test::run_command(test::kHmp + " play '" + test::kDemo + "' --track flute --no-audio --device " + device +
                        " --from 130 --to 140 --log " + log_path + " </dev/null");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("device " + device + ": board qemu-an386"), std::string::npos) << r.err;
  HMP_SKIP_IF_TOO_LOADED(load, test::every_note_on_its_tick(log_path, expected.size()),
                         "notes off their tick or missing in " << log_path);
  test::expect_every_note_on_its_tick(log_path, expected.size(), r.err);
  fs::remove(log_path);
}

INSTANTIATE_TEST_SUITE_P(Links, PlayQemu, testing::Values("qemu", "qemu:net"),
                         [](const testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param) == "qemu" ? std::string("Uart") : std::string("Ethernet");
                         });

}  // namespace
