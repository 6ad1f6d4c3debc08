#pragma once
// The wire protocol (design §9): 64-byte reports, little-endian, fixed layouts, versioned.
// The same reports travel over USB HID, a framed serial link, and in process.
// docs/protocol.md documents every byte. decode() accepts any 64 bytes and returns either a message
// or a typed error; it never reads outside the report.
//
// Common header of every report:
//   byte 0     type   (0x01–0x3F host→device, 0x81–0xBF device→host)
//   bytes 1–2  seq    u16: host reports number themselves 1, 2, …; the device echoes the last one it
//                     processed (carried out or refused) in its status. Device reports carry their own counter.
//   bytes 3–63 payload, layout per type; unused bytes must be zero (checked: catches misframed data).
//
// Error codes decode() returns: unknown_type (byte 0), bad_length_field (count fields), bad_slot (preset
// slot numbers), bad_value (any other field out of range, non-finite floats, unknown enum values),
// nonzero_padding (a byte after the payload or in an unused note/entry slot is not zero). Fields are
// checked in wire order (the first bad one decides the code), then the padding. decode() is direction-agnostic: the
// receiver checks the direction with is_host_to_device() and answers wrong_direction itself.
#include <cstddef>
#include <cstdint>

#include "shared/envelope/envelope.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::protocol {

inline constexpr std::size_t kReportSize = 64;
// 2: Status carries the grip's position (bytes 45–57), for touching notes in the view.
// 3: Live reports (notes started now and held until released, pitch bend) and the not_playing error.
inline constexpr std::uint16_t kProtocolVersion = 3;
inline constexpr std::uint16_t kUsbVid = 0x1209;  // pid.codes open-source VID
inline constexpr std::uint16_t kUsbPid = 0x0001;  // pid.codes test PID (to be replaced by an allocated one)
inline constexpr std::uint16_t kUsagePage = 0xFF00;
inline constexpr std::size_t kNotesPerBatch = 5;
inline constexpr std::size_t kNoteBytes = 11;
inline constexpr std::uint32_t kMaxCompactDuration = 0xFFFFFF;  // longer notes go in a LongNote

// The seq after `last`, host's or device's: 1, 2, …, 65535, then 1 again; 0 never names a report.
constexpr std::uint16_t next_seq(std::uint16_t last) {
  return static_cast<std::uint16_t>(last == 0xFFFFu ? 1u : last + 1u);
}

using Report = std::uint8_t[kReportSize];

enum class Type : std::uint8_t {
  // host → device
  hello = 0x01,
  sync = 0x02,
  notes = 0x03,      // batch of up to 5 compact notes
  long_note = 0x04,  // one note with 64-bit start and 32-bit duration
  preset = 0x05,     // envelope preset upload into a user slot
  settings = 0x06,
  transport = 0x07,
  estop = 0x08,
  live = 0x09,  // up to 5 live events: a held note on, its release, its frequency
  // device → host
  hello_reply = 0x81,
  sync_reply = 0x82,
  status = 0x83,
  started = 0x84,  // notes the device started: scheduled vs actual tick (for --log)
  error = 0x85,
};

// Type byte checks (any byte value is accepted).
bool is_known_type(std::uint8_t type);
inline bool is_host_to_device(Type t) { return (static_cast<std::uint8_t>(t) & 0x80u) == 0; }

// ---- host → device ----
// bytes 3–4 protocol_version u16 (≥ 1). Hello and HelloReply keep this layout in every protocol
// version, so two peers of different versions can always tell each other their version.
struct Hello {
  std::uint16_t protocol_version = kProtocolVersion;
  friend bool operator==(const Hello&, const Hello&) = default;
};

// bytes 3–10 host_time_us u64 (any value; echoed back in the SyncReply)
struct Sync {
  std::uint64_t host_time_us = 0;  // echoed back
  friend bool operator==(const Sync&, const Sync&) = default;
};

// A compact note: start = base_tick + offset (11 bytes on the wire):
//   offset u8 | preset u8 (slot < kSlotCount) | duration u24 (ticks, 1 … kMaxCompactDuration)
//   | freq u32 (Q12.20 Hz, any) | amp u16 (65535 = 1.0, any)
// Notes whose start lies more than 255 ticks after the batch's base go in another batch; notes longer
// than kMaxCompactDuration ticks go in a LongNote.
struct CompactNote {
  std::uint8_t offset = 0;
  std::uint8_t preset = 0;
  std::uint32_t duration_ticks = 1;
  std::uint32_t freq_q20 = 0;
  std::uint16_t amp_q16 = 0;
  friend bool operator==(const CompactNote&, const CompactNote&) = default;
};

