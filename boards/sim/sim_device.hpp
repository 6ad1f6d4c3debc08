#pragma once
// The simulated board (SPEC §13 `sim`): the firmware core built natively on a deterministic virtual
// clock. Nothing runs by itself: advance(n) runs the tick interrupt n times, reports go in and come out
// through the same 64-byte interface as over USB HID. Used by the firmware tests and, later, as the
// default device of `hmp play` (the plant simulator of SPEC §12 will sit behind output()).
#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "firmware/core.hpp"

namespace hmp::sim {

class SimDevice {
 public:
  // Device reports held for the host before the board reports "no room" (counted by the core).
  static constexpr std::size_t kMaxPendingReports = 1u << 16;
  static constexpr std::size_t kMaxLogLines = 256;

  explicit SimDevice(std::uint32_t tick_hz = fw::kDefaultTickHz, std::uint64_t first_tick = 0);
  SimDevice(const SimDevice&) = delete;
  SimDevice& operator=(const SimDevice&) = delete;

  // ---- host → device ----
  // Hands the report to the core now (it is handled on the next tick). false: the core's inbox was
  // full and the report is lost, as over a UART with no flow control.
  bool send_to_device(const protocol::Report& report);
  // Like a USB transfer the device NAKs while busy: runs ticks until the inbox has room, then sends.
  // Returns the number of ticks it had to run.
  std::uint64_t deliver(const protocol::Report& report);

  // ---- device → host ----
  bool poll_report(protocol::Report& out);  // oldest first; false when none
  std::size_t pending_reports() const { return reports_.size(); }
  void clear_reports() { reports_.clear(); }

  // ---- virtual time ----
  // Runs the tick interrupt `ticks` times; if `record` is given it receives one output sample per tick.
  // Each tick first advances the tick counter: the samples are those of ticks tick()+1 … tick()+ticks
  // (tick() read before the call). A report sent while tick() == k arrived during tick k (a SyncReply
  // says k) and is handled at the start of tick k+1, so a note scheduled for k+1 still starts on time.
  void advance(std::uint64_t ticks, float* record = nullptr);
  std::vector<float> record(std::size_t ticks);
  // What the board's timer reports as the fraction of the present tick elapsed (2^32 = one tick) for
  // the next packets; the virtual clock itself only moves in whole ticks.
  void set_subtick(std::uint32_t fraction) { subtick_ = fraction; }

  // ---- inspection ----
  const fw::Core& core() const { return core_; }
  std::uint64_t tick() const { return core_.tick(); }
  float last_output() const { return last_output_; }
  const std::deque<std::string>& log() const { return log_; }  // the last kMaxLogLines lines
  void set_log_echo(bool on) { echo_log_ = on; }                // also print log lines on stderr

 private:
  static fw::BoardSeam make_seam(SimDevice* self);
  static void on_output(void* ctx, float value);
  static bool on_send(void* ctx, const protocol::Report& report);
  static void on_log(void* ctx, const char* line);
  static std::uint32_t on_subtick(void* ctx);

  struct Report {
    std::uint8_t bytes[protocol::kReportSize];
  };

  std::deque<Report> reports_;
  std::deque<std::string> log_;
  float* record_ = nullptr;  // during advance(): where the next sample goes
  float last_output_ = 0.0f;
  std::uint32_t subtick_ = 0;
  bool echo_log_ = false;
  fw::Core core_;  // last: its seam points at the members above
};

}  // namespace hmp::sim
