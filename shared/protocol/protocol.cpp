#include "shared/protocol/protocol.hpp"

#include "shared/common/bytes.hpp"
#include "shared/framing/framing.hpp"

namespace hmp::protocol {
namespace {

constexpr std::size_t kHeaderSize = 3;  // type u8 + seq u16

// The payload walkers: one description of each layout (walk() below) drives both directions, so the
// encoder and the decoder cannot disagree about an offset. Both refuse to step past the report's end
// (which a correct layout never asks for) instead of trusting the arithmetic.
class Reader {
 public:
  explicit Reader(const std::uint8_t* report) : p_(report) {}
  void u8(std::uint8_t& v) {
    if (const std::uint8_t* q = take(1)) v = q[0];
  }
  void u16(std::uint16_t& v) {
    if (const std::uint8_t* q = take(2)) v = bytes::get_u16(q);
  }
  void u24(std::uint32_t& v) {
    if (const std::uint8_t* q = take(3)) v = bytes::get_u24(q);
  }
  void u32(std::uint32_t& v) {
    if (const std::uint8_t* q = take(4)) v = bytes::get_u32(q);
  }
  void u64(std::uint64_t& v) {
    if (const std::uint8_t* q = take(8)) v = bytes::get_u64(q);
  }
  void f32(float& v) {
    if (const std::uint8_t* q = take(4)) v = bytes::get_f32(q);
  }
  // One-byte enums: every byte value is representable (uint8_t underlying type); validate() range-checks.
  template <class E>
  void e8(E& v) {
    if (const std::uint8_t* q = take(1)) v = static_cast<E>(q[0]);
  }
  std::size_t end() const { return pos_; }
  bool overflowed() const { return overflow_; }

 private:
  const std::uint8_t* take(std::size_t n) {
    if (pos_ + n > kReportSize) {
      overflow_ = true;
      return nullptr;
    }
    const std::uint8_t* q = p_ + pos_;
    pos_ += n;
    return q;
  }
  const std::uint8_t* p_;
  std::size_t pos_ = kHeaderSize;
  bool overflow_ = false;
};

class Writer {
 public:
  explicit Writer(std::uint8_t* report) : p_(report) {}
  void u8(std::uint8_t v) {
    if (std::uint8_t* q = take(1)) q[0] = v;
  }
  void u16(std::uint16_t v) {
    if (std::uint8_t* q = take(2)) bytes::put_u16(q, v);
  }
  void u24(std::uint32_t v) {
    if (std::uint8_t* q = take(3)) bytes::put_u24(q, v);
  }
  void u32(std::uint32_t v) {
    if (std::uint8_t* q = take(4)) bytes::put_u32(q, v);
  }
  void u64(std::uint64_t v) {
    if (std::uint8_t* q = take(8)) bytes::put_u64(q, v);
  }
  void f32(float v) {
    if (std::uint8_t* q = take(4)) bytes::put_f32(q, v);
  }
  template <class E>
  void e8(E v) {
    u8(static_cast<std::uint8_t>(v));
  }
  bool overflowed() const { return overflow_; }

