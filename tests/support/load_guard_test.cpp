// LoadWatch (tests/support/load_guard.hpp) sees a machine made busy on purpose: more spinning threads than
// cores for half a second must read as CPU pressure far above the "too loaded" line, and a skip it
// records lands in $HMP_LOADED_SKIPS with the test's name.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "tests/support/load_guard.hpp"

namespace {

using namespace std::chrono_literals;

TEST(LoadGuard, MoreBusyThreadsThanCoresReadAsTooLoaded) {
  if (!hmp::test::cpu_stall_total_us()) GTEST_SKIP() << "this kernel has no /proc/pressure/cpu";
  const hmp::test::LoadWatch watch;
  std::atomic<bool> stop{false};
  std::vector<std::thread> spinners;
  const unsigned n = std::thread::hardware_concurrency() + 2;
  for (unsigned i = 0; i < n; ++i) {
    spinners.emplace_back([&stop] {
      volatile unsigned long x = 0;
      while (!stop.load(std::memory_order_relaxed)) x = x + 1;
    });
  }
  std::this_thread::sleep_for(600ms);
  stop = true;
  for (std::thread& t : spinners) t.join();
  ASSERT_TRUE(watch.pressure().has_value());
  EXPECT_GE(*watch.pressure(), 2 * hmp::test::kTooLoadedPressure) << watch.describe();
  EXPECT_TRUE(watch.too_loaded());
  EXPECT_NE(watch.describe().find("CPU pressure"), std::string::npos);
}

TEST(LoadGuard, ASkipIsRecordedWithTheTestsName) {
  const std::string path = (std::filesystem::temp_directory_path() / "hmp-loaded-skips-test.txt").string();
  std::filesystem::remove(path);
  const char* outer = std::getenv("HMP_LOADED_SKIPS");  // scripts/test's own: put back afterwards
  const std::string saved = outer != nullptr ? outer : "";
  ::setenv("HMP_LOADED_SKIPS", path.c_str(), 1);
  hmp::test::record_loaded_skip("too loaded to measure: example");
  if (outer != nullptr)
    ::setenv("HMP_LOADED_SKIPS", saved.c_str(), 1);
  else
    ::unsetenv("HMP_LOADED_SKIPS");
  std::ifstream in(path);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "LoadGuard.ASkipIsRecordedWithTheTestsName: too loaded to measure: example");
  std::filesystem::remove(path);
}

}  // namespace
