#pragma once
// The study in the animation window (2015 §6.1: the participants used the whole environment, sound,
// animation and vibration): the round's song scrolling with the round's instrument in front in blue, the
// round and its prompt (which key is playing, the ranks so far) as the window's top line. Keys typed in the
// window are the terminal's keys (0/1/2, a/b/c, u, Enter); closing the window, or q/Esc in it, stops the
// session as Ctrl-C does. The participant is not shown the envelope's name, nor the vibration strip,
// which would show its shape.
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "host/audio/audio_player.hpp"
#include "host/midi/song.hpp"
#include "host/view/live_view.hpp"

namespace hmp::cli {

class StudyWindow {
 public:
  // The window on `song`, its sound's clock `audio`; null and `error` (one line) when none can be had.
  static std::unique_ptr<StudyWindow> open(const midi::Song& song, const audio::AudioPlayer& audio,
                                           const std::string& title, std::string& error);
  StudyWindow(const StudyWindow&) = delete;
  StudyWindow& operator=(const StudyWindow&) = delete;
  ~StudyWindow();

  const midi::Song& song() const { return song_; }
  // What the window shows from now on: `track` in front, `line` at the top. Any thread.
  void show(std::uint32_t track, std::string line);
  // The next key typed in the window, if any; 'q' when it was closed or q/Esc pressed.
  std::optional<char> next_key();

 private:
  explicit StudyWindow(const midi::Song& song) : song_(song) {}

  const midi::Song& song_;
  std::mutex mutex_;  // track_, line_, keys_: written by the study's thread, read by the view's
  std::uint32_t track_ = 0;
  std::string line_;
  std::deque<char> keys_;
  std::unique_ptr<view::LiveView> view_;  // last: its thread stops before the rest goes
};

}  // namespace hmp::cli
