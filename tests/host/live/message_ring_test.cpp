// MessageRing: the MIDI callback's lock-free hand-over. Order, the all-or-none split of long messages,
// the count of what a full ring drops, and a writer thread racing the reader over a million messages.
#include "host/live/message_ring.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <thread>
#include <vector>

namespace hmp::live {
namespace {

std::vector<std::uint8_t> drain_bytes(MessageRing& ring, std::vector<std::int64_t>* times = nullptr) {
  std::vector<std::uint8_t> out;
  ring.drain([&](const MidiChunk& c) {
    EXPECT_GE(c.size, 1);
    EXPECT_LE(c.size, 3);
    out.insert(out.end(), c.bytes, c.bytes + c.size);
    if (times != nullptr) times->push_back(c.received_us);
  });
  return out;
}

TEST(MessageRing, KeepsOrderAndTimes) {
  auto ring = std::make_unique<MessageRing>();
  const std::uint8_t on[] = {0x90, 60, 100}, off[] = {0x80, 60, 0}, pc[] = {0xC0, 5};
  EXPECT_TRUE(ring->push(10, on, 3));
  EXPECT_TRUE(ring->push(20, off, 3));
  EXPECT_TRUE(ring->push(30, pc, 2));
  EXPECT_TRUE(ring->push(40, on, 0));  // nothing to hand over
  std::vector<std::int64_t> times;
  EXPECT_EQ(drain_bytes(*ring, &times), (std::vector<std::uint8_t>{0x90, 60, 100, 0x80, 60, 0, 0xC0, 5}));
  EXPECT_EQ(times, (std::vector<std::int64_t>{10, 20, 30}));
  EXPECT_TRUE(drain_bytes(*ring).empty());
  EXPECT_EQ(ring->dropped(), 0u);
}

TEST(MessageRing, ALongMessageGoesWholeInChunksOrNotAtAll) {
  auto ring = std::make_unique<MessageRing>();
  std::vector<std::uint8_t> sysex = {0xF0, 0x7E, 0x7F, 0x06, 0x01, 0xF7, 0x90};
  ASSERT_TRUE(ring->push(1, sysex.data(), sysex.size()));
  EXPECT_EQ(drain_bytes(*ring), sysex);
  // Fill all but two chunks: a three-chunk message does not fit, a one-chunk one does.
  const std::uint8_t on[] = {0x90, 60, 100};
  for (std::size_t i = 0; i + 2 < MessageRing::kCapacity; ++i) ASSERT_TRUE(ring->push(2, on, 3));
  EXPECT_FALSE(ring->push(3, sysex.data(), sysex.size()));
  EXPECT_EQ(ring->dropped(), 1u);
  EXPECT_TRUE(ring->push(4, on, 3));
  EXPECT_TRUE(ring->push(5, on, 3));
  EXPECT_FALSE(ring->push(6, on, 3));
  EXPECT_EQ(ring->dropped(), 2u);
  std::vector<std::int64_t> times;
  EXPECT_EQ(drain_bytes(*ring, &times).size(), 3 * MessageRing::kCapacity);
  EXPECT_EQ(times.back(), 5);
  EXPECT_TRUE(ring->push(7, on, 3)) << "room again once read";
}

// A writer thread pushes a million numbered messages (retrying when full, as a test; the callback
// drops instead) while this thread drains: every message arrives once, in order, intact.
TEST(MessageRing, AWriterThreadAndTheReaderNeverLoseOrReorder) {
  auto ring = std::make_unique<MessageRing>();
  constexpr std::uint32_t kMessages = 1'000'000;
  std::thread writer([&] {
    for (std::uint32_t i = 0; i < kMessages; ++i) {
      const std::uint8_t m[] = {static_cast<std::uint8_t>(0x80 | (i >> 14 & 0x0F)),
                                static_cast<std::uint8_t>(i >> 7 & 0x7F), static_cast<std::uint8_t>(i & 0x7F)};
      while (!ring->push(static_cast<std::int64_t>(i), m, 3)) std::this_thread::yield();
    }
  });
  std::uint32_t next = 0;
  bool intact = true;
  while (next < kMessages) {
    ring->drain([&](const MidiChunk& c) {
      const std::uint32_t i = next++;
      intact = intact && c.size == 3 && c.received_us == static_cast<std::int64_t>(i) &&
               c.bytes[0] == (0x80 | (i >> 14 & 0x0F)) && c.bytes[1] == (i >> 7 & 0x7F) && c.bytes[2] == (i & 0x7F);
    });
  }
  writer.join();
  EXPECT_TRUE(intact);
  EXPECT_EQ(next, kMessages);
}

}  // namespace
}  // namespace hmp::live
