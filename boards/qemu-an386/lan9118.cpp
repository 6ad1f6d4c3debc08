#include "lan9118.hpp"

#include "registers.hpp"

namespace hmp::board {
namespace {

constexpr std::uintptr_t kRxData = 0x00, kTxData = 0x20, kRxStatus = 0x40, kIrqCfg = 0x54, kIntSts = 0x58,
                         kIntEn = 0x5C, kByteTest = 0x64, kTxCfg = 0x70, kHwCfg = 0x74, kRxFifoInf = 0x7C,
                         kTxFifoInf = 0x80, kMacCsrCmd = 0xA4, kMacCsrData = 0xA8;
constexpr std::uint32_t kByteTestValue = 0x87654321;
constexpr std::uint32_t kIrqEnable = 1u << 8, kIrqActiveHigh = 1u << 4, kIrqPushPull = 1u << 0;
constexpr std::uint32_t kIntRxStatusLevel = 1u << 3;
constexpr std::uint32_t kTxOn = 1u << 1;
constexpr std::uint32_t kSoftReset = 1u << 0;
constexpr std::uint32_t kMacBusy = 1u << 31;
constexpr std::uint32_t kMacCr = 1, kMacRxEnable = 1u << 2, kMacTxEnable = 1u << 3, kMacFullDuplex = 1u << 20,
                        kMacPromiscuous = 1u << 18;
// TX command A: first and last segment of a frame in one buffer; B: the frame's length (and a tag).
constexpr std::uint32_t kTxFirstSegment = 1u << 13, kTxLastSegment = 1u << 12;
constexpr std::uint32_t kFcsBytes = 4;
constexpr int kBusyPolls = 1000;  // the reset and a MAC access take microseconds

}  // namespace

bool Lan9118::init() const {
  if (reg(base_ + kByteTest) != kByteTestValue) return false;
  reg(base_ + kHwCfg) = kSoftReset;
  for (int i = 0; i < kBusyPolls && (reg(base_ + kHwCfg) & kSoftReset) != 0; ++i) {
  }
  reg(base_ + kMacCsrData) = kMacRxEnable | kMacTxEnable | kMacFullDuplex | kMacPromiscuous;
  reg(base_ + kMacCsrCmd) = kMacBusy | kMacCr;
  for (int i = 0; i < kBusyPolls && (reg(base_ + kMacCsrCmd) & kMacBusy) != 0; ++i) {
  }
  reg(base_ + kTxCfg) = kTxOn;
  reg(base_ + kIntSts) = 0xFFFFFFFFu;
  reg(base_ + kIntEn) = kIntRxStatusLevel;
  reg(base_ + kIrqCfg) = kIrqEnable | kIrqActiveHigh | kIrqPushPull;
  return true;
}

std::uint32_t Lan9118::frames_waiting() const { return (reg(base_ + kRxFifoInf) >> 16) & 0xFFu; }

std::size_t Lan9118::read_frame(std::uint8_t* out, std::size_t capacity) const {
  const std::size_t length = (reg(base_ + kRxStatus) >> 16) & 0x3FFFu;  // with the FCS
  for (std::size_t i = 0; i < length; i += 4) {
    const std::uint32_t word = reg(base_ + kRxData);
    for (std::size_t b = 0; b < 4 && i + b < capacity; ++b) out[i + b] = static_cast<std::uint8_t>(word >> (8 * b));
  }
  return length > kFcsBytes ? length - kFcsBytes : 0;
}

void Lan9118::clear_rx_interrupt() const { reg(base_ + kIntSts) = kIntRxStatusLevel; }

bool Lan9118::tx_room(std::size_t size) const { return (reg(base_ + kTxFifoInf) & 0xFFFFu) >= size + 8; }

void Lan9118::send(const std::uint8_t* frame, std::size_t size) const {
  const auto length = static_cast<std::uint32_t>(size);
  reg(base_ + kTxData) = kTxFirstSegment | kTxLastSegment | length;
  reg(base_ + kTxData) = length;
  for (std::size_t i = 0; i < size; i += 4) {
    std::uint32_t word = 0;
    for (std::size_t b = 0; b < 4 && i + b < size; ++b) word |= static_cast<std::uint32_t>(frame[i + b]) << (8 * b);
    reg(base_ + kTxData) = word;
  }
}

}  // namespace hmp::board
