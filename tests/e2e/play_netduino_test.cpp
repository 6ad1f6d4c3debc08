// The stm32f407 board's image under QEMU `netduinoplus2` (design §13; boards/stm32f407/README.md): the
// very .elf a board is flashed with boots on QEMU's STM32F405 model, which has no RCC, GPIO or OTG, so
// its clock set-up runs out of time into the documented fallback; the tick runs on SysTick, and `hmp play
// --device serial:` plays a 10 s passage of the demo's flute over USART2, every note of the passage
// (counted independently from `hmp info --json --notes`) on its scheduled tick. Skipped when the
// stm32f407 tree (next to this build tree, or $HMP_STM32_ELF) or the emulator is missing.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "play_harness.hpp"
#include "host/common/install_layout.hpp"
#include "host/flash/firmware_image.hpp"
#include "tests/support/load_guard.hpp"

namespace {

namespace test = hmp::test;
namespace fs = std::filesystem;

// $HMP_STM32_ELF, else the image `hmp flash` writes from this source tree.
std::string image() {
  if (const char* e = std::getenv("HMP_STM32_ELF"); e != nullptr && *e != '\0') return e;
  const auto tree = hmp::install::source_tree();
  return tree ? hmp::flash::default_image(*tree, true).string() : std::string{};
}

TEST(PlayNetduino, SameImageBootsOnTheFallbackClockAndPlaysEveryNoteOnItsTick) {
  if (!fs::exists(image())) GTEST_SKIP() << "no firmware image at " << image() << " (cmake --preset stm32f407)";
  if (test::run_command("command -v qemu-system-arm").status != 0) GTEST_SKIP() << "qemu-system-arm is not installed";
  const auto expected = test::passage_notes(1, 130, 140);
  ASSERT_GT(expected.size(), 40u);
  const std::string tag = std::to_string(::getpid());
  const fs::path dir = fs::temp_directory_path() / ("hmp-e2e-netduino-" + tag);
  fs::create_directories(dir);
  const std::string sock = (dir / "usart2.sock").string(), log_path = (dir / "play.jsonl").string();
  // USART2 is QEMU's second serial port. hmp connects once the socket is there (up to 5 s).
  const std::string command = "(qemu-system-arm -M netduinoplus2 -kernel '" + image() +
                              "' -display none -monitor none -serial null"
                              " -serial unix:" +
                              sock +
                              ",server=on,wait=off & q=$!; "
                              "for i in $(seq 50); do [ -S " +
                              sock + " ] && break; sleep 0.1; done; " + test::kHmp + " play '" + test::kDemo +
                              "' --track flute --no-audio --no-view --device serial:" + sock +
                              " --from 130 --to 140 --log " + log_path +
                              " </dev/null; rc=$?; kill $q; wait $q 2>/dev/null; exit $rc)";
  const test::LoadWatch load;
  const test::CommandResult r = test::run_command(command);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("board stm32f407"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" 1000 Hz"), std::string::npos) << "the preset's tick rate (the build's default)\n" << r.err;
  // No RCC in the model: the fallback, reported to the host (and no USB, no motor board).
  EXPECT_NE(r.err.find("board condition clock_fallback,no_usb,no_drive"), std::string::npos) << r.err;
  HMP_SKIP_IF_TOO_LOADED(load, test::every_note_on_its_tick(log_path, expected.size()),
                         "notes off their tick or missing in " << log_path);
  test::expect_every_note_on_its_tick(log_path, expected.size(), r.err);
  fs::remove_all(dir);
}

}  // namespace
