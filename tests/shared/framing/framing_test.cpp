// Serial framing (shared/framing): COBS + CRC-16/CCITT-FALSE, streaming decoder.
// The checks use a whole-frame COBS decoder written here from the COBS definition, the CRC's published
// check value, and properties (no 0x00 inside a frame, bounded length, every corruption dropped).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "shared/framing/framing.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;
using hmp::framing::Decoder;
using hmp::framing::kMaxPacket;

// COBS by definition: code byte k (1…255) is followed by k−1 non-zero bytes; a code below 255 stands
// for a 0x00 after its bytes unless it is the last block. `frame` excludes the delimiter.
std::optional<Bytes> reference_cobs_decode(const Bytes& frame) {
  Bytes out;
  std::size_t i = 0;
  while (i < frame.size()) {
    const unsigned code = frame[i++];
    if (code == 0) return std::nullopt;
    for (unsigned k = 1; k < code; ++k) {
      if (i >= frame.size() || frame[i] == 0) return std::nullopt;
      out.push_back(frame[i++]);
    }
    if (code < 0xFF && i < frame.size()) out.push_back(0);
  }
  return out;
}

Bytes frame_of(const Bytes& packet) {
  Bytes out(hmp::framing::max_frame_size(packet.size()));
  const std::size_t n = hmp::framing::encode(packet.data(), packet.size(), out.data(), out.size());
  out.resize(n);
  return out;
}

// Packets with different byte statistics: uniform, zero-heavy, all zero, never zero.
Bytes random_packet(std::mt19937& rng, std::size_t size) {
  Bytes p(size);
  const unsigned kind = rng() % 4;
  for (auto& b : p) {
    const auto r = static_cast<std::uint8_t>(rng());
    switch (kind) {
      case 0: b = r; break;
      case 1: b = (rng() % 2 == 0) ? 0 : r; break;
      case 2: b = 0; break;
      default: b = static_cast<std::uint8_t>(r == 0 ? 1 : r); break;
    }
  }
  return p;
}

// Feeds bytes and collects every delivered packet.
std::vector<Bytes> feed(Decoder& d, const Bytes& stream) {
  std::vector<Bytes> got;
  for (const std::uint8_t b : stream) {
    if (d.push(b)) got.emplace_back(d.packet(), d.packet() + d.size());
  }
  return got;
}

void append(Bytes& to, const Bytes& what) { to.insert(to.end(), what.begin(), what.end()); }

TEST(Framing, CrcMatchesPublishedCheckValue) {
  const char* digits = "123456789";
  const auto* p = reinterpret_cast<const std::uint8_t*>(digits);
  EXPECT_EQ(hmp::framing::crc16_ccitt_false(p, 9), 0x29B1);  // CRC-16/CCITT-FALSE check value
  EXPECT_EQ(hmp::framing::crc16_ccitt_false(p, 0), 0xFFFF);  // nothing processed: the init value
}

TEST(Framing, FramesAreStuffedCorrectlyAndBounded) {
  std::mt19937 rng(1);
  for (int i = 0; i < 5000; ++i) {
    const Bytes packet = random_packet(rng, rng() % (kMaxPacket + 1));
    const Bytes frame = frame_of(packet);
    ASSERT_FALSE(frame.empty());
    ASSERT_LE(frame.size(), hmp::framing::max_frame_size(packet.size()));
    ASSERT_EQ(frame.back(), 0);
    const Bytes body(frame.begin(), frame.end() - 1);
    for (const std::uint8_t b : body) ASSERT_NE(b, 0) << "0x00 inside a frame";
    const auto decoded = reference_cobs_decode(body);
    ASSERT_TRUE(decoded.has_value());
    const std::uint16_t crc = hmp::framing::crc16_ccitt_false(packet.data(), packet.size());
    Bytes expected = packet;
    expected.push_back(static_cast<std::uint8_t>(crc));
    expected.push_back(static_cast<std::uint8_t>(crc >> 8));
    ASSERT_EQ(*decoded, expected);
  }
}

TEST(Framing, AllZeroReportHasMinimalOverhead) {
  const Bytes zeros(kMaxPacket, 0);
  // 66 stuffed bytes need one code byte each zero plus one: 67 bytes, plus the delimiter.
  EXPECT_EQ(frame_of(zeros).size(), kMaxPacket + 2 + 1 + 1);
  EXPECT_EQ(hmp::framing::kMaxFrame, kMaxPacket + 2 + 1 + 1);
}

