// Host → device reports: one handler per type. Every report is decoded and validated in full
// (shared/protocol) before anything acts on it; a refused report is answered with an Error and changes
// nothing else (a note batch is taken whole or not at all).
#include "firmware/core.hpp"
#include "shared/synth/frequency.hpp"

namespace hmp::fw {

using protocol::ErrorCode;
using protocol::State;
using protocol::Type;

void Core::handle(const InboxEntry& entry) {
  ++stats_.packets;
  if (entry.error != ErrorCode::none) {
    // The header is read raw: the type byte may be the unknown one.
    reject(entry.error, entry.raw_seq, entry.raw_type);
    return;
  }
  const protocol::Message& m = entry.message;
  if (!protocol::is_host_to_device(m.type)) {
    reject(ErrorCode::wrong_direction, m.seq, static_cast<std::uint8_t>(m.type));
    return;
  }
  // A well-formed report shows the host is alive, even one refused below for what it asks, and it is
  // "processed" for Status.last_seq whether carried out or refused (docs/protocol.md, flow control).
  const std::uint64_t rx = rx_tick64(entry.rx_tick);
  if (rx > last_host_tick_) last_host_tick_ = rx;
  last_seq_ = m.seq;

  // After a Hello of another protocol version only Hello, Sync and Estop are understood.
  if (version_locked_ && m.type != Type::hello && m.type != Type::sync && m.type != Type::estop) {
    reject(ErrorCode::version_mismatch, m.seq, static_cast<std::uint8_t>(m.type));
    return;
  }
  switch (m.type) {
    case Type::hello: on_hello(m); break;
    case Type::sync: on_sync(m, entry); break;
    case Type::notes: on_notes(m, rx); break;
    case Type::long_note: on_long_note(m); break;
    case Type::preset: on_preset(m); break;
    case Type::settings: on_settings(m); break;
    case Type::transport: on_transport(m); break;
    case Type::estop: emergency_stop(); break;
    case Type::live: on_live(m); break;
    default: break;  // unreachable: decode knows no other host type
  }
}

void Core::on_hello(const protocol::Message& m) {
  version_locked_ = m.hello.protocol_version != protocol::kProtocolVersion;
  if (!version_locked_) {
    // A new session: nothing of the old one keeps sounding or waiting, faults are acknowledged.
    // Settings and uploaded presets stay.
    flush_notes();
    engine_.stop_all();
    output_.silence();
    faults_ = protocol::fault_none;
    state_ = State::idle;
    status_countdown_ = 1;  // the Status that follows each HelloReply goes out at the end of this tick
    log_event("hello, protocol ", m.hello.protocol_version);
  }
  // The reply tells a host of another version which version we speak; the Error then refuses its own.
  protocol::Message reply = protocol::make(Type::hello_reply, 0);
  reply.hello_reply.protocol_version = protocol::kProtocolVersion;
  reply.hello_reply.fw_major = kFirmwareMajor;
  reply.hello_reply.fw_minor = kFirmwareMinor;
  reply.hello_reply.fw_patch = kFirmwarePatch;
  reply.hello_reply.board = board_.id;
  reply.hello_reply.tick_hz = tick_hz_;
  reply.hello_reply.voices = synth::kVoiceCount;
  reply.hello_reply.queue_capacity = kQueueCapacityReports;
  reply.hello_reply.preset_slots = envelope::kSlotCount;
  reply.hello_reply.board_flags = board_.flags;
  send(reply);
  if (version_locked_) reject(ErrorCode::version_mismatch, m.seq, static_cast<std::uint8_t>(m.type));
}

void Core::on_sync(const protocol::Message& m, const InboxEntry& entry) {
  protocol::Message reply = protocol::make(Type::sync_reply, 0);
  reply.sync_reply.host_time_us = m.sync.host_time_us;
  reply.sync_reply.tick = rx_tick64(entry.rx_tick);
  reply.sync_reply.subtick = entry.rx_subtick;
  send(reply);
}

// What the wire format allows but this device cannot play: an empty preset slot (bad_slot), a
// frequency of 0 or at/above half the tick rate (bad_value). Checked for the whole report before any
// note is queued, so a report is taken whole or not at all.
ErrorCode Core::check_playable(std::uint8_t preset, std::uint32_t freq_q20) const {
  if (engine_.preset(preset) == nullptr) return ErrorCode::bad_slot;
  if (!engine_.frequency_ok(freq_q20)) return ErrorCode::bad_value;
  return ErrorCode::none;
}

void Core::on_notes(const protocol::Message& m, std::uint64_t rx_tick) {
  const protocol::Notes& batch = m.notes;
  for (std::uint8_t i = 0; i < batch.count; ++i) {
    const ErrorCode e = check_playable(batch.notes[i].preset, batch.notes[i].freq_q20);
    if (e != ErrorCode::none) {
      reject(e, m.seq, static_cast<std::uint8_t>(m.type));
      return;
    }
  }
  if (batch.count > free_note_slots()) {
    reject(ErrorCode::queue_full, m.seq, static_cast<std::uint8_t>(m.type));
    return;
  }
  // base_tick carries the low 32 bits; take the 64-bit tick nearest to the arrival (a base up to 2^31
  // ticks in the past or future). Before tick 0 there is nothing: such notes are simply late.
  const auto delta = static_cast<std::int32_t>(batch.base_tick - static_cast<std::uint32_t>(rx_tick));
  std::uint64_t base = rx_tick + static_cast<std::uint64_t>(static_cast<std::int64_t>(delta));
  if (delta < 0 && static_cast<std::uint64_t>(-static_cast<std::int64_t>(delta)) > rx_tick) base = 0;
  for (std::uint8_t i = 0; i < batch.count; ++i) {
    const protocol::CompactNote& c = batch.notes[i];
    synth::Note note;
    note.start_tick = base + c.offset;
    note.duration_ticks = c.duration_ticks;
    note.freq_q20 = c.freq_q20;
    note.amp_q16 = c.amp_q16;
    note.preset = c.preset;
    note.track = batch.track;
    queue_.push(note, m.seq, i);
  }
}

void Core::on_long_note(const protocol::Message& m) {
  const protocol::LongNote& l = m.long_note;
  const ErrorCode e = check_playable(l.preset, l.freq_q20);
  if (e != ErrorCode::none) {
    reject(e, m.seq, static_cast<std::uint8_t>(m.type));
    return;
  }
  if (free_note_slots() == 0) {
    reject(ErrorCode::queue_full, m.seq, static_cast<std::uint8_t>(m.type));
    return;
  }
  synth::Note note;
  note.start_tick = l.start_tick;
  note.duration_ticks = l.duration_ticks;
  note.freq_q20 = l.freq_q20;
  note.amp_q16 = l.amp_q16;
  note.preset = l.preset;
  note.track = l.track;
  queue_.push(note, m.seq, 0);
}

// Live input: each event acts on this tick, in order (no schedule: a note-on sounds now, a note-off starts
// its release now). Taken whole or not at all, like a note batch; only while playing (a device that does
// not play would start notes nobody asked to hear once it does).
void Core::on_live(const protocol::Message& m) {
  const protocol::Live& b = m.live;
  const auto type = static_cast<std::uint8_t>(m.type);
  if (state_ != State::playing) {
    reject(ErrorCode::not_playing, m.seq, type);
    return;
  }
  for (std::uint8_t i = 0; i < b.count; ++i) {
    const protocol::LiveEvent& e = b.events[i];
    ErrorCode error = ErrorCode::none;
    if (e.op == protocol::LiveOp::on) error = check_playable(e.preset, e.freq_q20);
    if (e.op == protocol::LiveOp::bend && !engine_.frequency_ok(e.freq_q20)) error = ErrorCode::bad_value;
    if (error != ErrorCode::none) {
      reject(error, m.seq, type);
      return;
    }
  }
  for (std::uint8_t i = 0; i < b.count; ++i) {
    const protocol::LiveEvent& e = b.events[i];
    switch (e.op) {
      case protocol::LiveOp::on: {
        QueuedNote q;
        q.note.start_tick = tick_;
        q.note.freq_q20 = e.freq_q20;
        q.note.amp_q16 = e.amp_q16;
        q.note.preset = e.preset;
        q.note.track = b.track;
        q.note.key = e.key;
        q.seq = m.seq;
        q.index = i;
        if (!engine_.start_held(q.note)) {
          ++stats_.engine_refused;  // unreachable: checked above
          break;
        }
        ++stats_.started;
        ++stats_.started_in_tick;
        note_started(q);
        break;
      }
      case protocol::LiveOp::off: engine_.release(b.track, e.key); break;
      case protocol::LiveOp::bend: engine_.bend(b.track, e.key, e.freq_q20); break;
    }
  }
  // A player at the keys waits for no Status tick (up to 10 ms away): the Started report goes out now.
  flush_started();
}

void Core::on_preset(const protocol::Message& m) {
  if (!engine_.set_preset(m.preset.slot, m.preset.adsr)) {
    reject(ErrorCode::bad_slot, m.seq, static_cast<std::uint8_t>(m.type));  // decode checks it: unreachable
    return;
  }
  prep_.invalidate();  // voices prepared with the slot's old envelope; notes started from now on use the new one
}

void Core::on_settings(const protocol::Message& m) {
  if (has_drive_ && m.settings.t_max_n > drive_.max_tension_n()) {  // more than the motors can hold
    reject(ErrorCode::bad_value, m.seq, static_cast<std::uint8_t>(m.type));
    return;
  }
  settings_ = m.settings;
  apply_settings();
}

void Core::apply_settings() {
  static constexpr synth::Polyphony kPolicies[] = {synth::Polyphony::sum, synth::Polyphony::highest,
                                                   synth::Polyphony::latest};
  const auto policy = static_cast<std::uint8_t>(settings_.policy);
  engine_.set_polyphony(policy < 3 ? kPolicies[policy] : synth::Polyphony::sum);
  if (settings_.end_fade_ms != synth_cfg_.end_fade_ms) {
    synth_cfg_.end_fade_ms = settings_.end_fade_ms;  // applies to notes started from now on
    engine_.configure(synth_cfg_);
    prep_.invalidate();  // voices prepared with the old fade
  }
  output_.configure(tick_hz_, settings_.ramp_in_ms, settings_.gain);
  drive_.apply(settings_);
  watchdog_ticks_ = ms_to_ticks(settings_.watchdog_ms, tick_hz_);
}

void Core::on_transport(const protocol::Message& m) {
  switch (m.transport.op) {
    case protocol::TransportOp::play:
      if (state_ == State::fault) {  // latched: only hello or stop clears it
        log_event("play refused: fault latched ", faults_);
        return;
      }
      if (state_ != State::playing) {
        if (!output_.silent()) engine_.stop_all();  // a fade still running: cut it, then ramp from 0
        output_.start_ramp();
        last_host_tick_ = tick_;
        state_ = State::playing;
        log_event("play at tick ", tick_);
      }
      return;
    case protocol::TransportOp::pause:
      if (state_ != State::fault) fade_out(State::paused);
      return;
    case protocol::TransportOp::stop:
      fade_out(State::stopped);
      if (faults_ != protocol::fault_none) log_event("stop clears faults ", faults_);
      faults_ = protocol::fault_none;
      return;
    case protocol::TransportOp::seek:
      // Notes are scheduled in device ticks: after a seek the host sends the notes of the new position.
      // Whatever was queued or sounding belongs to the old one.
      flush_notes();
      engine_.stop_all();
      song_tick_ = m.transport.tick;
      log_event("seek to song tick ", song_tick_);
      return;
  }
}

void Core::emergency_stop() {
  engine_.stop_all();
  output_.silence();
  flush_notes();
  faults_ |= protocol::fault_estop;
  if (state_ != State::fault) log_event("EMERGENCY STOP at tick ", tick_);
  state_ = State::fault;
}

}  // namespace hmp::fw
