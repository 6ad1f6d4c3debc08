// Reports in Ethernet frames (shared/framing/ether_frame.hpp), checked against the frame layout of IEEE
// 802.3 written out here byte by byte: destination, source, EtherType big-endian, then the payload.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>

#include "shared/framing/ether_frame.hpp"

namespace {

namespace ether = hmp::framing::ether;
using Payload = std::array<std::uint8_t, ether::kPayloadBytes>;

TEST(EtherFrame, LayoutIsDestinationSourceTypeThenTheReportWhole) {
  Payload report{};
  for (std::size_t i = 0; i < report.size(); ++i) report[i] = static_cast<std::uint8_t>(0xA0 + i);
  std::array<std::uint8_t, ether::kFrameBytes> frame{};
  ether::build(report.data(), ether::kHostMac, ether::kDeviceMac, frame.data());
  EXPECT_EQ(frame.size(), 78u);
  const std::uint8_t device[6] = {0x02, 0x48, 0x4D, 0x50, 0x00, 0x01}, host[6] = {0x02, 0x48, 0x4D, 0x50, 0x00, 0x02};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(frame[i], device[i]) << i;
    EXPECT_EQ(frame[6 + i], host[i]) << i;
  }
  EXPECT_EQ(frame[12], 0x88);
  EXPECT_EQ(frame[13], 0xB5);
  for (std::size_t i = 0; i < report.size(); ++i) EXPECT_EQ(frame[14 + i], report[i]) << i;
  EXPECT_EQ(frame[0] & 0x02, 0x02);  // locally administered
  EXPECT_EQ(frame[0] & 0x01, 0x00);  // unicast
}

TEST(EtherFrame, RandomReportsComeBackWholeAndForeignFramesAreRefused) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int round = 0; round < 1000; ++round) {
    Payload report{};
    for (auto& b : report) b = static_cast<std::uint8_t>(byte(rng));
    std::array<std::uint8_t, ether::kFrameBytes + 1> frame{};
    ether::build(report.data(), ether::kDeviceMac, ether::kHostMac, frame.data());
    const std::uint8_t* got = ether::payload_of(frame.data(), ether::kFrameBytes);
    ASSERT_NE(got, nullptr);
    for (std::size_t i = 0; i < report.size(); ++i) ASSERT_EQ(got[i], report[i]);
    EXPECT_EQ(ether::payload_of(frame.data(), ether::kFrameBytes - 1), nullptr);  // cut short
    EXPECT_EQ(ether::payload_of(frame.data(), ether::kFrameBytes + 1), nullptr);  // longer: not ours
    frame[12] = 0x08;                                                             // IPv4
    frame[13] = 0x00;
    EXPECT_EQ(ether::payload_of(frame.data(), ether::kFrameBytes), nullptr);
  }
  EXPECT_EQ(ether::payload_of(nullptr, 0), nullptr);
}

}  // namespace
