#pragma once
// A progress bar on stderr for long work: silent unless stderr is a terminal and the work has already
// taken more than a second (short runs and pipelines stay quiet).
#include <chrono>
#include <cstdint>
#include <string>

namespace hmp {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();
  void update(std::uint64_t done, std::uint64_t total);

 private:
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  bool tty_ = false, shown_ = false;
  int last_percent_ = -1;
};

}  // namespace hmp
