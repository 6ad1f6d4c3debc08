#pragma once
// Channel voice messages out of a MIDI byte stream (MIDI 1.0 §2): running status (a message's status byte
// left out while it repeats), realtime bytes (0xF8–0xFF: clock, start, active sensing…) anywhere, even
// inside a message, and system exclusive and system common messages, which are skipped. A MIDI input
// port hands over whole messages, but a stream may be cut anywhere: the state carries across feed().
#include <cstddef>
#include <cstdint>

namespace hmp::live {

struct ChannelMessage {
  std::uint8_t status = 0;  // 0x80–0xEF: the kind in the high nibble, the channel in the low one
  std::uint8_t data1 = 0, data2 = 0;
  std::uint8_t kind() const { return static_cast<std::uint8_t>(status & 0xF0u); }
  std::uint8_t channel() const { return static_cast<std::uint8_t>(status & 0x0Fu); }
};

class MidiStream {
 public:
  // Calls emit(const ChannelMessage&) for each complete channel voice message in `bytes`.
  template <class Emit>
  void feed(const std::uint8_t* bytes, std::size_t n, Emit&& emit) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t b = bytes[i];
      if (b >= 0xF8) continue;  // realtime: one byte, does not touch the running status
      if (b >= 0x80) {
        // A status byte: a channel message starts (and sets the running status); system ones clear it,
        // their data bytes (up to the next status byte, or the end of a sysex) are skipped.
        status_ = b < 0xF0 ? b : 0;
        count_ = 0;
        continue;
      }
      if (status_ == 0) continue;  // data of a system message, or before any status
      data_[count_++] = b;
      if (count_ == needed(status_)) {
        emit(ChannelMessage{status_, data_[0], count_ > 1 ? data_[1] : std::uint8_t{0}});
        count_ = 0;  // the next data bytes reuse the running status
      }
    }
  }
  void reset() { status_ = 0, count_ = 0; }

 private:
  // Program change (0xC_) and channel pressure (0xD_) carry one data byte, the others two.
  static int needed(std::uint8_t status) { return (status & 0xE0u) == 0xC0u ? 1 : 2; }
  std::uint8_t status_ = 0;
  std::uint8_t data_[2] = {};
  int count_ = 0;
};

}  // namespace hmp::live
