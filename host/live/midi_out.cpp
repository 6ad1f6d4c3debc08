#include "host/live/midi_out.hpp"

#include <algorithm>
#include <chrono>
#include <climits>

namespace hmp::live {
namespace {

// The song time may step back by this much without it being a seek (the audio clock's corrections).
constexpr std::int64_t kBackStepUs = 50'000;
// A forward jump beyond this is a seek: the events skipped are not sent in a burst.
constexpr std::int64_t kJumpUs = 500'000;
constexpr std::uint8_t kSustain = 64, kAllNotesOff = 123;

std::uint8_t status(std::uint8_t kind, std::uint8_t channel) {
  return static_cast<std::uint8_t>(kind | (channel & 0x0F));
}

}  // namespace

void midi_message(const audio::AudioEvent& e, std::vector<std::uint8_t>& out) {
  const std::uint8_t ch = e.channel & 0x0F;
  using Kind = audio::AudioEvent::Kind;
  using Control = midi::Control::Kind;
  switch (e.kind) {
    case Kind::note_on:
      out.insert(out.end(), {status(0x90, ch), static_cast<std::uint8_t>(e.key & 0x7F),
                             static_cast<std::uint8_t>(std::clamp<int>(e.velocity, 1, 127))});
      return;
    case Kind::note_off: out.insert(out.end(), {status(0x80, ch), static_cast<std::uint8_t>(e.key & 0x7F), 0}); return;
    case Kind::control:
      switch (e.control) {
        case Control::controller:
          out.insert(out.end(), {status(0xB0, ch), static_cast<std::uint8_t>(e.key & 0x7F),
                                 static_cast<std::uint8_t>(e.value & 0x7F)});
          return;
        case Control::pitch_bend:
          out.insert(out.end(), {status(0xE0, ch), static_cast<std::uint8_t>(e.value & 0x7F),
                                 static_cast<std::uint8_t>(e.value >> 7 & 0x7F)});
          return;
        case Control::pressure:
          out.insert(out.end(), {status(0xD0, ch), static_cast<std::uint8_t>(e.value & 0x7F)});
          return;
        case Control::program: return;  // each note-on carries its program (MidiOutSender::send)
      }
  }
}

MidiOutSender::MidiOutSender(MidiOutput& out, std::vector<audio::AudioEvent> events, Clock clock)
    : out_(out), events_(std::move(events)), clock_(std::move(clock)) {
  std::fill(std::begin(programs_), std::end(programs_), -1);
  for (const audio::AudioEvent& e : events_) used_[e.channel & 0x0F] = true;
  thread_ = std::thread([this] { run(); });
}

MidiOutSender::~MidiOutSender() {
  stop_ = true;
  thread_.join();
  silence();
}

std::string MidiOutSender::error() const {
  std::lock_guard lock(error_mutex_);
  return error_;
}

void MidiOutSender::write(const std::vector<std::uint8_t>& bytes) {
  std::string why;
  if (out_.send(bytes.data(), bytes.size(), why)) return;
  std::lock_guard lock(error_mutex_);
  if (error_.empty()) error_ = why;
}

void MidiOutSender::send(const audio::AudioEvent& e) {
  const std::uint8_t ch = e.channel & 0x0F;
  // The program travels with each note: a program change first when the channel's last one differs.
  if (e.kind == audio::AudioEvent::Kind::note_on && programs_[ch] != e.program) {
    write({status(0xC0, ch), static_cast<std::uint8_t>(e.program & 0x7F)});
    programs_[ch] = e.program;
  }
  std::vector<std::uint8_t> bytes;
  midi_message(e, bytes);
  if (!bytes.empty()) write(bytes);
  if (e.kind == audio::AudioEvent::Kind::note_on) sounding_ = true;
  ++sent_;
}

void MidiOutSender::silence() {
  if (!sounding_) return;
  for (std::uint8_t ch = 0; ch < 16; ++ch) {
    if (!used_[ch]) continue;
    write({status(0xB0, ch), kSustain, 0});
    write({status(0xB0, ch), kAllNotesOff, 0});
  }
  sounding_ = false;
}

void MidiOutSender::run() {
  std::size_t next = 0;
  std::int64_t last = INT64_MIN;  // the song time of the last round while playing; MIN: none yet
  while (!stop_) {
    if (!clock_.playing()) {
      silence();
      last = INT64_MIN;  // resume or seek: found again from the clock
    } else {
      const std::int64_t now = clock_.song_us();
      if (last == INT64_MIN || now < last - kBackStepUs || now > last + kJumpUs) {
        if (last != INT64_MIN) silence();
        next = static_cast<std::size_t>(
            std::lower_bound(events_.begin(), events_.end(), now,
                             [](const audio::AudioEvent& e, std::int64_t t) { return e.time_us < t; }) -
            events_.begin());
      }
      while (next < events_.size() && events_[next].time_us <= now) send(events_[next++]);
      last = std::max(last, now);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

}  // namespace hmp::live
