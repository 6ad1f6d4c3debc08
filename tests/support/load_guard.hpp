#pragma once
// For tests that measure wall-clock behaviour (label `realtime`, tests/CMakeLists.txt): tells a bound
// that the code missed from one that a busy machine made it miss.
//
// LoadWatch reads the kernel's CPU pressure (Linux PSI, /proc/pressure/cpu, "some": the share of wall
// time in which at least one runnable task waited for a CPU) at its start and when asked. A test measures
// as usual; when its bound does not hold and the CPU pressure over the measurement reached
// kTooLoadedPressure, HMP_SKIP_IF_TOO_LOADED skips the test with "too loaded to measure" and the
// numbers, and records the skip where scripts/test counts it ($HMP_LOADED_SKIPS, one line a test).
// scripts/test fails on such a skip unless the user allowed it (scripts/test --allow-loaded). A bound
// missed on a quiet machine fails as usual, and a kernel without PSI never skips.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

namespace hmp::test {

// At this share of wall time with a task waiting for a CPU the machine is too busy for a timing bound.
// An idle 2-core machine shows 0–5 %; a parallel build beside the tests 40–90 %.
inline constexpr double kTooLoadedPressure = 0.10;

// Cumulative µs of "some" CPU stall since boot; nullopt where the kernel has no PSI.
inline std::optional<unsigned long long> cpu_stall_total_us() {
  std::ifstream in("/proc/pressure/cpu");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("some ", 0) != 0) continue;
    const auto at = line.find("total=");
    if (at == std::string::npos) return std::nullopt;
    return std::strtoull(line.c_str() + at + 6, nullptr, 10);
  }
  return std::nullopt;
}

class LoadWatch {
 public:
  LoadWatch() : start_(std::chrono::steady_clock::now()), stall_start_(cpu_stall_total_us()) {}

  // The share of wall time since construction with a task waiting for a CPU; nullopt without PSI.
  std::optional<double> pressure() const {
    const auto now = cpu_stall_total_us();
    if (!now || !stall_start_) return std::nullopt;
    const double wall_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start_).count();
    if (wall_us <= 0.0) return std::nullopt;
    return static_cast<double>(*now - *stall_start_) / wall_us;
  }
  bool too_loaded() const {
    const auto p = pressure();
    return p && *p >= kTooLoadedPressure;
  }
  // "CPU pressure 47 % over 12.3 s" (or that it could not be measured).
  std::string describe() const {
    const auto p = pressure();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char buf[96];
    if (p) {
      std::snprintf(buf, sizeof buf, "CPU pressure %.0f %% over %.1f s", *p * 100.0, s);
    } else {
      std::snprintf(buf, sizeof buf, "CPU pressure unknown (no /proc/pressure/cpu) over %.1f s", s);
    }
    return buf;
  }

 private:
  std::chrono::steady_clock::time_point start_;
  std::optional<unsigned long long> stall_start_;
};

// Watches for the whole machine stopping for a moment: a thread that sleeps 1 ms at a time keeps the
// longest it overslept. A virtual machine its host pauses (which no load figure inside it shows: this
// kind reports no steal time) stops every thread at once, the watcher too; a program late on its own
// account does not make the watcher oversleep. A timing test that missed its bound during such a stall
// measures again (saying so) instead of failing on it.
class StallWatch {
 public:
  StallWatch() : thread_([this] { watch(); }) {}
  StallWatch(const StallWatch&) = delete;
  StallWatch& operator=(const StallWatch&) = delete;
  ~StallWatch() {
    stop_ = true;
    thread_.join();
  }
  // The longest the watcher overslept so far, ms.
  double worst_ms() const { return static_cast<double>(worst_us_.load()) / 1000.0; }

 private:
  void watch() {
    using namespace std::chrono;
    auto last = steady_clock::now();
    while (!stop_) {
      std::this_thread::sleep_for(milliseconds(1));
      const auto now = steady_clock::now();
      const long over = static_cast<long>(duration_cast<microseconds>(now - last).count()) - 1000;
      if (over > worst_us_.load()) worst_us_ = over;
      last = now;
    }
  }
  std::atomic<bool> stop_{false};
  std::atomic<long> worst_us_{0};
  std::thread thread_;  // last: starts once the members it reads exist
};

// Runs `measure()` (which returns what it measured) and runs it again, up to three runs in all, while
// `missed(result)` says it missed a bound and a StallWatch over that run saw the whole machine stop for
// longer than `stall_ms` (the tightest bound's slack); each repeat is said on stdout with
// `describe(result)`. A miss without such a stall is returned at once, for the test to fail on.
template <class Measure, class Missed, class Describe>
auto measure_unless_stalled(double stall_ms, Measure&& measure, Missed&& missed, Describe&& describe) {
  for (int run = 1;; ++run) {
    const StallWatch stall;
    auto result = measure();
    if (run == 3 || !missed(result) || stall.worst_ms() < stall_ms) return result;
    std::printf("run %d missed (%s) while the machine stalled %.1f ms: measured again\n", run, describe(result).c_str(),
                stall.worst_ms());
  }
}

// Appends "Suite.Name: why" to $HMP_LOADED_SKIPS (scripts/test reads it); a no-op when unset.
inline void record_loaded_skip(const std::string& why) {
  const char* path = std::getenv("HMP_LOADED_SKIPS");
  if (path == nullptr || *path == '\0') return;
  const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
  std::ofstream out(path, std::ios::app);
  out << (t != nullptr ? std::string(t->test_suite_name()) + "." + t->name() : std::string("?")) << ": " << why << "\n";
}

}  // namespace hmp::test

// In a test body, after a measurement and before its assertions: when `bound_held` is false and the
// machine was too loaded over `watch`'s span, skip with "too loaded to measure" (what missed, the load).
#define HMP_SKIP_IF_TOO_LOADED(watch, bound_held, what)                                   \
  do {                                                                                    \
    if (!(bound_held) && (watch).too_loaded()) {                                          \
      std::ostringstream hmp_why_;                                                        \
      hmp_why_ << "too loaded to measure: " << what << " (" << (watch).describe() << ")"; \
      ::hmp::test::record_loaded_skip(hmp_why_.str());                                    \
      GTEST_SKIP() << hmp_why_.str();                                                     \
    }                                                                                     \
  } while (false)
