#pragma once
// Which notes go to the device next (design §10, §16): the haptic track's notes inside the played window,
// in start order, each placed on the device tick at which its sound is heard, sent ahead by at most the
// lookahead. Pure bookkeeping: the player supplies the song-time → device-tick map (audio clock + clock
// sync) and sends what next() returns when flow control allows.
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "host/haptics/haptic_track.hpp"
#include "host/player/note_batcher.hpp"

namespace hmp::player {

// What the log needs to know about a sent note (design §3 --log).
struct NoteOrigin {
  std::uint32_t track = 0;
  std::uint8_t key = 0;
  double start_s = 0;
  std::uint64_t tick = 0;  // device tick it was sent for
  std::uint32_t duration_ticks = 1;
};

// What places a note in time: its start and the sound it has in the song's audio (whose onset the
// haptic note meets, AudioPlayer::heard_onset_at).
struct NoteSound {
  std::int64_t start_us = 0;
  std::uint8_t channel = 0, program = 0, key = 0;
};

// One note report about to be sent: the message (seq still 0) and the notes it carries, by slot.
struct PendingReport {
  protocol::Message message;
  std::vector<NoteOrigin> notes;
};

class Scheduler {
 public:
  // The window of the song that plays: notes starting in [from_us, to_us).
  Scheduler(std::int64_t from_us, std::int64_t to_us) : from_us_(from_us), to_us_(to_us) {}

  // Replaces the notes (a new track, envelope or mapping) and places the cursor at `song_us`.
  void load(const haptics::HapticTrack& track, std::int64_t song_us);
  // The next note to send is the first starting at or after `song_us` (and not before the window).
  void seek(std::int64_t song_us);

  // The next report, made of notes whose device tick (tick_of(the note's sound)) is ≤ horizon. Notes that ended
  // before `stale_tick` (a long stall: playing them now would only be noise) are skipped and counted.
  std::optional<PendingReport> next(std::uint64_t horizon, std::uint64_t stale_tick,
                                    const std::function<std::uint64_t(const NoteSound&)>& tick_of);

  bool finished() const { return cursor_ >= notes_.size(); }
  std::size_t size() const { return notes_.size(); }  // notes in the window
  std::size_t skipped() const { return skipped_; }
  // End of the last note of the window (µs of song time); from_us when there is none.
  std::int64_t last_end_us() const { return last_end_us_; }
  std::int64_t from_us() const { return from_us_; }
  std::int64_t to_us() const { return to_us_; }

 private:
  struct Entry {
    NoteSound sound;
    std::int64_t end_us;
    synth::Note note;  // start_tick: song tick (replaced by the device tick when sent)
    double start_s;
  };
  std::int64_t from_us_, to_us_;
  std::vector<Entry> notes_;
  std::uint32_t track_ = 0;
  std::size_t cursor_ = 0;
  std::size_t skipped_ = 0;
  std::int64_t last_end_us_ = 0;
};

std::int64_t seconds_to_us(double s);  // exact for times read from a MIDI file (integer µs)

}  // namespace hmp::player
