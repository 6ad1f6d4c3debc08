#pragma once
// `hmp play` without the terminal (design §3, §10, §14, §16): plays one track of a song on a device in
// step with the song's audio. The audio player's clock says when each song time is heard; the clock
// sync says which device tick that is; the scheduler streams the haptic track's notes ahead by the
// lookahead within the device's flow-control credit. Pause, seek, stop and live switching of track,
// envelope and mapping flush the device and resend from the new position. docs/player.md has the
// whole picture.
//
// Threads: run() and everything it calls happen on the caller's thread (the receiver thread lives in
// DeviceLink); post() and snapshot() may be called from any thread.
#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "host/audio/audio_player.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/midi/song.hpp"
#include "host/player/device_link.hpp"
#include "host/player/scheduler.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::player {

// Playback speeds the [ and ] keys step through (0.5 … 2); `direction` +1 is one step faster, −1 slower,
// clamped at the ends. A speed not on the list (a --speed between steps) steps from 1.
double next_speed(double current, int direction);
inline constexpr double kMinSpeed = 0.5, kMaxSpeed = 2.0;

// A note the device started, as its Started report says (64-bit ticks).
struct StartedNote {
  NoteOrigin origin;
  std::uint64_t scheduled_tick = 0;
  std::uint64_t actual_tick = 0;
};

// The closing line of --log (design §3): device counters since the session began.
struct Counters {
  std::uint64_t notes_sent = 0;    // notes handed to the device (a resend after queue_full counts once)
  std::uint64_t notes_played = 0;  // Status.started
  std::uint64_t late = 0, stolen = 0, rejected = 0;
  std::uint64_t skipped = 0;  // notes not sent because they ended long before they could be (stalls)
  // Notes sent that never started because the song stopped, moved or was left before their tick: the
  // device was told to drop them. sent − played − cancelled is what the device failed to start.
  std::uint64_t cancelled = 0;
  std::uint64_t recoveries = 0;  // device restarts or watchdog faults the player recovered from
};

enum class Command {
  toggle_pause,
  seek_back,     // −5 s
  seek_forward,  // +5 s
  next_track,
  previous_track,
  cycle_envelope,  // auto → square → triangle → auto
  cycle_mapping,   // paper → rank → constant → legacy2013 → paper
  slower,          // playback speed one step down (2, 1.5, 1.25, 1, 0.75, 0.5)
  faster,          // one step up
  next_song,       // a playlist's next song (the player ends with Outcome::next_song)
  previous_song,   // the one before (or this one again from its start, as the first)
  quit,
  interrupt,  // Ctrl-C: like quit, reported as interrupted
};

enum class Outcome { finished, quit, interrupted, next_song, previous_song };

// What the status line shows.
struct Snapshot {
  std::int64_t song_us = 0, end_us = 0;
  bool paused = false;
  std::uint32_t track = 0;
  std::string track_name, envelope, mapping;
  Counters counters;
  int queue_free = 0, queue_capacity = 0;
  protocol::State device_state = protocol::State::idle;
  std::uint8_t active_voices = 0;
  std::optional<std::array<float, 3>> grip_m;  // the grip's position (m, device frame) when the device knows it
  std::int64_t begin_us = 0;                   // the passage's start (--from)
  double speed = 1.0;
  std::shared_ptr<const haptics::HapticTrack> haptic;  // the haptic track's notes as now sent (the view's strip)
  std::string song_label;                              // PlayerOptions::song_label
  bool device_lost = false;                            // waiting for the device to come back
  std::string message;                                 // the player's last message (the window shows it a while)
  std::chrono::steady_clock::time_point message_at{};  // when it was said
};

struct PlayerOptions {
  std::uint32_t track = 0;
  haptics::HapticOptions haptic;  // tick_hz is replaced by the device's
  std::int64_t from_us = 0;
  std::optional<std::int64_t> to_us;  // default: the song's end
  protocol::Settings settings;        // policy and end fade are taken from `haptic`
  double lookahead_s = 0.2;           // notes are sent this long before they are heard (design §10)
  double start_preroll_s = 0.6;       // play starts this long before the first note: the device's ramp-in
  double seek_preroll_s = 0.05;       // after a seek or resume: time to get the first notes across
  double seek_step_s = 5.0;
  double stale_s = 1.0;                        // notes that ended this long ago are not sent any more
  std::chrono::milliseconds sync_period{100};  // also feeds the device's host watchdog (250 ms)
  std::chrono::microseconds loop_period{5000};
  double touch_lead_s = 0.004;    // a touched note starts this long after the device's present tick
  std::function<void()> on_idle;  // every loop turn, on the player's thread (keys, status line)
  std::function<void(const StartedNote&)> on_started;
  std::function<void(const std::string&)> on_message;  // one-line notices (track switched, recovery)
  std::string song_label;                              // shown with the song's time: "[2/5] name.mid" in a playlist
  // A device that is lost (unplugged, rebooted, silent): the player pauses and calls this every
  // `find_period` until it returns the same device opened again (null: not back yet), greets it and
  // plays on from where the song stopped. Not set: the loss ends run() with DeviceLost.
  std::function<transport::Transport*()> find_device;
  std::chrono::milliseconds find_period{250};
};

class Player {
 public:
  // The link must be connected (DeviceLink::connect()); the audio player is owned by the caller.
  Player(DeviceLink& link, audio::AudioPlayer& audio, const midi::Song& song, PlayerOptions options);

