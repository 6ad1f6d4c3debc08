#include "host/view/live_view.hpp"

#include <algorithm>
#include <cmath>

namespace hmp::view {
namespace {

constexpr double kMinAcross = 2.0, kMaxAcross = 60.0, kZoomStep = 1.25;
constexpr auto kFramePeriod = std::chrono::microseconds(16'667);  // a cap when the swap does not wait for vsync
constexpr auto kEventPoll = std::chrono::milliseconds(2);         // between frames

bool same_bar(const Bar& a, const Bar& b) { return a.track == b.track && a.start_us == b.start_us && a.key == b.key; }

}  // namespace

std::vector<std::string> LiveView::help_lines() const {
  std::vector<std::string> lines = options_.help;
  lines.emplace_back("+ / \u2212  zoom    f  fullscreen    h  this help");
  return lines;
}

LiveView::LiveView(const midi::Song& song, LiveViewOptions options, LiveViewHooks hooks)
    : options_(std::move(options)), hooks_(std::move(hooks)), index_(song) {
  seconds_across_ = std::clamp(options_.seconds_across, kMinAcross, kMaxAcross);
  hidden_.assign(index_.tracks(), false);
  keys_ = key_range(song, options_.setup.keys);
  for (std::size_t t = 0; t < options_.track_labels.size() && t < index_.tracks(); ++t) {
    if (!options_.track_labels[t].empty()) legend_tracks_.push_back(static_cast<std::uint32_t>(t));
  }
}

std::unique_ptr<LiveView> LiveView::open(const midi::Song& song, LiveViewOptions options, LiveViewHooks hooks,
                                         std::string& error) {
  if (!hooks.song_time || !hooks.state) {
    error = "the view needs a clock and a state";
    return nullptr;
  }
  options.setup.song = &song;
  std::unique_ptr<LiveView> view(new LiveView(song, std::move(options), std::move(hooks)));
  // The window is opened, drawn and closed on the view's thread (one GL context, current there only).
  std::atomic<int> opened{0};  // 0 waiting, 1 open, −1 failed
  std::string open_error;
  view->thread_ = std::thread([v = view.get(), &open_error, &opened] { v->run(&open_error, &opened); });
  while (opened.load() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  if (opened.load() < 0) {
    view->thread_.join();
    error = open_error;
    return nullptr;
  }
  return view;
}

LiveView::~LiveView() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

std::string LiveView::renderer() const {
  std::lock_guard lock(mutex_);
  return renderer_;
}

void LiveView::inject(const ViewEvent& event) {
  {
    std::lock_guard lock(mutex_);
    injected_.push_back(event);
  }
  wake_.notify_one();
}

void LiveView::run(std::string* open_error, std::atomic<int>* opened) {
  {
    std::string error;
    window_ = open_view(options_.setup, error);
    if (!window_) {
      *open_error = error;
      opened->store(-1);
      return;
    }
    std::lock_guard lock(mutex_);
    renderer_ = window_->renderer();
  }
  opened->store(1);  // from here on `open_error` and `opened` are gone with open()'s frame
  std::vector<ViewEvent> events;
  FrameState frame;
  bool open = true;
  while (open && !stop_) {
    const Clock::time_point start = Clock::now();
    const LiveState state = hooks_.state();
    {
      std::lock_guard lock(geometry_mutex_);
      window_->size(width_px_, height_px_, scale_);
      fill_frame(frame, state, start);
    }
    frame.song_us = hooks_.song_time(start + present_delay_.get());
    frame.played.clear();
    if (hooks_.played) {
      const RollLayout layout = make_layout();
      hooks_.played(layout.window_begin_us(frame.song_us), layout.window_end_us(frame.song_us), frame.played);
    }
    update_touch(frame, state, start);
    frame.cursor_pressing = pressing_ && !dragging_progress_;
    events.clear();
    open = window_->frame(frame, events);
    const Clock::time_point presented = Clock::now();
    frames_.fetch_add(1);
    if (hooks_.on_frame) hooks_.on_frame({frame.song_us, hooks_.song_time(presented), start, presented, state.paused});
    present_delay_.add(presented - start);
    handle_all(events, state);
    // Until the next frame (none when the swap waited for the display): events as they come, so that a
    // touch does not wait for a frame. Without vsync this also keeps the frame rate at 60 Hz.
    const Clock::time_point next = start + kFramePeriod;
    while (open && !stop_ && Clock::now() < next) {
      {
        std::unique_lock lock(mutex_);
        wake_.wait_until(lock, std::min(next, Clock::now() + kEventPoll), [&] { return !injected_.empty() || stop_; });
      }
      events.clear();
      open = window_->poll(events);
      handle_all(events, state);
    }
  }
  if (!open) {
    closed_ = true;
    if (hooks_.key) hooks_.key('q');
  }
  window_.reset();
}

void LiveView::handle_all(std::vector<ViewEvent>& events, const LiveState& state) {
  {
    std::lock_guard lock(mutex_);
    events.insert(events.end(), injected_.begin(), injected_.end());
    injected_.clear();
  }
  if (events.empty()) return;
  const Clock::time_point now = Clock::now();
  bool moved = false;
  for (const ViewEvent& e : events) {
    handle(e, state, now);
    moved = moved || e.kind == ViewEvent::Kind::cursor || e.kind == ViewEvent::Kind::press;
  }
  if (moved) {  // touch now, at the song time of now
    FrameState f;
    f.song_us = hooks_.song_time(now);
    update_touch(f, state, now);
  }
}

void LiveView::fill_frame(FrameState& f, const LiveState& state, Clock::time_point now) {
  if (state.haptic_track != shown_haptic_) {  // a switch: the layers glide to their new depth
    previous_haptic_ = shown_haptic_;
    shown_haptic_ = state.haptic_track;
    glide_start_ = now;
  }
  f.haptic_track = shown_haptic_;
  f.previous_haptic = previous_haptic_;
  f.depth_blend = 1.0f;
  if (glide_start_) {
    const double s = std::chrono::duration<double>(now - *glide_start_).count() / options_.glide_s;
    if (s >= 1.0) {
      glide_start_.reset();
    } else {
      f.depth_blend = static_cast<float>(s * s * (3 - 2 * s));  // smoothstep
    }
  }
  f.paused = state.paused;
  f.end_us = state.end_us;
  f.seconds_across = seconds_across_;
  f.overlay = state.overlay;
  f.legend.clear();
  for (const std::uint32_t t : legend_tracks_) {
    f.legend.push_back({t, options_.track_labels[t], t == shown_haptic_, t < hidden_.size() && hidden_[t]});
  }
  f.help = help_ ? help_lines() : std::vector<std::string>{};
  f.vibration_samples = hooks_.vibration ? hooks_.vibration(hooks_.song_time(now), f.vibration, 256) : 0;
}

LayoutParams LiveView::params() const {
  LayoutParams p = for_drawable(LayoutParams{}, width_px_, height_px_, scale_, seconds_across_);
  p.key_low = keys_.first;
  p.key_high = keys_.second;
  return p;
}

RollLayout LiveView::make_layout() const {
  const auto tracks = static_cast<std::uint32_t>(index_.tracks());
  return RollLayout(params(), tracks, tracks == 0 ? 0 : std::min(shown_haptic_, tracks - 1));
}

RollLayout LiveView::layout_at() const {
  std::lock_guard lock(geometry_mutex_);
  return make_layout();
}

Chrome LiveView::chrome() const {
  std::lock_guard lock(geometry_mutex_);
  return chrome_layout(params(), scale_);
}

bool LiveView::hidden(std::uint32_t track) const {
  std::lock_guard lock(geometry_mutex_);
  return track < hidden_.size() && hidden_[track];
}

void LiveView::handle(const ViewEvent& e, const LiveState& state, Clock::time_point now) {
  std::unique_lock geometry(geometry_mutex_);  // zoom and hidden tracks change here
  const Chrome chrome = chrome_layout(params(), scale_);
  switch (e.kind) {
    case ViewEvent::Kind::quit: break;  // the window reports itself closed on the same frame
    case ViewEvent::Kind::key:
      switch (e.key) {
        case '+': seconds_across_ = std::max(kMinAcross, seconds_across_ / kZoomStep); break;
        case '-': seconds_across_ = std::min(kMaxAcross, seconds_across_ * kZoomStep); break;
        case 'h': help_ = !help_; break;
        case 'f': break;  // the window itself
        default:
          if (hooks_.key) hooks_.key(e.key);
      }
      break;
    case ViewEvent::Kind::press: {
      mouse_x_ = e.x;
      mouse_y_ = e.y;
      mouse_seen_ = true;
      mouse_moved_ = now;
      if (chrome.progress.contains(e.x, e.y)) {
        dragging_progress_ = true;
        last_drag_seek_ = now;
        if (hooks_.seek_to) hooks_.seek_to(progress_time(chrome, e.x, state.begin_us, state.end_us));
        break;
      }
      for (std::size_t row = 0; row < legend_tracks_.size(); ++row) {
        if (chrome.legend_row_rect(row).contains(e.x, e.y)) {
          const std::uint32_t t = legend_tracks_[row];
          if (t < hidden_.size() && options_.legend_hides_tracks) hidden_[t] = !hidden_[t];
          return;
        }
      }
      pressing_ = true;
      push_start_ = now;
      push_done_ = false;
      break;
    }
    case ViewEvent::Kind::release:
      if (dragging_progress_ && hooks_.seek_to)
        hooks_.seek_to(progress_time(chrome, e.x, state.begin_us, state.end_us));
      pressing_ = dragging_progress_ = false;
      push_start_.reset();
      break;
    case ViewEvent::Kind::cursor:
      mouse_x_ = e.x;
      mouse_y_ = e.y;
      mouse_seen_ = true;
      mouse_moved_ = now;
      // Dragging along the progress bar seeks as it goes, ten times a second at most (each seek flushes
      // the device and restarts the sound).
      if (dragging_progress_ && hooks_.seek_to && now - last_drag_seek_ >= std::chrono::milliseconds(100)) {
        last_drag_seek_ = now;
        hooks_.seek_to(progress_time(chrome, e.x, state.begin_us, state.end_us));
      }
      break;
  }
}

void LiveView::update_touch(FrameState& f, const LiveState& state, Clock::time_point now) {
  const std::int64_t song_us = f.song_us;
  // The cursor: the grip's position when it moves, else the mouse's. It touches the roll while the mouse
  // button is held, or while the grip is in the roll's plane (z ≤ 0): a pointer merely resting on the
  // window plays nothing.
  float x = mouse_x_, y = mouse_y_;
  bool have = mouse_seen_;
  bool touching = pressing_;
  bool pushing = pressing_;
  if (state.grip_m) {
    const auto& g = *state.grip_m;
    if (!last_grip_ || std::hypot((*last_grip_)[0] - g[0], (*last_grip_)[1] - g[1], (*last_grip_)[2] - g[2]) > 0.002f) {
      last_grip_ = g;
      grip_moved_ = now;
    }
    if (!mouse_seen_ || grip_moved_ > mouse_moved_) {
      x = roll_width(params()) * (0.5f + 0.5f * g[0] / kGripSpanM);  // the grip's span across the roll
      y = static_cast<float>(height_px_) * (0.5f - 0.5f * g[1] / kGripSpanM);
      have = true;
      const bool in = g[2] < -kPushDepthM;
      if (in && !push_start_) push_start_ = now, push_done_ = false;
      if (!in && !pressing_) push_start_.reset();
      pushing = in || pressing_;
      touching = g[2] <= 0.0f || pressing_;
    }
  }
  f.cursor = have && static_cast<bool>(hooks_.touch);  // no cursor where nothing can be touched
  f.cursor_x = x;
  f.cursor_y = y;
  if (!have || !touching || dragging_progress_) {
    touched_.reset();
    return;
  }
  const auto tracks = static_cast<std::uint32_t>(index_.tracks());
  if (tracks == 0) return;
  const RollLayout layout = make_layout();
  std::vector<Bar> candidates;
  for (std::uint32_t t = 0; t < tracks; ++t) {
    if (t < hidden_.size() && hidden_[t]) continue;
    index_.visible(t, layout.window_begin_us(song_us), layout.window_end_us(song_us), visible_);
    candidates.insert(candidates.end(), visible_.begin(), visible_.end());
  }
  const std::optional<Bar> under = layout.pick(candidates, song_us, x, y);
  if (under && (!touched_ || !same_bar(*under, *touched_)) && hooks_.touch) hooks_.touch(*under);
  touched_ = under;
  // Pushing into a bar long enough: its track becomes the haptic one (once per push).
  if (pushing && under && push_start_ && !push_done_ &&
      std::chrono::duration<double>(now - *push_start_).count() >= options_.push_s) {
    push_done_ = true;
    if (under->track != shown_haptic_ && hooks_.select_track) hooks_.select_track(under->track);
  }
}

}  // namespace hmp::view
