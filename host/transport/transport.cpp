#include "host/transport/transport.hpp"

#include "host/transport/link_state.hpp"

namespace hmp::transport {

const char* name(Received r) {
  switch (r) {
    case Received::report: return "report";
    case Received::timeout: return "timeout";
    case Received::closed: return "closed";
  }
  return "?";
}

bool LinkState::mark_closed(const std::string& reason) {
  std::lock_guard lock(mutex_);
  if (!open_.load(std::memory_order_relaxed)) return false;
  reason_ = reason;
  open_.store(false, std::memory_order_release);
  return true;
}

std::string LinkState::reason() const {
  std::lock_guard lock(mutex_);
  return reason_;
}

LinkCounters LinkState::counters() const {
  LinkCounters c;
  c.sent = sent_.load(std::memory_order_relaxed);
  c.received = received_.load(std::memory_order_relaxed);
  c.dropped = dropped_.load(std::memory_order_relaxed);
  return c;
}

}  // namespace hmp::transport
