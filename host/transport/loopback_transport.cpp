#include "host/transport/loopback_transport.hpp"

#include <array>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>

namespace hmp::transport {

struct LoopbackTransport::Shared {
  std::mutex mutex;
  std::condition_variable arrived;
  std::array<std::deque<std::array<std::uint8_t, protocol::kReportSize>>, 2> queue;
  std::array<LinkCounters, 2> counters{};
  bool open = true;
  std::string reason;
};

LoopbackTransport::Pair LoopbackTransport::make_pair(const std::string& name) {
  auto shared = std::make_shared<Shared>();
  return {std::unique_ptr<LoopbackTransport>(new LoopbackTransport(shared, 0, name + ":host")),
          std::unique_ptr<LoopbackTransport>(new LoopbackTransport(shared, 1, name + ":device"))};
}

LoopbackTransport::LoopbackTransport(std::shared_ptr<Shared> shared, int side, std::string name)
    : shared_(std::move(shared)), side_(side), name_(std::move(name)) {}

// An end that goes away closes the link, like a cable pulled out.
LoopbackTransport::~LoopbackTransport() { close(); }

bool LoopbackTransport::send(const Report& report) {
  const auto peer = static_cast<std::size_t>(1 - side_);
  {
    std::lock_guard lock(shared_->mutex);
    if (!shared_->open) return false;
    auto& slot = shared_->queue[peer].emplace_back();
    for (std::size_t i = 0; i < protocol::kReportSize; ++i) slot[i] = report[i];
    ++shared_->counters[static_cast<std::size_t>(side_)].sent;
  }
  shared_->arrived.notify_all();
  return true;
}

Received LoopbackTransport::receive(Report& out, Timeout timeout) {
  const auto self = static_cast<std::size_t>(side_);
  std::unique_lock lock(shared_->mutex);
  auto& queue = shared_->queue[self];
  shared_->arrived.wait_for(lock, timeout, [&] { return !queue.empty() || !shared_->open; });
  if (queue.empty()) return shared_->open ? Received::timeout : Received::closed;
  for (std::size_t i = 0; i < protocol::kReportSize; ++i) out[i] = queue.front()[i];
  queue.pop_front();
  ++shared_->counters[self].received;
  return Received::report;
}

void LoopbackTransport::close() {
  {
    std::lock_guard lock(shared_->mutex);
    if (!shared_->open) return;
    shared_->open = false;
    shared_->reason = "closed by " + name_;
  }
  shared_->arrived.notify_all();
}

bool LoopbackTransport::is_open() const {
  std::lock_guard lock(shared_->mutex);
  return shared_->open;
}

std::string LoopbackTransport::closed_reason() const {
  std::lock_guard lock(shared_->mutex);
  return shared_->reason;
}

LinkCounters LoopbackTransport::counters() const {
  std::lock_guard lock(shared_->mutex);
  return shared_->counters[static_cast<std::size_t>(side_)];
}

}  // namespace hmp::transport
