#include "host/transport/sim_transport.hpp"

#include <algorithm>
#include <cstring>

namespace hmp::transport {

namespace {
// Ticks the pacer runs per lock hold when catching up: keeps send() and receive() responsive.
constexpr std::uint64_t kMaxTicksPerBurst = 32;
}  // namespace

SimTransport::SimTransport(const Options& options) : options_(options), device_(options.tick_hz, options.first_tick) {
  options_.tick_hz = device_.core().tick_hz();  // 0 means the default; keep what the device runs at
  start_time_ = SteadyClock::now();
  start_tick_ = device_.tick();
  if (options_.pacing == Pacing::real_time) pacer_ = std::thread([this] { pace(); });
}

SimTransport::~SimTransport() {
  close();
  if (pacer_.joinable()) pacer_.join();
}

void SimTransport::close() {
  state_.mark_closed("closed by the host");
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
}

std::uint64_t SimTransport::due_tick(SteadyClock::time_point now) const {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now - start_time_).count();
  if (ns <= 0) return start_tick_;
  const auto elapsed = static_cast<std::uint64_t>(ns);
  const std::uint64_t hz = options_.tick_hz;
  // Split in whole seconds and the rest so that ns × hz cannot overflow.
  return start_tick_ + (elapsed / 1'000'000'000u) * hz + (elapsed % 1'000'000'000u) * hz / 1'000'000'000u;
}

SimTransport::SteadyClock::time_point SimTransport::tick_due_at(std::uint64_t tick) const {
  std::lock_guard lock(mutex_);
  const auto ticks = static_cast<std::int64_t>(tick) - static_cast<std::int64_t>(start_tick_);
  const std::int64_t hz = options_.tick_hz;
  return start_time_ + std::chrono::nanoseconds(ticks / hz * 1'000'000'000 + ticks % hz * 1'000'000'000 / hz);
}

std::uint32_t SimTransport::subtick(SteadyClock::time_point now) const {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now - start_time_).count();
  const double position = static_cast<double>(ns) * 1e-9 * options_.tick_hz + static_cast<double>(start_tick_);
  const double fraction = position - static_cast<double>(device_.tick());
  if (fraction <= 0.0) return 0;
  if (fraction >= 1.0) return 0xFFFFFFFFu;  // the pacer is behind: the tick is (over)due
  return static_cast<std::uint32_t>(fraction * 4294967296.0);
}

void SimTransport::collect_reports() {
  Report r;
  while (device_.poll_report(r)) {
    auto& slot = inbox_.emplace_back();
    std::memcpy(slot.data(), r, protocol::kReportSize);
  }
}

bool SimTransport::pop(Report& out) {
  if (inbox_.empty()) return false;
  std::memcpy(out, inbox_.front().data(), protocol::kReportSize);
  inbox_.pop_front();
  state_.count_received();
  return true;
}

void SimTransport::pace() {
  std::unique_lock lock(mutex_);
  while (!stop_) {
    const std::uint64_t due = due_tick(SteadyClock::now());
    if (device_.tick() < due) {
      device_.advance(std::min(due - device_.tick(), kMaxTicksPerBurst));
      collect_reports();
      lock.unlock();
      changed_.notify_all();
      lock.lock();
      continue;
    }
    // Sleep until the next tick is due (or until closed).
    const std::uint64_t ticks = device_.tick() + 1 - start_tick_, hz = options_.tick_hz;
    const std::uint64_t next_ns = ticks / hz * 1'000'000'000u + ticks % hz * 1'000'000'000u / hz;
    changed_.wait_until(lock, start_time_ + std::chrono::nanoseconds(static_cast<std::int64_t>(next_ns)),
                        [this] { return stop_; });
  }
}

void SimTransport::advance(std::uint64_t ticks) {
  if (options_.pacing != Pacing::virtual_time) return;
  std::lock_guard lock(mutex_);
  device_.advance(ticks);
  collect_reports();
}

void SimTransport::lose_ticks(std::chrono::nanoseconds span) {
  if (options_.pacing != Pacing::real_time) return;
  {
    std::lock_guard lock(mutex_);
    start_time_ += span;  // every tick from now on is due `span` later
  }
  changed_.notify_all();
}

bool SimTransport::send(const Report& report) {
  if (!state_.is_open()) return false;
  std::unique_lock lock(mutex_);
  if (options_.pacing == Pacing::virtual_time) {
    device_.deliver(report);  // runs ticks while the inbox is full, as a NAKed transfer would wait
    collect_reports();
    state_.count_sent();
    return true;
  }
  const auto deadline = SteadyClock::now() + options_.send_timeout;
  for (;;) {
    if (stop_) return false;
    device_.set_subtick(subtick(SteadyClock::now()));
    if (device_.send_to_device(report)) break;
    // Inbox full: like a NAKed USB transfer, try again after the device's next tick.
    const std::uint64_t tick = device_.tick();
    if (!changed_.wait_until(lock, deadline, [&] { return stop_ || device_.tick() != tick; })) {
      lock.unlock();
      state_.mark_closed(
          "simulated device took no report for " +
          std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(options_.send_timeout).count()) + " ms");
      return false;
    }
  }
  state_.count_sent();
  return true;
}

Received SimTransport::receive(Report& out, Timeout timeout) {
  std::unique_lock lock(mutex_);
  if (options_.pacing == Pacing::virtual_time) {
    collect_reports();
    if (pop(out)) return Received::report;
    if (stop_) return Received::closed;
    // Virtual time: the timeout is measured in device ticks, run here and now.
    const auto us = static_cast<std::uint64_t>(std::max<std::int64_t>(timeout.count(), 0));
    const std::uint64_t ticks = (us * options_.tick_hz + 999'999) / 1'000'000;
    for (std::uint64_t i = 0; i < ticks; ++i) {
      device_.advance(1);
      collect_reports();
      if (pop(out)) return Received::report;
    }
    return Received::timeout;
  }
  changed_.wait_for(lock, timeout, [this] { return !inbox_.empty() || stop_; });
  if (pop(out)) return Received::report;
  return stop_ ? Received::closed : Received::timeout;
}

}  // namespace hmp::transport
