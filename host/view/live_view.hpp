#pragma once
// The window while a song plays (`hmp play`, `hmp view`): one thread owns the window, draws a frame at
// the display's pace and turns what the user does in it into calls on the player. The player side is
// reached only through the hooks below (the clock, its state, its commands), so this folder does not
// depend on the player, and tests drive it with a clock and state of their own.
//
// Sync (docs/view.md): each frame shows the song time at the moment it is expected on the screen: the
// clock that places the sound (the audio clock when audio plays) read at the frame's start plus the
// time frames have been taking from their start to the end of the buffer swap (a running average).
// Pause and seek are the clock's: a paused clock shows a still picture, a seek jumps.
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "host/midi/song.hpp"
#include "host/view/note_index.hpp"
#include "host/view/present_delay.hpp"
#include "host/view/roll_layout.hpp"
#include "host/view/view_backend.hpp"

namespace hmp::view {

using Clock = std::chrono::steady_clock;

// The player's state in the view's words, read once per frame.
struct LiveState {
  std::uint32_t haptic_track = 0;
  bool paused = false;
  std::int64_t begin_us = 0, end_us = 0;       // the passage played (progress bar, seeks)
  std::string overlay;                         // the top line
  std::optional<std::array<float, 3>> grip_m;  // the device's grip (m, device frame) when it knows it
};

// One frame's timing: the song time it showed, and the clock's song time when its swap returned.
struct FrameTiming {
  std::int64_t shown_us = 0;
  std::int64_t clock_at_present_us = 0;
  Clock::time_point started, presented;
  bool paused = false;
};

struct LiveViewHooks {
  std::function<std::int64_t(Clock::time_point)> song_time;  // required: the clock the sound follows
  std::function<LiveState()> state;                          // required
  std::function<void(char key)> key;                  // the terminal's keys: ' ' '<' '>' 't' 'T' 'e' 'm' 'q' '[' ']'
  std::function<void(std::int64_t song_us)> seek_to;  // the progress bar
  std::function<void(const Bar& bar)> touch;          // the cursor met a note's bar
  std::function<void(std::uint32_t track)> select_track;  // pushed into a track's bar for 0.5 s
  // The device's output up to `song_us`, newest last: fills up to `max` samples, returns how many.
  std::function<int(std::int64_t song_us, float* out, int max)> vibration;
  // Notes that are not the song's (`hmp live`): those overlapping [t0_us, t1_us) of the clock's time,
  // appended to `out`; a note still held ends at the present.
  std::function<void(std::int64_t t0_us, std::int64_t t1_us, std::vector<Bar>& out)> played;
  std::function<void(const FrameTiming&)> on_frame;  // tests and the benchmark
};

struct LiveViewOptions {
  ViewSetup setup;
  double seconds_across = 12.0;
  std::vector<std::string> track_labels;  // the legend, per track ("" for a track without notes: not listed)
  double push_s = 0.5;                    // pushing into a bar this long makes its track the haptic one
  double glide_s = 0.3;                   // the depth animation after a switch of the haptic track
  // What `h` shows: the command's keys and mouse actions (the window's own, zoom, fullscreen and help, are
  // added under them), and whether a click in the legend hides a track (the study's rounds decide).
  std::vector<std::string> help;
  bool legend_hides_tracks = true;
};

class LiveView {
 public:
  // Opens the window on the view's own thread and starts drawing. Null and `error` (one line) when no
  // window can be had; the caller warns and goes on without it.
  static std::unique_ptr<LiveView> open(const midi::Song& song, LiveViewOptions options, LiveViewHooks hooks,
                                        std::string& error);
  ~LiveView();  // closes the window
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  bool closed() const { return closed_.load(); }  // the user closed the window
  std::string renderer() const;
  // Tests: handled as if it came from the window, at the next frame.
  void inject(const ViewEvent& event);
  // Where things are in the window now (tests aim injected clicks with it): the layout of the roll at
  // `song_us` and the chrome around it.
  RollLayout layout_at() const;
  Chrome chrome() const;
  bool hidden(std::uint32_t track) const;
  std::uint64_t frames() const { return frames_.load(); }

  std::vector<std::string> help_lines() const;

 private:
  LiveView(const midi::Song& song, LiveViewOptions options, LiveViewHooks hooks);
  void run(std::string* open_error, std::atomic<int>* opened);
  void handle(const ViewEvent& e, const LiveState& state, Clock::time_point now);
  void handle_all(std::vector<ViewEvent>& events, const LiveState& state);  // plus the injected ones
  void update_touch(FrameState& f, const LiveState& state, Clock::time_point now);
  void fill_frame(FrameState& f, const LiveState& state, Clock::time_point now);
  LayoutParams params() const;  // the view thread's, or under geometry_mutex_
  RollLayout make_layout() const;

  LiveViewOptions options_;
  LiveViewHooks hooks_;
  NoteIndex index_;
  std::pair<int, int> keys_;
  std::unique_ptr<ViewWindow> window_;
  std::thread thread_;
  std::atomic<bool> stop_{false}, closed_{false};
  std::atomic<std::uint64_t> frames_{0};
  mutable std::mutex mutex_;      // injected_, renderer_
  std::condition_variable wake_;  // an injected event, or stop
  std::vector<ViewEvent> injected_;
  std::string renderer_;

  // The view thread's own state; what tests read from other threads (size, zoom, hidden, haptic) changes
  // under geometry_mutex_.
  mutable std::mutex geometry_mutex_;
  int width_px_ = 0, height_px_ = 0;
  float scale_ = 1.0f;
  double seconds_across_ = 12.0;
  bool help_ = false;
  std::vector<bool> hidden_;
  std::vector<std::uint32_t> legend_tracks_;  // the legend's rows, top down
  std::uint32_t shown_haptic_ = 0, previous_haptic_ = 0;
  std::optional<Clock::time_point> glide_start_;
  float mouse_x_ = 0, mouse_y_ = 0;
  bool mouse_seen_ = false, pressing_ = false, dragging_progress_ = false;
  Clock::time_point mouse_moved_{}, grip_moved_{}, last_drag_seek_{};
  std::optional<std::array<float, 3>> last_grip_;
  std::optional<Bar> touched_;
  std::optional<Clock::time_point> push_start_;
  bool push_done_ = false;
  std::vector<Bar> visible_;
  PresentDelay present_delay_;
};

// Where the grip's position (m, device frame: x right, y up, z towards the user) puts the cursor:
// ±kGripSpanM in x and y spans the roll. At z ≤ 0 it touches the roll; pushing in is z below −kPushDepthM.
inline constexpr float kGripSpanM = 0.1f;
inline constexpr float kPushDepthM = 0.01f;

}  // namespace hmp::view
