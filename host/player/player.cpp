#include "host/player/player.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "host/common/error.hpp"
#include "host/common/time_format.hpp"
#include "host/midi/gm.hpp"
#include "host/player/note_batcher.hpp"
#include "host/transport/handshake.hpp"

namespace hmp::player {

namespace {

using Clock = std::chrono::steady_clock;

std::int64_t to_us(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
}

std::int64_t seconds(double s) { return std::llround(s * 1e6); }

std::uint32_t since(std::uint32_t now, std::uint32_t base) { return now - base; }  // wrapping counters

const char* const kEnvelopeCycle[] = {"auto", "square", "triangle"};
constexpr double kSpeeds[] = {kMinSpeed, 0.75, 1.0, 1.25, 1.5, kMaxSpeed};
const mapping::Mode kMappingCycle[] = {mapping::Mode::paper, mapping::Mode::rank, mapping::Mode::constant,
                                       mapping::Mode::legacy2013};

}  // namespace

double next_speed(double current, int direction) {
  const double* here = std::find(std::begin(kSpeeds), std::end(kSpeeds), current);
  const std::ptrdiff_t i = here == std::end(kSpeeds) ? 2 : here - std::begin(kSpeeds);
  const std::ptrdiff_t last = static_cast<std::ptrdiff_t>(std::size(kSpeeds)) - 1;
  return kSpeeds[std::clamp<std::ptrdiff_t>(i + (direction > 0 ? 1 : -1), 0, last)];
}

Player::Player(DeviceLink& link, audio::AudioPlayer& audio, const midi::Song& song, PlayerOptions options)
    : link_(link),
      audio_(audio),
      song_(song),
      options_(std::move(options)),
      scheduler_(options_.from_us, options_.to_us ? *options_.to_us : std::numeric_limits<std::int64_t>::max()) {
  tick_hz_ = link_.hello().tick_hz;
  options_.haptic.tick_hz = tick_hz_;
  base_ranges_ = options_.haptic.ranges;
  for (const midi::Track& t : song_.tracks) {
    if (t.note_count > 0) playable_tracks_.push_back(t.index);
  }
  static constexpr protocol::PolicyCode kPolicy[] = {protocol::PolicyCode::sum, protocol::PolicyCode::highest,
                                                     protocol::PolicyCode::latest};
  options_.settings.policy = kPolicy[static_cast<int>(options_.haptic.polyphony)];
  options_.settings.end_fade_ms = static_cast<float>(options_.haptic.end_fade_ms);
  protocol::Message m = protocol::make(protocol::Type::settings, 0);
  m.settings = options_.settings;
  if (protocol::validate(m) != protocol::ErrorCode::none)
    throw BadInput("device settings out of range (check the config's [device])");
  set_track(haptics::build_haptic_track(song_, options_.track, options_.haptic));
  update_snapshot();
}

void Player::message(const std::string& text) const {
  {
    std::lock_guard lock(message_mutex_);
    message_ = text;
    message_at_ = std::chrono::steady_clock::now();
  }
  if (options_.on_message) options_.on_message(text);
}

std::optional<std::uint16_t> Player::send(const protocol::Message& m) { return link_.send(m); }

void Player::send_transport(protocol::TransportOp op, std::uint64_t tick) {
  protocol::Message m = protocol::make(protocol::Type::transport, 0);
  m.transport.op = op;
  m.transport.tick = op == protocol::TransportOp::seek ? tick : 0;
  const std::optional<std::uint16_t> seq = send(m);
  if (op == protocol::TransportOp::play && seq) play_seq_ = *seq;
}

std::int64_t Player::song_now() const { return paused_ ? paused_at_us_ : audio_.song_time_us(); }

std::uint64_t Player::tick_of_sound(const NoteSound& s) const {
  return link_.tick_at(to_us(audio_.heard_onset_at(s.channel, s.program, s.key, s.start_us))).value_or(0);
}

std::uint64_t Player::extend(std::uint32_t low) const {
  // The 64-bit tick nearest the device's present one with these low 32 bits (docs/protocol.md).
  const std::uint64_t now = link_.tick_at(steady_us()).value_or(0);
  const auto delta = static_cast<std::int32_t>(low - static_cast<std::uint32_t>(now));
  const std::int64_t t = static_cast<std::int64_t>(now) + delta;
  return t < 0 ? low : static_cast<std::uint64_t>(t);
}

std::int64_t Player::window_end_us() const {
  const std::int64_t end = options_.to_us ? std::min(*options_.to_us, song_.duration_us) : song_.duration_us;
  return std::max(end, scheduler_.last_end_us());
}

void Player::send_presets() {
  for (const haptics::UserPreset& u : track_.uploads) {
    protocol::Message m = protocol::make(protocol::Type::preset, 0);
    m.preset.slot = u.slot;
    m.preset.adsr = u.adsr;
    send(m);
  }
}

void Player::sync_burst() {
  // A dozen quick exchanges before playing: enough for the offset (the drift comes with the periodic
  // syncs while playing, over seconds).
  constexpr std::size_t kWanted = 8, kMaxSent = 24;
  const auto deadline = Clock::now() + std::chrono::seconds(1);
  std::size_t sent = 0;
  auto next = Clock::now();
  while (link_.sync_samples() < kWanted) {
    link_.check();
    if (Clock::now() > deadline) {
      if (link_.sync_samples() > 0) break;
      throw LinkError(fmt::format("device {}: no answer to Sync within 1 s", link_.transport().name()));
    }
    if (sent < kMaxSent && Clock::now() >= next) {
      link_.send_sync();
      ++sent;
      next = Clock::now() + std::chrono::milliseconds(3);
    }
    link_.wait(std::chrono::milliseconds(2));
  }
  next_sync_us_ = steady_us() + std::chrono::duration_cast<std::chrono::microseconds>(options_.sync_period).count();
}

void Player::set_up_device() {
  protocol::Message m = protocol::make(protocol::Type::settings, 0);
  m.settings = options_.settings;
  send(m);
  send_presets();
  sync_burst();
  baseline_ = link_.status();
}

void Player::start_at(std::int64_t song_us, double preroll_s) {
  ++epoch_;
  resend_.clear();
  scheduler_.seek(song_us);
  const bool resume = paused_ || !audio_.playing();
  paused_ = false;
  // The sound starts a little before the position, so that the first notes can reach the device in time
  // (a preroll of real time: more song time at a higher speed).
  audio_.start(song_us - seconds(preroll_s * options_.haptic.speed));
  if (resume) send_transport(protocol::TransportOp::play);
}

void Player::flush_device(protocol::TransportOp op, std::int64_t song_us) {
  send_transport(op, haptics::seconds_to_tick(song_us, tick_hz_));
  ++epoch_;
  resend_.clear();
  last_note_end_tick_ = 0;
}

void Player::set_track(haptics::HapticTrack&& track) {
  track_ = std::move(track);
  auto published = std::make_shared<const haptics::HapticTrack>(track_);
  std::lock_guard lock(mutex_);
  published_track_ = std::move(published);
}

void Player::rebuild_track(std::int64_t song_us) {
  haptics::HapticTrack rebuilt;
  try {
    rebuilt = haptics::build_haptic_track(song_, options_.track, options_.haptic);
  } catch (const BadInput& e) {
    message(fmt::format("cannot switch: {}", e.what()));
    return;
  }
  set_track(std::move(rebuilt));
  send_presets();
  if (!paused_) flush_device(protocol::TransportOp::seek, song_us);
  ++epoch_;
  resend_.clear();
  scheduler_.load(track_, song_us);
  const midi::Track& t = song_.tracks[options_.track];
  message(fmt::format("haptic track {} \"{}\" ({}), envelope {}, mapping {}", t.index, t.name,
                      midi::gm_instrument_name(t.program(), t.channel()), options_.haptic.envelope,
                      mapping::name(options_.haptic.mapping)));
}

void Player::schedule() {
  const std::int64_t now = steady_us();
  const std::optional<double> position = link_.position(now);
  if (!position) return;
  const auto device_now = static_cast<std::uint64_t>(std::max(0.0, std::floor(*position)));
  const auto lookahead = static_cast<std::uint64_t>(std::llround(options_.lookahead_s * tick_hz_));
  const auto stale = static_cast<std::uint64_t>(std::llround(options_.stale_s * tick_hz_));
  const std::uint64_t horizon = device_now + lookahead;
  const std::uint64_t stale_tick = device_now > stale ? device_now - stale : 0;
  const auto tick_of = [this](const NoteSound& sound) { return tick_of_sound(sound); };

  while (link_.credit() >= 1) {
    PendingReport report;
    bool resend = false;
    if (!resend_.empty()) {
      report = std::move(resend_.front());
      resend_.pop_front();
      resend = true;
    } else if (auto next = scheduler_.next(horizon, stale_tick, tick_of)) {
      report = std::move(*next);
    } else {
      break;
    }
    const std::optional<std::uint16_t> seq = send(report.message);
    if (!seq) return;  // the link died: check() says so on the next turn
    if (!resend) counters_.notes_sent += report.notes.size();
    for (const NoteOrigin& n : report.notes)
      last_note_end_tick_ = std::max(last_note_end_tick_, n.tick + n.duration_ticks);
    sent_[*seq] = SentReport{epoch_, std::move(report), 0};
  }
}

void Player::handle_events() {
  DeviceLink::Events events = link_.take_events();
  if (events.restarted) {
    recover("its clock went back");
    return;
  }
  for (const std::uint16_t seq : events.refused_full) {
    // Only a report of the present position is worth sending again; a flush made the others moot.
    auto it = sent_.find(seq);
    if (it == sent_.end()) continue;
    if (it->second.epoch == epoch_) resend_.push_back(std::move(it->second.report));
    sent_.erase(it);
  }
  for (const protocol::Error& e : events.errors) {
    if (e.code == protocol::ErrorCode::version_mismatch) {
      throw LinkError(fmt::format("device {} refused a report: protocol version mismatch", link_.transport().name()));
    }
    // Once per kind: a device refusing every note must not flood the terminal.
    if (!refusals_seen_.insert(static_cast<unsigned>(e.code) << 8 | e.type).second) continue;
    message(fmt::format("device refused a {} report (seq {}): {}", protocol::name(static_cast<protocol::Type>(e.type)),
                        e.seq, protocol::name(e.code)));
  }
  for (const protocol::StartedEntry& entry : events.started) {
    auto it = sent_.find(entry.seq);
    if (it == sent_.end() || entry.index >= it->second.report.notes.size()) continue;
    StartedNote s{it->second.report.notes[entry.index], extend(entry.scheduled_tick), extend(entry.actual_tick)};
    if (options_.on_started) options_.on_started(s);
    it->second.started_mask |= 1u << entry.index;
    if (++it->second.started == it->second.report.notes.size()) sent_.erase(it);
  }
}

static_assert(protocol::kNotesPerBatch <= 32, "SentReport::started_mask has a bit per note of a report");

void Player::count_cancelled(std::uint64_t stop_tick) {
  // A note of an earlier epoch went with the flush that ended it; one of the present epoch is dropped
  // by the stop only if its tick was still ahead of the device when the stop came. Every note left
  // unstarted before that tick the device should have started: not cancelled, it stays missing.
  for (const auto& [seq, sent] : sent_) {
    for (std::size_t i = 0; i < sent.report.notes.size(); ++i) {
      if (sent.started_mask & (1u << i)) continue;
      if (sent.epoch != epoch_ || sent.report.notes[i].tick > stop_tick) ++counters_.cancelled;
    }
  }
  sent_.clear();
}

void Player::recover(const std::string& why) {
  message(fmt::format("device restarted ({}): greeting it again", why));
  carried_ = counters_;  // what the old session counted (update_counters ignores the new one's reports)
  const protocol::HelloReply hello = link_.reconnect();
  sent_.clear();
  resend_.clear();
  last_note_end_tick_ = 0;
  if (hello.tick_hz != tick_hz_) {
    tick_hz_ = hello.tick_hz;
    options_.haptic.tick_hz = tick_hz_;
    set_track(haptics::build_haptic_track(song_, options_.track, options_.haptic));
    scheduler_.load(track_, song_now());
  }
  set_up_device();
  ++counters_.recoveries;
  if (!paused_) {
    paused_ = true;  // the new session is idle: start_at sends play
    paused_at_us_ = audio_.song_time_us();
    start_at(paused_at_us_, options_.seek_preroll_s);
  }
}

void Player::check_device_state() {
  const std::optional<protocol::Status> s = link_.status();
  if (!s) return;
  if (s->faults & protocol::fault_estop) {
    throw LinkError(fmt::format("device {}: emergency stop latched: playback stopped", link_.transport().name()));
  }
  // Idle after it processed our play: the device lost the session (it restarted, and its clock happens
  // not to look restarted).
  if (!paused_ && s->state == protocol::State::idle && play_seq_ && link_.processed(*play_seq_)) {
    recover("it is idle");
    return;
  }
  // The device's host watchdog fired (we were silent too long: a stalled host). Acknowledge with a stop,
  // then play on from where the song is; at most once a second (the Status may predate the stop).
  const std::int64_t now = steady_us();
  if (!paused_ && s->state == protocol::State::fault && now - last_fault_recovery_us_ > 1'000'000) {
    last_fault_recovery_us_ = now;
    message(fmt::format("device fault ({}): playing on", transport::fault_names(s->faults)));
    const std::int64_t at = song_now();
    flush_device(protocol::TransportOp::stop, at);
    paused_ = true;
    paused_at_us_ = at;
    start_at(at, options_.seek_preroll_s);
    ++counters_.recoveries;
  }
}

void Player::seek(std::int64_t target) {
  target = std::clamp(target, options_.from_us, window_end_us());
  if (paused_) {
    paused_at_us_ = target;
    audio_.seek(target);  // the clock (and the view) show the new position while paused
  } else {
    flush_device(protocol::TransportOp::seek, target);
    start_at(target, options_.seek_preroll_s);
  }
}

void Player::set_speed(double speed) {
  {
    std::lock_guard lock(mutex_);
    wanted_speed_ = std::clamp(speed, kMinSpeed, kMaxSpeed);
  }
  link_.notify();
}

void Player::apply_speed(double speed) {
  if (speed == options_.haptic.speed) return;
  const std::int64_t at = song_now();
  options_.haptic.speed = speed;
  audio_.set_speed(speed);  // the sound goes on from `at` at the new pace
  rebuild_track(at);        // the device's notes last 1/speed as long; resent from `at`
  message(fmt::format("speed {:g}×", speed));
}

void Player::seek_to(std::int64_t song_us) {
  {
    std::lock_guard lock(mutex_);
    wanted_seek_us_ = song_us;
  }
  link_.notify();
}

bool Player::handle_commands(Outcome& outcome) {
  std::deque<Command> commands;
  std::optional<std::int64_t> seek_to;
  std::optional<double> speed;
  {
    std::lock_guard lock(mutex_);
    commands.swap(commands_);
    seek_to.swap(wanted_seek_us_);
    speed.swap(wanted_speed_);
  }
  if (speed) apply_speed(*speed);
  if (seek_to) seek(*seek_to);
  for (const Command c : commands) {
    switch (c) {
      case Command::toggle_pause:
        if (paused_) {
          start_at(paused_at_us_, options_.seek_preroll_s);
        } else {
          paused_at_us_ = audio_.song_time_us();
          audio_.pause();
          flush_device(protocol::TransportOp::pause, paused_at_us_);
          paused_ = true;
        }
        break;
      case Command::seek_back:
      case Command::seek_forward: {
        const double step = c == Command::seek_back ? -options_.seek_step_s : options_.seek_step_s;
        seek(song_now() + seconds(step));
        break;
      }
      case Command::next_track:
      case Command::previous_track: {
        if (playable_tracks_.empty()) break;
        auto it = std::find(playable_tracks_.begin(), playable_tracks_.end(), options_.track);
        std::size_t i = it == playable_tracks_.end() ? 0 : static_cast<std::size_t>(it - playable_tracks_.begin());
        const std::size_t n = playable_tracks_.size();
        i = c == Command::next_track ? (i + 1) % n : (i + n - 1) % n;
        options_.track = playable_tracks_[i];
        rebuild_track(song_now());
        break;
      }
      case Command::cycle_envelope: {
        std::size_t i = 0;
        while (i < 3 && options_.haptic.envelope != kEnvelopeCycle[i]) ++i;
        options_.haptic.envelope = kEnvelopeCycle[i < 3 ? (i + 1) % 3 : 0];
        rebuild_track(song_now());
        break;
      }
      case Command::cycle_mapping: {
        std::size_t i = 0;
        while (i < 4 && options_.haptic.mapping != kMappingCycle[i]) ++i;
        options_.haptic.mapping = kMappingCycle[(i + 1) % 4];
        // legacy2013 has its own frequency range (design §5); the others use the user's.
        options_.haptic.ranges = base_ranges_;
        if (options_.haptic.mapping == mapping::Mode::legacy2013) {
          options_.haptic.ranges.f_min_hz = mapping::kLegacyFminHz;
          options_.haptic.ranges.f_max_hz = mapping::kLegacyFmaxHz;
        }
        rebuild_track(song_now());
        break;
      }
      case Command::slower:
      case Command::faster: {
        apply_speed(next_speed(options_.haptic.speed, c == Command::faster ? 1 : -1));
        break;
      }
      case Command::next_song: outcome = Outcome::next_song; return true;
      case Command::previous_song: outcome = Outcome::previous_song; return true;
      case Command::quit: outcome = Outcome::quit; return true;
      case Command::interrupt: outcome = Outcome::interrupted; return true;
    }
  }
  return false;
}

bool Player::ended() {
  if (paused_ || !scheduler_.finished() || !resend_.empty()) return false;
  if (song_now() < window_end_us()) return false;
  // The device's own report of its tick, not the clock fit's estimate: a device whose clock fell behind
  // the fit (an emulated board losing ticks on a busy host) still has notes to start, which a stop now
  // would cancel.
  const std::optional<protocol::Status> s = link_.status();
  return s && s->tick >= last_note_end_tick_ + 2;
}

void Player::finish() {
  protocol::Message m = protocol::make(protocol::Type::transport, 0);
  m.transport.op = protocol::TransportOp::stop;
  const std::optional<std::uint16_t> seq = send(m);
  audio_.stop();
  // The Status that follows the stop comes after every Started entry of the notes played before it.
  const auto deadline = Clock::now() + std::chrono::seconds(1);
  while (seq && !link_.processed(*seq) && Clock::now() < deadline) {
    link_.check();
    link_.wait(std::chrono::milliseconds(10));
  }
  handle_events();
  update_counters();
  if (const std::optional<protocol::Status> s = link_.status(); s && seq && link_.processed(*seq)) {
    count_cancelled(s->tick);
  }
  update_snapshot();
}

void Player::update_counters() {
  const std::optional<protocol::Status> s = link_.status();
  // A Status older than the baseline's tick comes from a device that restarted: recover() takes over.
  if (!s || !baseline_ || s->tick < baseline_->tick) return;
  counters_.notes_played = carried_.notes_played + since(s->started, baseline_->started);
  counters_.late = carried_.late + since(s->late, baseline_->late);
  counters_.stolen = carried_.stolen + since(s->stolen, baseline_->stolen);
  counters_.rejected = carried_.rejected + since(s->rejected, baseline_->rejected);
  counters_.skipped = scheduler_.skipped();
}

void Player::update_snapshot() {
  Snapshot s;
  s.song_us = song_now();
  s.end_us = window_end_us();
  s.paused = paused_;
  s.track = options_.track;
  s.track_name = song_.tracks[options_.track].name;
  s.envelope = options_.haptic.envelope;
  s.mapping = mapping::name(options_.haptic.mapping);
  s.counters = counters_;
  s.begin_us = options_.from_us;
  s.speed = options_.haptic.speed;
  s.song_label = options_.song_label;
  s.device_lost = device_lost_;
  s.queue_capacity = link_.hello().queue_capacity;
  if (const auto st = link_.status()) {
    s.queue_free = st->queue_free;
    s.device_state = st->state;
    s.active_voices = st->active_voices;
    if (st->grip_known != 0) s.grip_m = std::array<float, 3>{st->grip_m[0], st->grip_m[1], st->grip_m[2]};
  }
  {
    std::lock_guard lock(message_mutex_);
    s.message = message_;
    s.message_at = message_at_;
  }
  std::lock_guard lock(mutex_);
  s.haptic = published_track_;
  snapshot_ = std::move(s);
}

void Player::touch(std::uint32_t track, std::uint8_t key, double start_s) {
  {
    std::lock_guard lock(mutex_);
    touches_.push_back({track, key, start_s});
  }
  link_.notify();
}

const haptics::HapticTrack* Player::haptic_track_of(std::uint32_t track) {
  if (track == options_.track) return &track_;
  auto it = other_tracks_.find(track);
  if (it == other_tracks_.end()) {
    try {
      it = other_tracks_.emplace(track, haptics::build_haptic_track(song_, track, options_.haptic)).first;
    } catch (const BadInput& e) {
      message(fmt::format("touch: {}", e.what()));
      return nullptr;
    }
  }
  return &it->second;
}

void Player::handle_touches() {
  std::deque<Touch> touches;
  std::optional<std::uint32_t> wanted;
  {
    std::lock_guard lock(mutex_);
    touches.swap(touches_);
    wanted.swap(wanted_track_);
  }
  if (wanted && *wanted != options_.track) {
    if (std::find(playable_tracks_.begin(), playable_tracks_.end(), *wanted) == playable_tracks_.end()) {
      message(fmt::format("track {} has no notes to feel", *wanted));
    } else {
      options_.track = *wanted;
      rebuild_track(song_now());
    }
  }
  for (const Touch& t : touches) {
    if (paused_ || t.track >= song_.tracks.size()) continue;
    const haptics::HapticTrack* track = haptic_track_of(t.track);
    if (track == nullptr) continue;
    const auto found = std::find_if(track->notes.begin(), track->notes.end(), [&](const haptics::HapticNote& n) {
      return n.key == t.key && std::fabs(n.start_s - t.start_s) < 1e-6;
    });
    if (found == track->notes.end()) {
      message(fmt::format("touch: track {} has no note {} at {:.3f} s", t.track, t.key, t.start_s));
      continue;
    }
    // A user preset is on the device only for the haptic track (its slots are that track's).
    if (track != &track_ && found->note.preset >= envelope::kFirstUserSlot) {
      message(fmt::format("touch: the note's envelope is a user preset of track {}: not on the device", t.track));
      continue;
    }
    const std::optional<double> position = link_.position(steady_us());
    if (!position) continue;
    DeviceNote note = found->note;
    note.start_tick = static_cast<std::uint64_t>(std::ceil(*position + options_.touch_lead_s * tick_hz_));
    PendingReport report;
    make_report(std::span<const DeviceNote>(&note, 1), report.message);
    report.notes.push_back({t.track, t.key, found->start_s, note.start_tick, note.duration_ticks});
    const std::optional<std::uint16_t> seq = send(report.message);
    if (!seq) return;
    ++counters_.notes_sent;
    last_note_end_tick_ = std::max(last_note_end_tick_, note.start_tick + note.duration_ticks);
    sent_[*seq] = SentReport{epoch_, std::move(report), 0};
  }
}

void Player::select_track(std::uint32_t track) {
  {
    std::lock_guard lock(mutex_);
    wanted_track_ = track;
  }
  link_.notify();
}

void Player::post(Command c) {
  {
    std::lock_guard lock(mutex_);
    commands_.push_back(c);
  }
  link_.notify();
}

Snapshot Player::snapshot() const {
  std::lock_guard lock(mutex_);
  return snapshot_;
}

bool Player::turn(Outcome& outcome) {
  link_.wait(options_.loop_period);
  link_.check();
  handle_events();
  check_device_state();
  if (handle_commands(outcome)) return true;
  handle_touches();
  if (steady_us() >= next_sync_us_) {
    link_.send_sync();
    next_sync_us_ = steady_us() + std::chrono::duration_cast<std::chrono::microseconds>(options_.sync_period).count();
  }
  if (!paused_) schedule();
  update_counters();
  if (ended()) return true;
  update_snapshot();
  if (options_.on_idle) options_.on_idle();
  return false;
}

bool Player::wait_for_device(const std::string& why, Outcome& outcome) {
  // Everything sent to the old session is gone with it: the song waits where it was heard.
  if (!paused_) {
    paused_at_us_ = audio_.song_time_us();
    audio_.pause();
    paused_ = true;
  }
  update_counters();
  carried_ = counters_;
  baseline_.reset();
  ++epoch_;
  sent_.clear();
  resend_.clear();
  play_seq_.reset();
  last_note_end_tick_ = 0;
  link_.detach();
  device_lost_ = true;
  update_snapshot();
  message(why);
  message("device lost — plug it back in, or q to quit");
  std::string last_failure;
  auto next_try = Clock::now();
  // The other keys (seek, track, envelope, mapping, speed) wait for the device, as the window's seeks and
  // track choices do: handed back to handle_commands once it is there.
  std::deque<Command> waiting;
  for (;;) {
    std::deque<Command> commands;
    {
      std::lock_guard lock(mutex_);
      commands.swap(commands_);
    }
    for (const Command c : commands) {
      switch (c) {
        case Command::quit: outcome = Outcome::quit; break;
        case Command::interrupt: outcome = Outcome::interrupted; break;
        case Command::next_song: outcome = Outcome::next_song; break;
        case Command::previous_song: outcome = Outcome::previous_song; break;
        case Command::toggle_pause:
          play_when_ready_ = !play_when_ready_;
          message(play_when_ready_ ? "the song plays on when the device is back"
                                   : "the song stays paused when the device is back");
          continue;
        default: waiting.push_back(c); continue;
      }
      device_lost_ = false;
      update_snapshot();
      return false;
    }
    if (Clock::now() >= next_try) {
      next_try = Clock::now() + options_.find_period;
      try {
        if (transport::Transport* found = options_.find_device()) {
          const protocol::HelloReply hello = link_.attach(*found);
          if (hello.tick_hz != tick_hz_) {
            tick_hz_ = hello.tick_hz;
            options_.haptic.tick_hz = tick_hz_;
            set_track(haptics::build_haptic_track(song_, options_.track, options_.haptic));
          }
          ++counters_.recoveries;
          device_lost_ = false;
          message(fmt::format("device {} is back: {} at {}", found->name(), play_when_ready_ ? "playing on" : "paused",
                              format_time(paused_at_us_)));
          {
            std::lock_guard lock(mutex_);
            commands_.insert(commands_.begin(), waiting.begin(), waiting.end());
          }
          return true;
        }
      } catch (const DeviceLost& e) {
        // Opened but not answering yet (a board still booting): try again.
        if (e.what() != last_failure) message(last_failure = e.what());
      } catch (const transport::TransportError& e) {
        // There but not openable (permissions, busy): said once, tried again.
        if (e.what() != last_failure) message(last_failure = e.what());
      }
    }
    update_snapshot();
    if (options_.on_idle) options_.on_idle();
    link_.wait(std::chrono::milliseconds(20));
  }
}

Outcome Player::run() {
  paused_ = true;  // the device is idle: start_at sends play
  paused_at_us_ = options_.from_us;
  audio_.set_speed(options_.haptic.speed);
  bool ready = false, first = true;
  Outcome outcome = Outcome::finished;
  for (;;) {
    try {
      if (!ready) {
        set_up_device();
        ready = true;
        scheduler_.load(track_, paused_at_us_);
        if (play_when_ready_) start_at(paused_at_us_, first ? options_.start_preroll_s : options_.seek_preroll_s);
        first = false;
      }
      if (turn(outcome)) break;
    } catch (const DeviceLost& e) {
      if (!options_.find_device) throw;
      if (ready) play_when_ready_ = !paused_;  // as the user left it (lost while setting up: as it was)
      ready = false;
      if (!wait_for_device(e.what(), outcome)) return outcome;
    }
  }
  try {
    finish();
  } catch (const DeviceLost&) {
    // Lost while stopping: the song is over anyway, and a device that is gone vibrates no more.
    audio_.stop();
  }
  return outcome;
}

}  // namespace hmp::player