TEST(Framing, EncodeRefusesOversizedPacketsAndShortBuffers) {
  std::uint8_t big[kMaxPacket + 1] = {};
  std::uint8_t out[hmp::framing::kMaxFrame + 8] = {};
  EXPECT_EQ(hmp::framing::encode(big, sizeof big, out, sizeof out), 0u);
  EXPECT_EQ(hmp::framing::encode(big, kMaxPacket, out, hmp::framing::kMaxFrame - 1), 0u);
  EXPECT_GT(hmp::framing::encode(big, kMaxPacket, out, hmp::framing::kMaxFrame), 0u);
}

TEST(Framing, RoundTripOfRandomPacketsInOneStream) {
  std::mt19937 rng(2);
  std::vector<Bytes> sent;
  Bytes stream;
  for (int i = 0; i < 20000; ++i) {
    sent.push_back(random_packet(rng, rng() % (kMaxPacket + 1)));
    append(stream, frame_of(sent.back()));
  }
  Decoder any_size(0);
  EXPECT_EQ(feed(any_size, stream), sent);
  EXPECT_EQ(any_size.counters().packets, sent.size());
  EXPECT_EQ(any_size.counters().dropped(), 0u);
}

// A report decoder delivers every packet at the expected size: a frame may carry fewer bytes (the sender
// left its trailing zeros out) and gets zeros put back; an empty packet or a longer one is dropped.
TEST(Framing, ReportDecoderZeroFillsShortPacketsAndDropsEmptyOrLongOnes) {
  Decoder reports;  // expects kMaxPacket
  const Bytes good(kMaxPacket, 0x5A);
  Bytes short_one(kMaxPacket, 0);
  std::fill_n(short_one.begin(), 10, 1);
  Bytes stream = frame_of(Bytes(10, 1));
  append(stream, frame_of(good));
  append(stream, frame_of(Bytes{}));
  append(stream, frame_of(Bytes{0x07}));
  const auto got = feed(reports, stream);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0], short_one);
  EXPECT_EQ(got[1], good);
  Bytes seven(kMaxPacket, 0);
  seven[0] = 0x07;
  EXPECT_EQ(got[2], seven);
  EXPECT_EQ(reports.counters().wrong_size, 1u) << "the empty packet";
  Decoder ten(10);
  EXPECT_TRUE(feed(ten, frame_of(Bytes(11, 3))).empty());
  EXPECT_EQ(ten.counters().wrong_size, 1u) << "longer than expected";
  // An expected size beyond what a packet can hold is kMaxPacket: a short packet is filled to 64, not past.
  Decoder hundred(100);
  const auto filled = feed(hundred, frame_of(Bytes(10, 1)));
  ASSERT_EQ(filled.size(), 1u);
  EXPECT_EQ(filled[0], short_one);
}

TEST(Framing, CarriedSizeLeavesOutTrailingZerosOnly) {
  const Bytes a = {1, 0, 2, 0, 0};
  EXPECT_EQ(hmp::framing::carried_size(a.data(), a.size()), 3u);
  const Bytes zeros(kMaxPacket, 0);
  EXPECT_EQ(hmp::framing::carried_size(zeros.data(), zeros.size()), 1u) << "at least one byte";
  const Bytes full(kMaxPacket, 9);
  EXPECT_EQ(hmp::framing::carried_size(full.data(), full.size()), kMaxPacket);
}

// Random reports of every zero statistic, framed with only their carried bytes, come out whole: the
// truth is the report itself.
TEST(Framing, CarriedReportsRoundTripWhole) {
  std::mt19937 rng(5);
  std::vector<Bytes> sent;
  Bytes stream;
  std::size_t framed = 0;
  for (int i = 0; i < 20000; ++i) {
    Bytes r = random_packet(rng, kMaxPacket);
    std::fill(r.begin() + static_cast<std::ptrdiff_t>(rng() % (kMaxPacket + 1)), r.end(), 0);  // padding
    sent.push_back(r);
    const Bytes f = frame_of(
        Bytes(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(hmp::framing::carried_size(r.data(), r.size()))));
    framed += f.size();
    append(stream, f);
  }
  Decoder reports;
  EXPECT_EQ(feed(reports, stream), sent);
  EXPECT_EQ(reports.counters().dropped(), 0u);
  EXPECT_LT(framed, sent.size() * hmp::framing::kMaxFrame);
}