// bytes 3 count (1–5) | 4 track | 5–8 base_tick u32 (low 32 bits of the device tick; the device picks the
// 64-bit tick nearest its own clock) | 9–63 notes (11 bytes each, unused slots zero)
struct Notes {
  std::uint8_t count = 0;
  std::uint8_t track = 0;
  std::uint32_t base_tick = 0;
  CompactNote notes[kNotesPerBatch];  // slots ≥ count are ignored by encode and default after decode
  friend bool operator==(const Notes&, const Notes&) = default;
};

// bytes 3 track | 4 preset (< kSlotCount) | 5–12 start_tick u64 (full device tick) | 13–16 duration u32
// (≥ 1) | 17–20 freq u32 | 21–22 amp u16
struct LongNote {
  std::uint8_t track = 0;
  std::uint8_t preset = 0;
  std::uint64_t start_tick = 0;
  std::uint32_t duration_ticks = 1;
  std::uint32_t freq_q20 = 0;
  std::uint16_t amp_q16 = 0;
  friend bool operator==(const LongNote&, const LongNote&) = default;
};

// bytes 3 slot [kFirstUserSlot, kSlotCount) | 4 shape (envelope::Shape) | 5–8 attack_ms f32 | 9–12 decay_ms
// | 13–16 release_ms | 17–20 sustain | 21–24 final (envelope::valid() must hold)
struct Preset {
  std::uint8_t slot = envelope::kFirstUserSlot;
  envelope::Adsr adsr{};
};
// Field by field (envelope::Adsr has no operator== of its own).
inline bool operator==(const Preset& a, const Preset& b) {
  return a.slot == b.slot && a.adsr.attack_ms == b.adsr.attack_ms && a.adsr.decay_ms == b.adsr.decay_ms &&
         a.adsr.release_ms == b.adsr.release_ms && a.adsr.sustain == b.adsr.sustain &&
         a.adsr.final_ratio == b.adsr.final_ratio && a.adsr.shape == b.adsr.shape;
}

enum class PolicyCode : std::uint8_t { sum = 0, highest = 1, latest = 2 };

// bytes 3 policy | 4–7 gain f32 [0,1] | 8–11 peak_force_n f32 (0,20] | 12–23 direction x,y,z f32 (unit
// within 1e-3) | 24–27 end_fade_ms f32 [0,1000] | 28–29 watchdog_ms u16 (≥ 10) | 30–31 ramp_in_ms u16
// (any) | 32–35 t_min_n f32 (≥ 0) | 36–39 t_max_n f32 (t_min < t_max ≤ 20; a device with motors refuses
// one it cannot hold: firmware Drive::max_tension_n)
// The largest force of full scale a Settings message may ask for (the motors' reach on the SPIDAR-G6).
inline constexpr float kMaxPeakForceN = 20.0f;

struct Settings {
  PolicyCode policy = PolicyCode::sum;
  float gain = 1.0f;
  float peak_force_n = 1.0f;
  float direction[3] = {0.0f, 1.0f, 0.0f};
  float end_fade_ms = 2.0f;
  std::uint16_t watchdog_ms = 250;
  std::uint16_t ramp_in_ms = 500;
  float t_min_n = 0.3f;
  float t_max_n = 6.0f;
  friend bool operator==(const Settings&, const Settings&) = default;
};

// One live event (9 bytes): op u8 | key u8 (any: the host's handle of a held note; on, off and bend pair
// by the report's track and this key) | preset u8 (on: < kSlotCount; off, bend: 0) | freq u32 (on, bend:
// Q12.20 Hz; off: 0) | amp u16 (on: 65535 = 1.0; off, bend: 0).
enum class LiveOp : std::uint8_t { on = 1, off = 2, bend = 3 };
struct LiveEvent {
  LiveOp op = LiveOp::on;
  std::uint8_t key = 0;
  std::uint8_t preset = 0;
  std::uint32_t freq_q20 = 0;
  std::uint16_t amp_q16 = 0;
  friend bool operator==(const LiveEvent&, const LiveEvent&) = default;
};
inline constexpr std::size_t kLiveEventBytes = 9;
// bytes 3 count (1–5) | 4 track | 5–49 events (9 bytes each, unused slots zero). Acted on in the tick it
// is taken in, in order, while the device plays; not queued (no credit).
struct Live {
  std::uint8_t count = 0;
  std::uint8_t track = 0;
  LiveEvent events[kNotesPerBatch];  // slots ≥ count: ignored by encode, default after decode
  friend bool operator==(const Live&, const Live&) = default;
};