 private:
  std::uint8_t* take(std::size_t n) {
    if (pos_ + n > kReportSize) {
      overflow_ = true;
      return nullptr;
    }
    std::uint8_t* q = p_ + pos_;
    pos_ += n;
    return q;
  }
  std::uint8_t* p_;
  std::size_t pos_ = kHeaderSize;
  bool overflow_ = false;
};

// Slots a count field makes live; an out-of-range count reads/writes none (validate() rejects it).
std::size_t live_slots(std::uint8_t count) { return count <= kNotesPerBatch ? count : 0; }

static_assert(kHeaderSize + 6 + kNotesPerBatch * kNoteBytes == kReportSize, "a notes batch fills the report");

// The byte layouts of protocol.hpp / docs/protocol.md, in wire order. Msg is Message (decode) or
// const Message (encode).
template <class IO, class Msg>
void walk(IO& io, Msg& m) {
  switch (m.type) {
    case Type::hello: io.u16(m.hello.protocol_version); break;
    case Type::sync: io.u64(m.sync.host_time_us); break;
    case Type::notes: {
      auto& b = m.notes;
      io.u8(b.count);
      io.u8(b.track);
      io.u32(b.base_tick);
      for (std::size_t i = 0; i < live_slots(b.count); ++i) {
        auto& n = b.notes[i];
        io.u8(n.offset);
        io.u8(n.preset);
        io.u24(n.duration_ticks);
        io.u32(n.freq_q20);
        io.u16(n.amp_q16);
      }
      break;
    }
    case Type::long_note: {
      auto& n = m.long_note;
      io.u8(n.track);
      io.u8(n.preset);
      io.u64(n.start_tick);
      io.u32(n.duration_ticks);
      io.u32(n.freq_q20);
      io.u16(n.amp_q16);
      break;
    }
    case Type::preset: {
      auto& p = m.preset;
      io.u8(p.slot);
      io.e8(p.adsr.shape);
      io.f32(p.adsr.attack_ms);
      io.f32(p.adsr.decay_ms);
      io.f32(p.adsr.release_ms);
      io.f32(p.adsr.sustain);
      io.f32(p.adsr.final_ratio);
      break;
    }
    case Type::settings: {
      auto& s = m.settings;
      io.e8(s.policy);
      io.f32(s.gain);
      io.f32(s.peak_force_n);
      for (auto& d : s.direction) io.f32(d);
      io.f32(s.end_fade_ms);
      io.u16(s.watchdog_ms);
      io.u16(s.ramp_in_ms);
      io.f32(s.t_min_n);
      io.f32(s.t_max_n);
      break;
    }
    case Type::transport:
      io.e8(m.transport.op);
      io.u64(m.transport.tick);
      break;
    case Type::estop: break;
    case Type::live: {
      auto& b = m.live;
      io.u8(b.count);
      io.u8(b.track);
      for (std::size_t i = 0; i < live_slots(b.count); ++i) {
        auto& e = b.events[i];
        io.e8(e.op);
        io.u8(e.key);
        io.u8(e.preset);
        io.u32(e.freq_q20);
        io.u16(e.amp_q16);
      }
      break;
    }
    case Type::hello_reply: {
      auto& h = m.hello_reply;
      io.u16(h.protocol_version);
      io.u8(h.fw_major);
      io.u8(h.fw_minor);
      io.u8(h.fw_patch);
      io.e8(h.board);
      io.u32(h.tick_hz);
      io.u8(h.voices);
      io.u16(h.queue_capacity);
      io.u8(h.preset_slots);
      io.u8(h.board_flags);
      break;
    }
    case Type::sync_reply:
      io.u64(m.sync_reply.host_time_us);
      io.u64(m.sync_reply.tick);
      io.u32(m.sync_reply.subtick);
      break;
    case Type::status: {
      auto& s = m.status;
      io.u64(s.tick);
      io.u16(s.queue_free);
      io.u16(s.last_seq);
      io.u32(s.late);
      io.u32(s.stolen);
      io.u32(s.rejected);
      io.u32(s.started);
      io.u32(s.faults);
      io.e8(s.state);
      io.u8(s.active_voices);
      io.f32(s.output);
      io.f32(s.force_n);
      for (std::size_t i = 0; i < 3; ++i) io.f32(s.grip_m[i]);
      io.u8(s.grip_known);
      break;
    }
    case Type::started: {
      auto& b = m.started;
      io.u8(b.count);
      for (std::size_t i = 0; i < live_slots(b.count); ++i) {
        auto& e = b.entries[i];
        io.u16(e.seq);
        io.u8(e.index);
        io.u32(e.scheduled_tick);
        io.u32(e.actual_tick);
      }
      break;
    }
    case Type::error:
      io.e8(m.error.code);
      io.u16(m.error.seq);
      io.u8(m.error.type);
      break;
  }
}

// Range checks written so that NaN fails them (every comparison with NaN is false).
bool within(float v, float lo, float hi) { return v >= lo && v <= hi; }
bool is_finite(float v) { return __builtin_isfinite(v); }
bool count_ok(std::uint8_t count) { return count >= 1 && count <= kNotesPerBatch; }
bool slot_ok(std::uint8_t slot) { return slot < envelope::kSlotCount; }

// A unit vector within 1e-3: | |d| − 1 | ≤ 1e-3, compared on the squared norm (no sqrt) in double.
bool unit_vector(const float (&d)[3]) {
  double norm2 = 0.0;
  for (float c : d) {
    if (!is_finite(c)) return false;
    norm2 += static_cast<double>(c) * static_cast<double>(c);
  }
  constexpr double lo = (1.0 - 1e-3) * (1.0 - 1e-3), hi = (1.0 + 1e-3) * (1.0 + 1e-3);
  return norm2 >= lo && norm2 <= hi;
}

ErrorCode check_note(std::uint8_t preset, std::uint32_t duration, std::uint32_t max_duration) {
  if (!slot_ok(preset)) return ErrorCode::bad_slot;
  if (duration < 1 || duration > max_duration) return ErrorCode::bad_value;
  return ErrorCode::none;
}

ErrorCode check(const Notes& b) {
  if (!count_ok(b.count)) return ErrorCode::bad_length_field;
  for (std::size_t i = 0; i < b.count; ++i) {
    const CompactNote& n = b.notes[i];
    if (const ErrorCode e = check_note(n.preset, n.duration_ticks, kMaxCompactDuration); e != ErrorCode::none) return e;
  }
  return ErrorCode::none;
}

// Each op carries only its own fields; the others must be zero (a misread op cannot pass as another).
ErrorCode check(const Live& b) {
  if (!count_ok(b.count)) return ErrorCode::bad_length_field;
  for (std::size_t i = 0; i < b.count; ++i) {
    const LiveEvent& e = b.events[i];
    switch (e.op) {
      case LiveOp::on:
        if (!slot_ok(e.preset)) return ErrorCode::bad_slot;
        break;
      case LiveOp::off:
        if (e.preset != 0 || e.freq_q20 != 0 || e.amp_q16 != 0) return ErrorCode::bad_value;
        break;
      case LiveOp::bend:
        if (e.preset != 0 || e.amp_q16 != 0) return ErrorCode::bad_value;
        break;
      default: return ErrorCode::bad_value;
    }
  }
  return ErrorCode::none;
}

ErrorCode check(const Preset& p) {
  if (p.slot < envelope::kFirstUserSlot || p.slot >= envelope::kSlotCount) return ErrorCode::bad_slot;
  const bool shape_known =
      static_cast<std::uint8_t>(p.adsr.shape) <= static_cast<std::uint8_t>(envelope::Shape::damped);
  return shape_known && envelope::valid(p.adsr) ? ErrorCode::none : ErrorCode::bad_value;
}

ErrorCode check(const Settings& s) {
  const bool ok = static_cast<std::uint8_t>(s.policy) <= static_cast<std::uint8_t>(PolicyCode::latest) &&
                  within(s.gain, 0.0f, 1.0f) && s.peak_force_n > 0.0f && s.peak_force_n <= kMaxPeakForceN &&
                  unit_vector(s.direction) && within(s.end_fade_ms, 0.0f, 1000.0f) && s.watchdog_ms >= 10 &&
                  within(s.t_min_n, 0.0f, 20.0f) && s.t_max_n > s.t_min_n && s.t_max_n <= 20.0f;
  return ok ? ErrorCode::none : ErrorCode::bad_value;
}

ErrorCode check(const Transport& t) {
  if (static_cast<std::uint8_t>(t.op) > static_cast<std::uint8_t>(TransportOp::seek)) return ErrorCode::bad_value;
  return t.op == TransportOp::seek || t.tick == 0 ? ErrorCode::none : ErrorCode::bad_value;
}

ErrorCode check(const HelloReply& h) {
  const bool ok = h.protocol_version >= 1 &&
                  static_cast<std::uint8_t>(h.board) <= static_cast<std::uint8_t>(Board::stm32f407) && h.tick_hz >= 1 &&
                  h.voices >= 1 && (h.board_flags & ~kKnownBoardFlags) == 0;
  return ok ? ErrorCode::none : ErrorCode::bad_value;
}

ErrorCode check(const Status& s) {
  const bool ok = static_cast<std::uint8_t>(s.state) <= static_cast<std::uint8_t>(State::fault) &&
                  (s.faults & ~kKnownFaults) == 0 && within(s.output, -1.0f, 1.0f) && is_finite(s.force_n);
  bool grip_ok = true;
  for (const float v : s.grip_m) {
    // Unknown: the bytes are zero (−0.0 too would compare equal to 0 but is not).
    grip_ok =
        grip_ok && within(v, -kGripRangeM, kGripRangeM) && (s.grip_known != 0 || (v == 0.0f && !__builtin_signbit(v)));
  }
  return ok && grip_ok && s.grip_known <= 1 ? ErrorCode::none : ErrorCode::bad_value;
}

ErrorCode check(const Started& b) {
  if (!count_ok(b.count)) return ErrorCode::bad_length_field;
  for (std::size_t i = 0; i < b.count; ++i)
    if (b.entries[i].index >= kNotesPerBatch) return ErrorCode::bad_value;
  return ErrorCode::none;
}

ErrorCode check(const Error& e) {
  const auto code = static_cast<std::uint8_t>(e.code);
  return code >= 1 && code <= static_cast<std::uint8_t>(ErrorCode::not_playing) ? ErrorCode::none
                                                                                : ErrorCode::bad_value;
}

}  // namespace

bool is_known_type(std::uint8_t type) {
  switch (static_cast<Type>(type)) {
    case Type::hello:
    case Type::sync:
    case Type::notes:
    case Type::long_note:
    case Type::preset:
    case Type::settings:
    case Type::transport:
    case Type::estop:
    case Type::live:
    case Type::hello_reply:
    case Type::sync_reply:
    case Type::status:
    case Type::started:
    case Type::error: return true;
  }
  return false;
}

ErrorCode validate(const Message& m) {
  switch (m.type) {
    case Type::hello: return m.hello.protocol_version >= 1 ? ErrorCode::none : ErrorCode::bad_value;
    case Type::notes: return check(m.notes);
    case Type::long_note: return check_note(m.long_note.preset, m.long_note.duration_ticks, 0xFFFFFFFFu);
    case Type::preset: return check(m.preset);
    case Type::settings: return check(m.settings);
    case Type::transport: return check(m.transport);
    case Type::live: return check(m.live);
    case Type::hello_reply: return check(m.hello_reply);
    case Type::status: return check(m.status);
    case Type::started: return check(m.started);
    case Type::error: return check(m.error);
    case Type::sync:
    case Type::estop:
    case Type::sync_reply: return ErrorCode::none;  // every field value is meaningful
  }
  return ErrorCode::unknown_type;
}

bool encode(const Message& msg, Report& out) {
  for (auto& b : out) b = 0;
  if (validate(msg) != ErrorCode::none) return false;
  out[0] = static_cast<std::uint8_t>(msg.type);
  bytes::put_u16(out + 1, msg.seq);
  Writer w(out);
  walk(w, msg);
  if (w.overflowed()) {  // unreachable with the layouts above; kept so a layout slip cannot write past out
    for (auto& b : out) b = 0;
    return false;
  }
  return true;
}

ErrorCode decode(const std::uint8_t (&in)[kReportSize], Message& out) {
  if (!is_known_type(in[0])) return ErrorCode::unknown_type;
  out = make(static_cast<Type>(in[0]), bytes::get_u16(in + 1));
  Reader r(in);
  walk(r, out);
  if (r.overflowed()) return ErrorCode::bad_length_field;  // unreachable, as in encode
  if (const ErrorCode e = validate(out); e != ErrorCode::none) return e;
  for (std::size_t i = r.end(); i < kReportSize; ++i)
    if (in[i] != 0) return ErrorCode::nonzero_padding;
  return ErrorCode::none;
}

std::size_t wire_size(const Report& report) {
  const auto type = static_cast<Type>(report[0]);
  if (type == Type::hello || type == Type::hello_reply) return kReportSize;
  return framing::carried_size(report, kReportSize);
}

Message make(Type t, std::uint16_t seq) {
  Message m;
  m.seq = seq;
  if (!is_known_type(static_cast<std::uint8_t>(t))) return m;
  m.type = t;
  switch (t) {
    case Type::hello: m.hello = Hello{}; break;
    case Type::sync: m.sync = Sync{}; break;
    case Type::notes: m.notes = Notes{}; break;
    case Type::long_note: m.long_note = LongNote{}; break;
    case Type::preset: m.preset = Preset{}; break;
    case Type::settings: m.settings = Settings{}; break;
    case Type::transport: m.transport = Transport{}; break;
    case Type::estop: m.estop = Estop{}; break;
    case Type::live: m.live = Live{}; break;
    case Type::hello_reply: m.hello_reply = HelloReply{}; break;
    case Type::sync_reply: m.sync_reply = SyncReply{}; break;
    case Type::status: m.status = Status{}; break;
    case Type::started: m.started = Started{}; break;
    case Type::error: m.error = Error{}; break;
  }
  return m;
}

bool operator==(const Message& a, const Message& b) {
  if (a.type != b.type || a.seq != b.seq) return false;
  switch (a.type) {
    case Type::hello: return a.hello == b.hello;
    case Type::sync: return a.sync == b.sync;
    case Type::notes: {
      const Notes &x = a.notes, &y = b.notes;
      if (x.count != y.count || x.track != y.track || x.base_tick != y.base_tick) return false;
      for (std::size_t i = 0; i < live_slots(x.count); ++i)
        if (!(x.notes[i] == y.notes[i])) return false;
      return true;
    }
    case Type::long_note: return a.long_note == b.long_note;
    case Type::preset: return a.preset == b.preset;
    case Type::settings: return a.settings == b.settings;
    case Type::transport: return a.transport == b.transport;
    case Type::estop: return true;
    case Type::live: {
      const Live &x = a.live, &y = b.live;
      if (x.count != y.count || x.track != y.track) return false;
      for (std::size_t i = 0; i < live_slots(x.count); ++i)
        if (!(x.events[i] == y.events[i])) return false;
      return true;
    }
    case Type::hello_reply: return a.hello_reply == b.hello_reply;
    case Type::sync_reply: return a.sync_reply == b.sync_reply;
    case Type::status: return a.status == b.status;
    case Type::started: {
      const Started &x = a.started, &y = b.started;
      if (x.count != y.count) return false;
      for (std::size_t i = 0; i < live_slots(x.count); ++i)
        if (!(x.entries[i] == y.entries[i])) return false;
      return true;
    }
    case Type::error: return a.error == b.error;
  }
  return true;  // both carry the same unknown type: no payload to compare
}

const char* name(ErrorCode e) {
  switch (e) {
    case ErrorCode::none: return "none";
    case ErrorCode::unknown_type: return "unknown_type";
    case ErrorCode::bad_length_field: return "bad_length_field";
    case ErrorCode::bad_value: return "bad_value";
    case ErrorCode::nonzero_padding: return "nonzero_padding";
    case ErrorCode::wrong_direction: return "wrong_direction";
    case ErrorCode::version_mismatch: return "version_mismatch";
    case ErrorCode::queue_full: return "queue_full";
    case ErrorCode::bad_slot: return "bad_slot";
    case ErrorCode::not_playing: return "not_playing";
  }
  return "unknown_error";
}

const char* name(Type t) {
  switch (t) {
    case Type::hello: return "hello";
    case Type::sync: return "sync";
    case Type::notes: return "notes";
    case Type::long_note: return "long_note";
    case Type::preset: return "preset";
    case Type::settings: return "settings";
    case Type::transport: return "transport";
    case Type::estop: return "estop";
    case Type::live: return "live";
    case Type::hello_reply: return "hello_reply";
    case Type::sync_reply: return "sync_reply";
    case Type::status: return "status";
    case Type::started: return "started";
    case Type::error: return "error";
  }
  return "unknown_type";
}

}  // namespace hmp::protocol