TEST(Framing, EverySingleBitCorruptionIsDetected) {
  std::mt19937 rng(3);
  int flips = 0;
  for (int i = 0; i < 300; ++i) {
    const Bytes packet = random_packet(rng, kMaxPacket);
    const Bytes next = random_packet(rng, kMaxPacket);
    const Bytes frame = frame_of(packet);
    const Bytes next_frame = frame_of(next);
    for (std::size_t bit = 0; bit < frame.size() * 8; ++bit) {
      Bytes corrupted = frame;
      corrupted[bit / 8] = static_cast<std::uint8_t>(corrupted[bit / 8] ^ (1u << (bit % 8)));
      Bytes stream = corrupted;
      stream.push_back(0x00);
      append(stream, next_frame);
      Decoder d;
      const auto got = feed(d, stream);
      ASSERT_EQ(got.size(), 1u) << "packet " << i << " bit " << bit;
      ASSERT_EQ(got[0], next) << "packet " << i << " bit " << bit;
      ASSERT_GE(d.counters().dropped(), 1u) << "packet " << i << " bit " << bit;
      ++flips;
    }
  }
  EXPECT_GT(flips, 300 * 60 * 8);
}

TEST(Framing, CutFramesAreDroppedAndCounted) {
  std::mt19937 rng(4);
  for (int i = 0; i < 200; ++i) {
    const Bytes packet = random_packet(rng, kMaxPacket);
    const Bytes next = random_packet(rng, kMaxPacket);
    const Bytes frame = frame_of(packet);
    for (std::size_t keep = 1; keep + 1 < frame.size(); ++keep) {
      // Cut, then the line goes idle (a delimiter), then a whole frame.
      Bytes stream(frame.begin(), frame.begin() + static_cast<std::ptrdiff_t>(keep));
      stream.push_back(0x00);
      append(stream, frame_of(next));
      Decoder d;
      const auto got = feed(d, stream);
      ASSERT_EQ(got, std::vector<Bytes>{next}) << "kept " << keep;
      ASSERT_EQ(d.counters().dropped(), 1u);
    }
    // Cut with the next frame glued on: both are lost together, the one after that arrives.
    Bytes stream(frame.begin(), frame.begin() + static_cast<std::ptrdiff_t>(frame.size() / 2));
    append(stream, frame_of(next));
    append(stream, frame_of(packet));
    Decoder d;
    EXPECT_EQ(feed(d, stream), std::vector<Bytes>{packet});
    EXPECT_EQ(d.counters().dropped(), 1u);
  }
}

TEST(Framing, GarbageBetweenFramesIsSkipped) {
  std::mt19937 rng(5);
  std::vector<Bytes> sent;
  Bytes stream;
  for (int i = 0; i < 3000; ++i) {
    const std::size_t garbage = rng() % 100;
    for (std::size_t k = 0; k < garbage; ++k) stream.push_back(static_cast<std::uint8_t>(rng()));
    stream.push_back(0x00);  // a sender starts each frame with a delimiter to end any garbage
    sent.push_back(random_packet(rng, kMaxPacket));
    append(stream, frame_of(sent.back()));
  }
  Decoder d;
  EXPECT_EQ(feed(d, stream), sent);
}

TEST(Framing, OversizedFrameIsDroppedWithoutOverrun) {
  Bytes stream(5000, 0x7F);
  stream.push_back(0x00);
  const Bytes good(kMaxPacket, 0);
  append(stream, frame_of(good));
  Decoder d;
  EXPECT_EQ(feed(d, stream), std::vector<Bytes>{good});
  EXPECT_EQ(d.counters().oversized, 1u);
  EXPECT_EQ(d.counters().dropped(), 1u);
}

TEST(Framing, IdleDelimitersAreNotErrors) {
  Bytes stream(50, 0x00);
  const Bytes good(kMaxPacket, 3);
  append(stream, frame_of(good));
  stream.insert(stream.end(), 50, 0x00);
  Decoder d;
  EXPECT_EQ(feed(d, stream), std::vector<Bytes>{good});
  EXPECT_EQ(d.counters().dropped(), 0u);
}

TEST(Framing, ResetForgetsAPartialFrame) {
  const Bytes good(kMaxPacket, 9);
  const Bytes frame = frame_of(good);
  Decoder d;
  for (std::size_t i = 0; i < frame.size() / 2; ++i) d.push(frame[i]);
  d.reset();
  EXPECT_EQ(feed(d, frame), std::vector<Bytes>{good});
  EXPECT_EQ(d.counters().dropped(), 0u);
}

}  // namespace
