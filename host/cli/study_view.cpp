#include "host/cli/study_view.hpp"

#include <utility>

#include "host/cli/play_view.hpp"

namespace hmp::cli {

std::unique_ptr<StudyWindow> StudyWindow::open(const midi::Song& song, const audio::AudioPlayer& audio,
                                               const std::string& title, std::string& error) {
  std::unique_ptr<StudyWindow> w(new StudyWindow(song));
  view::LiveViewOptions options;
  options.setup.title = title;
  options.track_labels = legend_labels(song);
  options.help = {"0 1 2  the envelope felt    a b c  rank it A, B or C    u  undo    Enter  next round",
                  "q / Esc  stop (run the same command again to resume)"};
  options.legend_hides_tracks = false;  // the round's own track stays in sight
  view::LiveViewHooks hooks;
  hooks.song_time = [&audio](view::Clock::time_point t) { return audio.song_time_us(t); };
  StudyWindow* self = w.get();
  hooks.state = [self] {
    std::lock_guard lock(self->mutex_);
    view::LiveState s;
    s.haptic_track = self->track_;
    s.end_us = self->song_.duration_us;
    s.overlay = self->line_;
    return s;
  };
  hooks.key = [self](char k) {
    std::lock_guard lock(self->mutex_);
    self->keys_.push_back(k);
  };
  // No seeking, touching, choosing a track or vibration strip: the round decides what is felt.
  w->view_ = view::LiveView::open(song, std::move(options), std::move(hooks), error);
  if (!w->view_) return nullptr;
  return w;
}

StudyWindow::~StudyWindow() { view_.reset(); }

void StudyWindow::show(std::uint32_t track, std::string line) {
  std::lock_guard lock(mutex_);
  track_ = track;
  line_ = std::move(line);
}

std::optional<char> StudyWindow::next_key() {
  std::lock_guard lock(mutex_);
  if (keys_.empty()) return std::nullopt;
  const char k = keys_.front();
  keys_.pop_front();
  return k;
}

}  // namespace hmp::cli
