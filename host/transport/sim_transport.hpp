#pragma once
// The in-process simulated device (boards/sim, design §13 `sim`) behind the Transport interface: what
// `--device sim` opens, and what `hmp play` falls back to when nothing is connected. Reports go in and
// come out as over USB HID (a full device inbox is a NAK: send() waits for the next tick).
//
// Two pacings of the device's virtual clock:
//   real_time    a thread runs the tick interrupt in step with the host's steady clock, so the device
//                behaves like a board on a cable (what `hmp play` uses). Reports carry the sub-tick
//                (fraction of the tick elapsed at arrival) from the host clock, as a board's timer would.
//   virtual_time nothing runs by itself: receive(timeout) runs up to timeout's worth of ticks until a
//                report appears, advance() runs ticks on request. Deterministic, for tests.
#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

#include "boards/sim/sim_device.hpp"
#include "host/transport/link_state.hpp"
#include "host/transport/transport.hpp"

namespace hmp::transport {

class SimTransport final : public TransportWithState {
 public:
  enum class Pacing { real_time, virtual_time };
  struct Options {
    std::uint32_t tick_hz = fw::kDefaultTickHz;
    Pacing pacing = Pacing::real_time;
    std::uint64_t first_tick = 0;
    Timeout send_timeout = std::chrono::seconds(2);  // real_time: longest NAK before the link is declared dead
  };

  explicit SimTransport(const Options& options);
  SimTransport() : SimTransport(Options{}) {}
  ~SimTransport() override;

  bool send(const Report& report) override;
  Received receive(Report& out, Timeout timeout) override;
  std::string name() const override { return "sim"; }
  void close() override;

  Pacing pacing() const { return options_.pacing; }
  std::uint32_t tick_hz() const { return options_.tick_hz; }
  // real_time: the host time at which tick `tick` is due (the device's own clock, for measurements;
  // its thread runs the tick then, or a little later when the host is busy).
  std::chrono::steady_clock::time_point tick_due_at(std::uint64_t tick) const;
  // virtual_time: runs `ticks` device ticks now (their reports wait for receive()). real_time: no-op.
  void advance(std::uint64_t ticks);
  // real_time: the device's clock stands still for `span` from now and then runs on from where it stood,
  // those ticks lost (an emulated board's timer on a busy host); the link stays up, reports wait for the
  // next tick. virtual_time: no-op.
  void lose_ticks(std::chrono::nanoseconds span);
  // Runs fn(device) with the device's clock held still: inspection, log echo, output recording.
  template <class F>
  decltype(auto) with_device(F&& fn) {
    std::lock_guard lock(mutex_);
    return fn(device_);
  }

 private:
  using SteadyClock = std::chrono::steady_clock;
  void pace();                                                // the real_time thread
  void collect_reports();                                     // device → inbox_; mutex_ held
  std::uint64_t due_tick(SteadyClock::time_point now) const;  // the tick the device should have reached
  std::uint32_t subtick(SteadyClock::time_point now) const;   // mutex_ held
  bool pop(Report& out);                                      // mutex_ held

  Options options_;
  mutable std::mutex mutex_;         // tick_due_at() reads start_time_, which lose_ticks() moves
  std::condition_variable changed_;  // a tick ran, a report arrived, or the link closed
  sim::SimDevice device_;
  std::deque<std::array<std::uint8_t, protocol::kReportSize>> inbox_;
  SteadyClock::time_point start_time_;
  std::uint64_t start_tick_ = 0;
  bool stop_ = false;
  std::thread pacer_;  // last: started once everything above exists
};

}  // namespace hmp::transport
