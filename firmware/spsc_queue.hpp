#pragma once
// Lock-free single-producer/single-consumer ring (design §8: transport → tick). One context only pushes
// (the transport interrupt or loop), one only pops (the tick). Indices are free-running 32-bit counters:
// each side writes only its own, so a plain release store publishes a slot and an acquire load sees it.
// On a Cortex-M4 these are ordinary loads/stores plus barriers: no locks, no interrupt masking.
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace hmp::fw {

template <typename T, std::uint32_t Capacity>
class SpscQueue {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "capacity must be a power of two");
  static_assert(std::atomic<std::uint32_t>::is_always_lock_free, "needs lock-free 32-bit atomics");

 public:
  static constexpr std::uint32_t kCapacity = Capacity;

  // Producer side. Returns a slot to fill, or nullptr when full; publish it with commit().
  T* prepare() {
    const std::uint32_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= Capacity) return nullptr;
    return &slots_[head & (Capacity - 1)];
  }
  void commit() { head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }
  bool has_room() const {
    return head_.load(std::memory_order_relaxed) - tail_.load(std::memory_order_acquire) < Capacity;
  }

  // Consumer side. The oldest slot, or nullptr when empty; release it with pop() after use.
  const T* front() const {
    const std::uint32_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) return nullptr;
    return &slots_[tail & (Capacity - 1)];
  }
  void pop() { tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

  std::uint32_t size() const { return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire); }

 private:
  T slots_[Capacity]{};
  std::atomic<std::uint32_t> head_{0};  // written by the producer only
  std::atomic<std::uint32_t> tail_{0};  // written by the consumer only
};

}  // namespace hmp::fw
