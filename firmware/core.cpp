#include "firmware/core.hpp"

namespace hmp::fw {

using protocol::State;

// The RAM budget of docs/firmware.md (measured: 12.1 KiB on the Cortex-M4F build, 8 KiB of it the note
// queue). A change that outgrows it must update the budget table too.
static_assert(sizeof(Core) <= 22 * 1024, "Core outgrew its RAM budget (docs/firmware.md)");
static_assert(kMotorCount == Drive::kMotors, "the board seam and the drive disagree on the motor count");

Core::Core(const BoardSeam& board, std::uint32_t tick_hz, std::uint64_t first_tick, const DriveParams& drive)
    : board_(board),
      tick_hz_(tick_hz != 0 ? tick_hz : kDefaultTickHz),
      drive_(tick_hz_, drive),
      has_drive_(board.read_encoders != nullptr && board.motor_output != nullptr),
      tick_(first_tick) {
  tick_lo_.store(static_cast<std::uint32_t>(tick_), std::memory_order_relaxed);
  last_host_tick_ = tick_;
  synth_cfg_.tick_hz = tick_hz_;
  synth_cfg_.end_fade_ms = settings_.end_fade_ms;
  engine_.configure(synth_cfg_);
  // Status ≥ 50 Hz while playing (design §9): 100 Hz at any tick rate; 10 Hz otherwise, so a host that
  // preloads the queue before play still sees queue_free move.
  status_period_playing_ = tick_hz_ >= 100 ? tick_hz_ / 100 : 1;
  status_period_idle_ = tick_hz_ >= 10 ? tick_hz_ / 10 : 1;
  const std::uint64_t ahead = static_cast<std::uint64_t>(tick_hz_) * kPrepareAheadMs / 1000;
  prepare_ahead_ticks_ = ahead > 2 ? static_cast<std::uint32_t>(ahead) : 2;
  apply_settings();
}

InboxEntry Core::decode_packet(const protocol::Report& report) {
  InboxEntry e;
  e.error = protocol::decode(report, e.message);
  e.raw_type = report[0];
  e.raw_seq = static_cast<std::uint16_t>(report[1] | (report[2] << 8));
  if (report[0] == static_cast<std::uint8_t>(protocol::Type::estop)) {
    bool zero_payload = true;
    for (std::size_t i = 3; i < protocol::kReportSize; ++i) zero_payload = zero_payload && report[i] == 0;
    e.estop = zero_payload;
  }
  return e;
}

bool Core::on_decoded(const InboxEntry& decoded, std::uint32_t* stamped_tick) {
  // An emergency stop must not wait behind other reports (or be lost to a full inbox): a well-formed
  // one raises a flag the next tick checks first. It still goes through the inbox to be acknowledged.
  if (decoded.estop) estop_pending_.store(true, std::memory_order_release);
  InboxEntry* slot = inbox_.prepare();
  if (slot == nullptr) {  // the tick turns this into a latched fault (this context must not touch stats_)
    inbox_lost_.store(inbox_lost_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    return false;
  }
  *slot = decoded;
  slot->rx_tick = tick_lo_.load(std::memory_order_relaxed);
  slot->rx_subtick = board_.subtick != nullptr ? board_.subtick(board_.ctx) : 0;
  if (stamped_tick != nullptr) *stamped_tick = slot->rx_tick;
  inbox_.commit();
  return true;
}

// Reports first in poll(): a host waits for them; voices are needed only on their tick.
bool Core::send_reports() {
  bool sent = false;
  while (const protocol::Message* m = outbox_.front()) {
    protocol::Report report;
    // encode() refusing one of our own reports would be a bug; count it like a report the board dropped.
    if (!protocol::encode(*m, report) || board_.send == nullptr || !board_.send(board_.ctx, report)) {
      send_failed_.store(send_failed_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    }
    outbox_.pop();
    sent = true;
  }
  return sent;
}

bool Core::prepare_voices() {
  bool prepared = false;
  while (prep_.prepare_one()) prepared = true;
  return prepared;
}

std::uint64_t Core::rx_tick64(std::uint32_t rx_tick) const {
  // The report arrived at or before the present tick, less than 2^32 ticks ago.
  return tick_ - static_cast<std::uint32_t>(static_cast<std::uint32_t>(tick_) - rx_tick);
}

void Core::on_tick() {
  ++tick_;
  tick_lo_.store(static_cast<std::uint32_t>(tick_), std::memory_order_relaxed);

  // 1. Safety first: an emergency stop silences this very tick.
  // (A plain load first: the exchange, a load-exclusive/store-exclusive loop, only when it is set.)
  if (estop_pending_.load(std::memory_order_acquire) && estop_pending_.exchange(false, std::memory_order_acq_rel)) {
    emergency_stop();
  }
  if (link_lost_.load(std::memory_order_acquire) && link_lost_.exchange(false, std::memory_order_acq_rel) &&
      state_ == State::playing) {
    log_event("link lost (suspend): fading out at tick ", tick_);
    fade_out(State::paused);
  }
  const std::uint32_t lost = inbox_lost_.load(std::memory_order_acquire);
  if (lost != stats_.inbox_full) {
    faults_ |= protocol::fault_queue_overflow;
    log_event("inbox full, reports lost: ", lost - stats_.inbox_full);
    stats_.inbox_full = lost;
  }
  // 2. Commands (bounded number per tick).
  for (std::uint32_t n = 0; n < kMaxPacketsPerTick; ++n) {
    const InboxEntry* entry = inbox_.front();
    if (entry == nullptr) break;
    handle(*entry);
    inbox_.pop();
  }
  // 3. Host watchdog, 4. due notes, and the next note to prepare in the background.
  check_watchdog();
  // (The checks inline: most ticks start nothing and hand nothing over.)
  const QueuedNote* pending = prep_.front();
  const bool queued = !queue_.empty();
  if (state_ == State::playing && ((pending != nullptr && pending->note.start_tick <= tick_) ||
                                   (queued && queue_.top().note.start_tick <= tick_))) {
    start_due_notes();
  }
  if (queued && queue_.top().note.start_tick <= tick_ + prepare_ahead_ticks_) request_upcoming();
  // 5. Voices, mix, policy and limiter (the engine), then ramp/fade, gain and clamp.
  const float mixed = output_.silent() ? 0.0f : engine_.tick();
  last_output_ = output_.process(mixed, faults_);
  if (output_.silent() && engine_.active_voices() > 0) engine_.stop_all();  // a fade has ended
  if (board_.output != nullptr) board_.output(board_.ctx, last_output_);
  // 6. The SPIDAR drive: encoders in, motor duties out.
  if (has_drive_) run_drive();
  // 7. Status and Started reports.
  send_periodic_reports();
}

void Core::run_drive() {
  // Safe state (docs/spidar.md): the drive cannot trust what it senses, so it holds every string at t_min
  // with plain stall duties. After an emergency stop or the watchdog the sensing is fine: the drive goes
  // on rendering, with the vibration at zero, so the strings' force returns to the bias cleanly.
  constexpr std::uint32_t kSensingFaults = protocol::fault_qp_infeasible | protocol::fault_pose_diverged |
                                           protocol::fault_encoder_jump | protocol::fault_string_slack;
  const bool safe = (faults_ & kSensingFaults) != 0;
  if (drive_.split()) {
    run_split_drive(safe);
    return;
  }
  std::int32_t counts[kMotorCount];
  board_.read_encoders(board_.ctx, counts);
  const DriveTick t = drive_.tick(last_output_, safe, counts, duty_);
  apply_drive_tick(t);
  if (t.faults != 0) drive_fault(t.faults);
}

// What every drive tick (whole or split) ends with: the duties out, the counters, what Status reports.
void Core::apply_drive_tick(const DriveTick& t) {
  board_.motor_output(board_.ctx, duty_);
  if (t.flags & spidar::flag::saturated) ++stats_.drive_saturated;
  if (t.flags & spidar::flag::not_converged) ++stats_.drive_not_converged;
  force_n_ = t.force_n;
  grip_ = t.grip;
}

// The split drive's tick: every ticks_per_plan() ticks a plan is asked for (with this tick's counts), and
// every tick renders from the newest plan; the faults a plan found are taken once.
void Core::run_split_drive(bool safe) {
  if (plan_countdown_ == 0) {
    plan_countdown_ = drive_.ticks_per_plan();
    if (plan_wanted_.load(std::memory_order_acquire)) {
      ++stats_.drive_plan_late;
    } else {
      board_.read_encoders(board_.ctx, plan_in_.counts);  // only when a plan needs them
      plan_in_.safe = safe;
      drive_.close_speed_window();
      plan_wanted_.store(true, std::memory_order_release);
    }
  }
  --plan_countdown_;
  const DrivePlan& plan = plans_[plan_front_.load(std::memory_order_acquire)];
  const std::uint32_t seq = plan_seq_.load(std::memory_order_acquire);
  const bool fresh = plan_seen_ != seq;
  if (fresh) drive_.take_plan_speeds(plan);
  apply_drive_tick(drive_.render(last_output_, safe, plan, duty_));
  if (fresh) {
    plan_seen_ = seq;
    if (plan.faults != 0) drive_fault(plan.faults);
  }
}

bool Core::plan_drive() {
  if (!drive_.split() || !plan_wanted_.load(std::memory_order_acquire)) return false;
  const std::uint8_t back = static_cast<std::uint8_t>(1u - plan_front_.load(std::memory_order_relaxed));
  drive_.plan(plan_in_, plans_[back]);
  plan_front_.store(back, std::memory_order_release);
  plan_seq_.fetch_add(1, std::memory_order_release);
  plan_wanted_.store(false, std::memory_order_release);
  return true;
}

// The drive cannot trust what it senses: no vibration from now on, the strings held at t_min (the drive
// already holds them on the tick it noticed), until the host acknowledges with Hello or Stop.
void Core::drive_fault(std::uint32_t faults) {
  const std::uint32_t fresh = faults & ~faults_;
  faults_ |= faults;
  engine_.stop_all();
  output_.silence();
  flush_notes();
  if (fresh != 0) log_event("drive fault, bits ", fresh);
  state_ = State::fault;
}

// Notes due now, earliest first: from the prepared ones and the schedule, whichever comes first in the
// schedule's order (a note can reach the schedule after later ones were handed to the background).
void Core::start_due_notes() {
  for (std::uint32_t n = 0; n < kMaxStartsPerTick; ++n) {
    const QueuedNote* pending = prep_.front();
    const QueuedNote* queued = queue_.empty() ? nullptr : &queue_.top();
    const bool prepared = pending != nullptr && (queued == nullptr || NoteQueue::before(*pending, *queued));
    const QueuedNote* next = prepared ? pending : queued;
    if (next == nullptr || next->note.start_tick > tick_) break;
    const QueuedNote q = *next;
    const synth::Voice* voice = prepared ? prep_.front_voice() : nullptr;
    const bool started = voice != nullptr ? engine_.start_prepared(*voice) : engine_.start(q.note);
    if (prepared) {
      prep_.pop_front();
    } else {
      queue_.pop();
    }
    if (!started) {
      ++stats_.engine_refused;
      continue;
    }
    ++stats_.started;
    if (voice == nullptr) ++stats_.started_in_tick;
    if (q.note.start_tick < tick_) {
      ++stats_.late;
      if (worth_logging(stats_.late)) log_event("late note, ticks behind: ", tick_ - q.note.start_tick);
    }
    note_started(q);
  }
}

// One note per tick leaves the schedule for the background to prepare its voice, once it is due within
// kPrepareAheadMs: one heap pop and a copy, so the tick's cost stays flat.
void Core::request_upcoming() {
  if (queue_.empty() || !prep_.can_request()) return;
  const QueuedNote& next = queue_.top();
  if (next.note.start_tick > tick_ + prepare_ahead_ticks_) return;  // (checked inline in on_tick too)
  const envelope::Adsr* preset = engine_.preset(next.note.preset);
  if (preset == nullptr) return;  // the engine refuses it on its tick
  prep_.request(next, *preset, synth_cfg_);
  queue_.pop();
  ++stats_.prepare_requests;
}

void Core::flush_notes() {
  queue_.clear();
  prep_.clear();
}

void Core::check_watchdog() {
  if (state_ != State::playing || watchdog_ticks_ == 0) return;
  if (tick_ - last_host_tick_ < watchdog_ticks_) return;
  faults_ |= protocol::fault_watchdog;
  log_event("watchdog: host silent for ticks ", tick_ - last_host_tick_);
  fade_out(State::fault);
}

void Core::fade_out(State next) {
  flush_notes();
  output_.start_fade();
  state_ = next;
}

void Core::send_periodic_reports() {
  // A countdown rather than tick % period: no 64-bit division on the Cortex-M4 in every tick.
  if (status_countdown_ > 1) {
    --status_countdown_;
    return;
  }
  status_countdown_ = state_ == State::playing ? status_period_playing_ : status_period_idle_;
  flush_started();
  if (protocol::Message* m = begin_report(protocol::Type::status)) {
    write_status(m->status);  // in place: the report is the tick's heaviest copy otherwise
    outbox_.commit();
  }
}

Stats Core::stats() const {
  Stats s = stats_;
  s.tx_dropped = outbox_full_ + send_failed_.load(std::memory_order_relaxed);
  return s;
}

protocol::Status Core::status() const {
  protocol::Status s;
  write_status(s);
  return s;
}

void Core::write_status(protocol::Status& s) const {
  s.tick = tick_;
  s.queue_free = static_cast<std::uint16_t>(free_note_slots() / protocol::kNotesPerBatch);
  s.last_seq = last_seq_;
  s.late = stats_.late;
  s.stolen = engine_.counters().stolen;
  s.rejected = stats_.rejected + stats_.engine_refused;
  s.started = stats_.started;
  s.faults = faults_;
  s.state = state_;
  s.active_voices = engine_.active_voices();
  s.output = last_output_;
  s.force_n = has_drive_ ? force_n_ : last_output_ * settings_.peak_force_n;
  // Only finite positions inside the report's range are sent (a wild estimate is "not known"); without
  // a drive there is none, and the tick that queues the Status does no more (it is the 16-voice tick's
  // heaviest kind, design §8).
  s.grip_known = 0;
  if (has_drive_ && grip_.known) {
    const float grip[3] = {grip_.position.x, grip_.position.y, grip_.position.z};
    bool inside = true;
    for (const float v : grip) inside = inside && v >= -protocol::kGripRangeM && v <= protocol::kGripRangeM;
    if (inside) {
      s.grip_known = 1;
      for (int i = 0; i < 3; ++i) s.grip_m[i] = grip[i];
      return;
    }
  }
  for (float& v : s.grip_m) v = 0.0f;
}

}  // namespace hmp::fw
