#pragma once
// Bookkeeping every transport needs: open/closed with the first reason, and the link counters. Safe to
// use from the sending thread, the receiving thread and a closing thread at once.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "host/transport/transport.hpp"

namespace hmp::transport {

class LinkState {
 public:
  bool is_open() const { return open_.load(std::memory_order_acquire); }
  // Marks the link closed. The first reason given is kept; returns true for the call that closed it.
  bool mark_closed(const std::string& reason);
  std::string reason() const;

  void count_sent() { sent_.fetch_add(1, std::memory_order_relaxed); }
  void count_received() { received_.fetch_add(1, std::memory_order_relaxed); }
  void set_dropped(std::uint64_t n) { dropped_.store(n, std::memory_order_relaxed); }
  void count_dropped() { dropped_.fetch_add(1, std::memory_order_relaxed); }
  LinkCounters counters() const;

 private:
  std::atomic<bool> open_{true};
  mutable std::mutex mutex_;
  std::string reason_;
  std::atomic<std::uint64_t> sent_{0}, received_{0}, dropped_{0};
};

// A transport whose open/closed state and counters live in a LinkState: the three queries of Transport
// answered from it (serial, Ethernet frames, the simulated device).
class TransportWithState : public Transport {
 public:
  bool is_open() const final { return state_.is_open(); }
  std::string closed_reason() const final { return state_.reason(); }
  LinkCounters counters() const final { return state_.counters(); }

 protected:
  LinkState state_;
};

}  // namespace hmp::transport