  // Plays to the end of the window, a quit, an interrupt or a change of song; stops the device (nothing
  // keeps vibrating) and returns. Throws LinkError when the device is lost (unless find_device brings
  // it back) or refuses the protocol.
  Outcome run();

  void post(Command c);  // any thread
  // Touch (the view, paper §5.3): play the note of `track` with this key that starts at `start_s` on the
  // device at once (a few ms ahead of the device's present tick), as that track's haptic note would
  // sound. While the song plays; a note that does not exist, or whose envelope is a user preset of
  // another track (not uploaded), is a one-line message. Any thread.
  void touch(std::uint32_t track, std::uint8_t key, double start_s);
  // Makes `track` the haptic track (the view's legend, or pushing into a track's bar), as `t` does for the
  // next one. A track without notes or out of range is a one-line message. Any thread.
  void select_track(std::uint32_t track);
  // Moves to `song_us` (clamped to the passage), playing or paused as before (the view's progress bar).
  // Any thread.
  void seek_to(std::int64_t song_us);
  // Playback speed 0.5–2 (clamped): the sound and the device follow from the present position. Any thread.
  void set_speed(double speed);
  Snapshot snapshot() const;  // any thread
  Counters counters() const { return snapshot().counters; }
  const haptics::HapticTrack& haptic_track() const { return track_; }
  std::int64_t window_end_us() const;
  std::size_t window_notes() const { return scheduler_.size(); }  // notes of the present track in the window

 private:
  struct SentReport {
    std::uint64_t epoch = 0;
    PendingReport report;
    std::uint8_t started = 0;
    std::uint32_t started_mask = 0;  // bit i: notes[i] started (a report holds kNotesPerBatch notes at most)
  };

  void set_up_device();
  bool turn(Outcome& outcome);                                     // one loop turn; true: leave run()
  bool wait_for_device(const std::string& why, Outcome& outcome);  // false: the user left meanwhile
  void send_presets();
  void sync_burst();
  void start_at(std::int64_t song_us, double preroll_s);
  void flush_device(protocol::TransportOp op, std::int64_t song_us);
  void rebuild_track(std::int64_t song_us);
  void set_track(haptics::HapticTrack&& track);  // track_, and its copy published in the snapshot
  void seek(std::int64_t target);
  void apply_speed(double speed);
  void schedule();
  void handle_events();
  void handle_touches();
  const haptics::HapticTrack* haptic_track_of(std::uint32_t track);
  bool handle_commands(Outcome& outcome);  // true: leave run()
  void check_device_state();
  void recover(const std::string& why);
  bool ended();
  void finish();
  void update_counters();
  void update_snapshot();
  void message(const std::string& text) const;
  std::int64_t song_now() const;
  std::uint64_t tick_of_sound(const NoteSound& sound) const;  // where the haptic note meets its sound
  std::uint64_t extend(std::uint32_t low) const;
  // At the song's stop (the device's Status after it, at stop_tick): the unstarted notes that were
  // dropped rather than missed go to counters_.cancelled.
  void count_cancelled(std::uint64_t stop_tick);
  std::optional<std::uint16_t> send(const protocol::Message& m);
  void send_transport(protocol::TransportOp op, std::uint64_t tick = 0);

  DeviceLink& link_;
  audio::AudioPlayer& audio_;
  const midi::Song& song_;
  PlayerOptions options_;
  std::uint32_t tick_hz_ = synth::kNominalTickHz;
  mapping::Ranges base_ranges_{};
  std::vector<std::uint32_t> playable_tracks_;

  haptics::HapticTrack track_;
  Scheduler scheduler_;
  std::uint64_t epoch_ = 0;  // bumped by every flush: reports of an older epoch are not resent
  std::map<std::uint16_t, SentReport> sent_;
  std::set<unsigned> refusals_seen_;  // (error code, report type) already reported
  std::deque<PendingReport> resend_;
  std::uint64_t last_note_end_tick_ = 0;
  bool paused_ = false;
  std::int64_t paused_at_us_ = 0;
  std::int64_t next_sync_us_ = 0;
  std::optional<std::uint16_t> play_seq_;  // the last Transport play sent
  std::int64_t last_fault_recovery_us_ = 0;
  bool play_when_ready_ = true;  // start playing once the device is set up (again)
  bool device_lost_ = false;

  std::optional<protocol::Status> baseline_;  // device counters when the session (or a restart) began
  Counters carried_{};                        // counters of device sessions before a restart
  Counters counters_{};

  mutable std::mutex mutex_;  // commands_, snapshot_
  std::deque<Command> commands_;
  struct Touch {
    std::uint32_t track;
    std::uint8_t key;
    double start_s;
  };
  std::deque<Touch> touches_;
  std::optional<std::uint32_t> wanted_track_;
  std::optional<std::int64_t> wanted_seek_us_;
  std::optional<double> wanted_speed_;
  std::shared_ptr<const haptics::HapticTrack> published_track_;
  std::map<std::uint32_t, haptics::HapticTrack> other_tracks_;  // touched tracks other than the haptic one
  Snapshot snapshot_;
  mutable std::mutex message_mutex_;  // the last message, said from const members too
  mutable std::string message_;
  mutable std::chrono::steady_clock::time_point message_at_{};
};

}  // namespace hmp::player
