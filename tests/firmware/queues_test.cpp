// The core's two queues on their own: the note heap against a brute-force stable sort, and the SPSC inbox
// with a real producer thread against a consumer thread.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <thread>
#include <vector>

#include "firmware/note_queue.hpp"
#include "firmware/spsc_queue.hpp"

namespace {

using hmp::fw::NoteQueue;

struct Expected {
  std::uint64_t start;
  std::uint16_t seq;
};

TEST(FirmwareNoteQueue, PopsInStartOrderAndArrivalOrderOnTies) {
  std::mt19937 rng(11);
  for (int round = 0; round < 200; ++round) {
    NoteQueue q;
    std::vector<Expected> pushed;  // reference: stable sort by start tick
    std::vector<Expected> popped;
    std::uint16_t seq = 0;
    // Interleave pushes and pops, with few distinct start ticks so that ties are common.
    for (int op = 0; op < 2000; ++op) {
      if (rng() % 3 != 0 && q.free_slots() > 0) {
        hmp::synth::Note n;
        n.start_tick = rng() % 20 + (popped.empty() ? 0 : popped.back().start);
        ASSERT_TRUE(q.push(n, ++seq, 0));
        pushed.push_back({n.start_tick, seq});
      } else if (!q.empty()) {
        // Reference: the earliest start among the waiting notes, the first pushed among equals.
        const auto best = std::min_element(pushed.begin(), pushed.end(), [](const Expected& a, const Expected& b) {
          return a.start < b.start;  // min_element keeps the first of equal elements
        });
        ASSERT_EQ(q.top().note.start_tick, best->start);
        ASSERT_EQ(q.top().seq, best->seq);
        popped.push_back(*best);
        pushed.erase(best);
        q.pop();
      }
      ASSERT_EQ(q.size(), pushed.size());
    }
  }
}

TEST(FirmwareNoteQueue, HoldsExactlyItsCapacity) {
  NoteQueue q;
  hmp::synth::Note n;
  for (unsigned i = 0; i < NoteQueue::kCapacity; ++i) ASSERT_TRUE(q.push(n, 1, 0));
  EXPECT_EQ(q.free_slots(), 0u);
  EXPECT_FALSE(q.push(n, 2, 0));
  EXPECT_EQ(q.size(), NoteQueue::kCapacity);
  q.clear();
  EXPECT_TRUE(q.empty());
  q.pop();  // popping an empty queue is harmless
  EXPECT_TRUE(q.empty());
}

TEST(FirmwareSpscQueue, ProducerAndConsumerThreadsSeeEveryItemOnceInOrder) {
  static hmp::fw::SpscQueue<std::uint64_t, 16> q;
  constexpr std::uint64_t kItems = 200'000;
  std::thread producer([] {
    for (std::uint64_t i = 0; i < kItems;) {
      std::uint64_t* slot = q.prepare();
      if (slot == nullptr) {  // full: retry later, as a transport would
        std::this_thread::yield();
        continue;
      }
      *slot = i * 2654435761u;  // a value the consumer can check
      q.commit();
      ++i;
    }
  });
  std::uint64_t next = 0;
  bool in_order = true;
  while (next < kItems) {
    const std::uint64_t* item = q.front();
    if (item == nullptr) {
      std::this_thread::yield();
      continue;
    }
    in_order = in_order && *item == next * 2654435761u;
    q.pop();
    ++next;
  }
  producer.join();
  EXPECT_TRUE(in_order);
  EXPECT_EQ(q.size(), 0u);
  EXPECT_EQ(q.front(), nullptr);
}

TEST(FirmwareSpscQueue, FullAndEmptyAtTheEdges) {
  hmp::fw::SpscQueue<int, 4> q;
  EXPECT_EQ(q.front(), nullptr);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(q.has_room());
    *q.prepare() = i;
    q.commit();
  }
  EXPECT_FALSE(q.has_room());
  EXPECT_EQ(q.prepare(), nullptr);
  for (int i = 0; i < 4; ++i) {
    ASSERT_NE(q.front(), nullptr);
    EXPECT_EQ(*q.front(), i);
    q.pop();
  }
  EXPECT_EQ(q.front(), nullptr);
}

}  // namespace
