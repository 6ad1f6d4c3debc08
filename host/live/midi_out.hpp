#pragma once
// `hmp play --midi-out PORT`: the song as MIDI to another synthesizer or a DAW, on the clock the device's
// notes follow. A thread of its own sends each audio event (audio_events(): the notes with their programs,
// the sound's controllers, pitch bend, channel pressure) when the song time heard reaches it, the time at
// which hmp's own sound plays it and the device starts its notes (design §10). Pause and seek silence what
// sounds (the sustain pedal up and all notes off on every channel the song uses); after a seek the events
// go on from the new time. The other synthesizer adds its own latency.
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "host/audio/audio_events.hpp"
#include "host/live/midi_port.hpp"

namespace hmp::live {

// The MIDI message of one audio event (note-on, note-off, controller, pitch bend, channel pressure),
// appended to `out`; nothing for a program change, which each note-on carries instead.
void midi_message(const audio::AudioEvent& e, std::vector<std::uint8_t>& out);

class MidiOutSender {
 public:
  struct Clock {
    std::function<std::int64_t()> song_us;  // the song time heard now
    std::function<bool()> playing;          // false while paused or stopped
  };
  // Starts sending at once; `out` outlives this.
  MidiOutSender(MidiOutput& out, std::vector<audio::AudioEvent> events, Clock clock);
  ~MidiOutSender();  // stops, and silences what sounds
  MidiOutSender(const MidiOutSender&) = delete;
  MidiOutSender& operator=(const MidiOutSender&) = delete;

  std::uint64_t sent() const { return sent_.load(); }  // events sent so far
  std::string error() const;                           // the first send that failed, or ""

 private:
  void run();
  void send(const audio::AudioEvent& e);
  void silence();
  void write(const std::vector<std::uint8_t>& bytes);

  MidiOutput& out_;
  std::vector<audio::AudioEvent> events_;
  Clock clock_;
  bool used_[16] = {};
  int programs_[16];
  bool sounding_ = false;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> sent_{0};
  mutable std::mutex error_mutex_;
  std::string error_;
  std::thread thread_;
};

}  // namespace hmp::live
