#pragma once
// `hmp live`'s run: MIDI messages from an input port (any thread) → LiveMapper → Live reports sent to the
// device at once (or after a set delay), a Sync every 100 ms (the device's watchdog), and the device's Started reports
// matched with the messages that caused them, for the latency.
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "host/live/live_mapper.hpp"
#include "host/live/message_ring.hpp"
#include "host/live/midi_port.hpp"
#include "host/player/device_link.hpp"

namespace hmp::live {

struct LiveProgress {
  MapperCounts counts;
  std::uint64_t started = 0;       // notes the device reported started
  std::uint64_t refused = 0;       // Live reports the device refused (each also in `last_error`)
  std::string last_error;          // the device's last Error, as text
  std::size_t held = 0;            // events due, waiting for the device to take the reports before them
  std::size_t most_held = 0;       // the most that ever waited
  std::uint64_t dropped = 0;       // MIDI messages lost because hmp's loop fell 8,192 chunks behind
  std::vector<double> latency_ms;  // per started note: message received → its Started report taken
};

// One note-on as it went through (`hmp live --log`): times in µs of the steady clock (CLOCK_MONOTONIC,
// the clock JACK's jack_get_time reads too), started_us 0 while no Started report has come.
struct NoteRecord {
  std::uint8_t channel = 0, key = 0;
  std::int64_t received_us = 0;  // the MIDI callback had the message
  std::int64_t sent_us = 0;      // its Live report was handed to the link
  std::int64_t started_us = 0;   // the device's Started report for it was taken
  std::uint32_t actual_tick = 0;
};

// A note as played, for the window: its times in µs since the session began, end_us INT64_MAX while it
// sounds (a note the pedal holds sounds on).
struct PlayedNote {
  std::uint8_t channel = 0, key = 0, velocity = 0;
  std::int64_t start_us = 0, end_us = INT64_MAX;
};

// Why run() returned.
enum class LiveEnd { stopped, time_up, port_gone };

class LiveSession {
 public:
  // keep_notes: keep a NoteRecord of every note-on (for --log).
  LiveSession(player::DeviceLink& link, const MapperOptions& options, bool keep_notes = false);
  // The MidiReceive of the input port: queues the message and wakes run(), without a lock or an
  // allocation (it may run in JACK's real-time thread, where either could cost the cycle).
  static void receive(void* self, const std::uint8_t* bytes, std::size_t size);
  // Also hands every channel message to `hear` (on run()'s thread, after its Live report is sent): the sound.
  void set_listener(std::function<void(const ChannelMessage&)> hear) { hear_ = std::move(hear); }
  // Each Live report waits this long (µs) after its message came: the sound's output latency, so that a
  // note is felt when it is heard rather than that much before. 0 (the default): sent at once.
  void set_vibration_delay_us(std::int64_t us) { delay_us_ = us < 0 ? 0 : us; }
  double vibration_delay_ms() const { return static_cast<double>(delay_us_) / 1e3; }
  // Sends Settings and play, then runs until `stop()` says so, `seconds` (> 0) have passed, or `input` is
  // gone; `show` is called about five times a second. Throws player::LinkError when the device is lost.
  LiveEnd run(const MidiInput& input, double seconds, const std::function<bool()>& stop,
              const std::function<void(const LiveProgress&)>& show);
  // Silences the device (Transport stop).
  void finish();
  const LiveProgress& progress() const { return progress_; }
  const std::vector<NoteRecord>& notes() const { return notes_; }
  // µs since the session began (the clock of PlayedNote).
  std::int64_t session_us() const { return player::steady_us() - origin_us_; }
  // Any thread: the notes overlapping [t0_us, t1_us), in the order played; a sounding one ends now.
  void played(std::int64_t t0_us, std::int64_t t1_us, std::vector<PlayedNote>& out) const;

 private:
  struct SentOn {
    std::int64_t received_us;
    std::size_t record;  // its NoteRecord, or SIZE_MAX when none is kept
  };
  void send_events();
  void take_device_events();

  player::DeviceLink& link_;
  LiveMapper mapper_;
  MidiStream stream_;
  MessageRing ring_;
  void record_played(const ChannelMessage& m, std::size_t first_event);
  std::int64_t origin_us_ = player::steady_us();
  mutable std::mutex played_mutex_;
  std::deque<PlayedNote> played_;  // the last kPlayedKept notes, under played_mutex_
  std::function<void(const ChannelMessage&)> hear_;
  std::vector<ChannelMessage> heard_;  // this round's messages, for hear_
  std::vector<DeviceEvent> events_;
  std::vector<std::int64_t> event_us_;  // when the message of each event arrived
  // Note-ons whose Started has not come yet, by seq << 8 | index in the report: a report the device
  // refused takes its entries with it; one lost on the way is replaced when its seq comes round again.
  std::unordered_map<std::uint32_t, SentOn> sent_on_;
  std::deque<std::uint16_t> in_flight_;  // seq of Live reports the device has not processed yet
  LiveProgress progress_;
  bool keep_notes_;
  std::vector<NoteRecord> notes_;
  std::int64_t delay_us_ = 0;
};

}  // namespace hmp::live