enum class TransportOp : std::uint8_t { play = 0, pause = 1, stop = 2, seek = 3 };
// bytes 3 op | 4–11 tick u64 (seek: flush, then continue at this song tick; other ops: must be 0)
struct Transport {
  TransportOp op = TransportOp::play;
  std::uint64_t tick = 0;
  friend bool operator==(const Transport&, const Transport&) = default;
};

// No payload: bytes 3–63 zero.
struct Estop {
  friend bool operator==(const Estop&, const Estop&) = default;
};

// ---- device → host ----
enum class Board : std::uint8_t { sim = 0, qemu_an386 = 1, stm32f407 = 2 };

// Conditions of the board itself, set once at start-up (HelloReply). Not faults: the device still plays.
enum BoardFlag : std::uint8_t {
  board_clock_fallback = 1u << 0,  // the crystal or the PLL did not start: running on the internal oscillator
  board_no_usb = 1u << 1,          // USB is off (it needs the crystal's accuracy); the UART link works
  board_watchdog_reset = 1u << 2,  // the last reset was the watchdog's (a stuck tick or main loop)
  board_no_drive = 1u << 3,        // no motor board detected: the SPIDAR drive is off, the vibration is computed
};
inline constexpr std::uint8_t kKnownBoardFlags = 0x0F;

// bytes 3–4 protocol u16 (≥ 1) | 5 fw major | 6 fw minor | 7 fw patch | 8 board | 9–12 tick_hz u32 (≥ 1)
// | 13 voices (≥ 1) | 14–15 queue capacity u16 (note reports, see Status) | 16 preset slots
// | 17 board flags (BoardFlag bits; a reply with any other bit set is rejected)
struct HelloReply {
  std::uint16_t protocol_version = kProtocolVersion;
  std::uint8_t fw_major = 0, fw_minor = 0, fw_patch = 0;
  Board board = Board::sim;
  std::uint32_t tick_hz = synth::kNominalTickHz;
  std::uint8_t voices = 16;
  std::uint16_t queue_capacity = 0;
  std::uint8_t preset_slots = envelope::kSlotCount;
  std::uint8_t board_flags = 0;
  friend bool operator==(const HelloReply&, const HelloReply&) = default;
};

// bytes 3–10 host_time_us (echo) | 11–18 device tick u64 | 19–22 sub-tick u32 (fraction of the tick
// elapsed when the request was handled, 2^32 = one tick)
struct SyncReply {
  std::uint64_t host_time_us = 0;
  std::uint64_t tick = 0;
  std::uint32_t subtick = 0;
  friend bool operator==(const SyncReply&, const SyncReply&) = default;
};

enum class State : std::uint8_t { idle = 0, playing = 1, paused = 2, stopped = 3, fault = 4 };

// Latched fault bits.
enum Fault : std::uint32_t {
  fault_none = 0,
  fault_estop = 1u << 0,
  fault_watchdog = 1u << 1,
  fault_output_limit = 1u << 2,
  fault_queue_overflow = 1u << 3,
  fault_qp_infeasible = 1u << 4,
  fault_pose_diverged = 1u << 5,
  fault_encoder_jump = 1u << 6,
  fault_string_slack = 1u << 7,
};
inline constexpr std::uint32_t kKnownFaults = 0xFFu;  // a status with any other bit set is rejected

