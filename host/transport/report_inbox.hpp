#pragma once
// Reports a transport's receive thread has read but not yet delivered (a read may bring several).
#include <array>
#include <cstdint>
#include <cstring>
#include <deque>

#include "host/transport/link_state.hpp"
#include "host/transport/transport.hpp"

namespace hmp::transport {

class ReportInbox {
 public:
  void push(const std::uint8_t* report) { std::memcpy(queue_.emplace_back().data(), report, protocol::kReportSize); }
  // Moves the oldest report into `out` and counts it as received; false when there is none.
  bool take(Report& out, LinkState& state) {
    if (queue_.empty()) return false;
    std::memcpy(out, queue_.front().data(), protocol::kReportSize);
    queue_.pop_front();
    state.count_received();
    return true;
  }

 private:
  std::deque<std::array<std::uint8_t, protocol::kReportSize>> queue_;
};

}  // namespace hmp::transport