// bytes 3–10 tick u64 | 11–12 queue free u16 | 13–14 last seq processed u16 | 15–18 late u32
// | 19–22 stolen u32 | 23–26 rejected u32 | 27–30 started u32 | 31–34 faults u32 (kKnownFaults) | 35 state
// | 36 active voices | 37–40 output f32 [-1,1] | 41–44 achieved force f32 (N, along the direction, finite)
// | 45–56 grip position x, y, z f32 (m, device frame, each within ±kGripRangeM) | 57 grip known u8 (0/1;
// 0: no drive or no pose, and the position is zero)
// queue_free counts note reports (Notes or LongNote, each up to a full batch) the device will still accept
// after the one numbered last_seq; counters are cumulative and wrap.
inline constexpr float kGripRangeM = 4.0f;  // no SPIDAR frame is larger: beyond it the report is corrupt
struct Status {
  std::uint64_t tick = 0;
  std::uint16_t queue_free = 0;
  std::uint16_t last_seq = 0;
  std::uint32_t late = 0, stolen = 0, rejected = 0, started = 0;
  std::uint32_t faults = 0;
  State state = State::idle;
  std::uint8_t active_voices = 0;
  float output = 0.0f;
  float force_n = 0.0f;
  float grip_m[3] = {0.0f, 0.0f, 0.0f};
  std::uint8_t grip_known = 0;  // 0 or 1
  friend bool operator==(const Status&, const Status&) = default;
};

// One started note: seq u16 + index u8 of the note in its report (LongNote: index 0), scheduled and
// actual tick (low 32 bits each) → 11 bytes: seq u16 | index u8 (< kNotesPerBatch) | scheduled u32
// | actual u32. bytes 3 count (1–5) | 4–58 entries (unused entries zero) | 59–63 zero.
struct StartedEntry {
  std::uint16_t seq = 0;
  std::uint8_t index = 0;
  std::uint32_t scheduled_tick = 0;
  std::uint32_t actual_tick = 0;
  friend bool operator==(const StartedEntry&, const StartedEntry&) = default;
};
struct Started {
  std::uint8_t count = 0;
  StartedEntry entries[kNotesPerBatch];  // entries ≥ count: ignored by encode, default after decode
  friend bool operator==(const Started&, const Started&) = default;
};

enum class ErrorCode : std::uint8_t {
  none = 0,
  // decode errors (also sent back in an Error report with the offending seq)
  unknown_type,
  bad_length_field,  // a count or size field outside its range
  bad_value,         // a field outside its documented range (NaN, negative duration, …)
  nonzero_padding,   // bytes after the payload are not zero
  wrong_direction,   // a device→host type received by the device or vice versa
  // semantic errors (device)
  version_mismatch,
  queue_full,
  bad_slot,
  not_playing,  // a Live report while the device is not playing
};
const char* name(ErrorCode e);
const char* name(Type t);

// bytes 3 code (any ErrorCode but none) | 4–5 seq of the offending report | 6 offending type byte (any:
// it may be the unknown one). When decoding failed, seq and type are read raw from bytes 1–2 and 0.
struct Error {
  ErrorCode code = ErrorCode::none;
  std::uint16_t seq = 0;
  std::uint8_t type = 0;
  friend bool operator==(const Error&, const Error&) = default;
};

// A decoded report: `type` says which member is valid (a tagged union without RTTI or heap).
struct Message {
  Type type = Type::hello;
  std::uint16_t seq = 0;
  union {
    Hello hello;
    Sync sync;
    Notes notes;
    LongNote long_note;
    Preset preset;
    Settings settings;
    Transport transport;
    Estop estop;
    Live live;
    HelloReply hello_reply;
    SyncReply sync_reply;
    Status status;
    Started started;
    Error error;
  };
  Message() : hello() {}
};
// Same type, seq and active member (for notes/started: only the first `count` slots).
bool operator==(const Message& a, const Message& b);

// The checks decode applies to the fields (everything but padding); ErrorCode::none if encodable.
ErrorCode validate(const Message& msg);
// Encode a message into a report (all 64 bytes written). Returns false if the message itself is
// invalid (the same checks decode applies), in which case the report is zeroed.
bool encode(const Message& msg, Report& out);
// Decode any 64 bytes. On failure returns the error and leaves `out` unspecified.
// On success, encode(out) reproduces `in` exactly.
ErrorCode decode(const std::uint8_t (&in)[kReportSize], Message& out);

// The bytes of `report` a serial frame carries (docs/protocol.md, "Serial framing"): without its
// trailing zeros, except for a greeting (Hello, HelloReply), which goes whole so that a peer of an
// older protocol version, whose decoder wants all 64 bytes, still reads it and the versions are told.
std::size_t wire_size(const Report& report);

// Builders for the common case: the member for `t` default-initialised (an unknown t gives a Hello).
Message make(Type t, std::uint16_t seq);

}  // namespace hmp::protocol
