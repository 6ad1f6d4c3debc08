// Wire protocol (design §9, docs/protocol.md): layouts checked against bytes written by hand from the
// documented offsets, range checks, padding checks, and decode over random and mutated input.
#include "shared/protocol/protocol.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace hmp::protocol {
namespace {

using Bytes = std::array<std::uint8_t, kReportSize>;

constexpr Type kAllTypes[] = {Type::hello,      Type::sync,      Type::notes,   Type::long_note, Type::preset,
                              Type::settings,   Type::transport, Type::estop,   Type::live,      Type::hello_reply,
                              Type::sync_reply, Type::status,    Type::started, Type::error};

// Payload ends from docs/protocol.md (first byte that must be zero), written out independently of the
// implementation's layout walker.
std::size_t documented_end(const Message& m) {
  switch (m.type) {
    case Type::hello: return 5;
    case Type::sync: return 11;
    case Type::notes: return 9 + 11 * std::size_t{m.notes.count};
    case Type::long_note: return 23;
    case Type::preset: return 25;
    case Type::settings: return 40;
    case Type::transport: return 12;
    case Type::estop: return 3;
    case Type::live: return 5 + 9 * std::size_t{m.live.count};
    case Type::hello_reply: return 18;
    case Type::sync_reply: return 23;
    case Type::status: return 58;
    case Type::started: return 4 + 11 * std::size_t{m.started.count};
    case Type::error: return 7;
  }
  return 0;
}

Bytes encoded(const Message& m) {
  Bytes b{};
  EXPECT_TRUE(encode(m, *reinterpret_cast<Report*>(b.data()))) << name(m.type);
  return b;
}

ErrorCode decode_bytes(const Bytes& b, Message& out) {
  return decode(*reinterpret_cast<const std::uint8_t(*)[kReportSize]>(b.data()), out);
}

std::vector<std::uint8_t> le(std::uint64_t v, std::size_t n) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  return out;
}
std::vector<std::uint8_t> le_f32(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return le(u, 4);
}

// ---- random valid messages ----
class Gen {
 public:
  explicit Gen(std::uint64_t seed) : rng_(seed) {}
  std::uint64_t bits(unsigned n) { return n >= 64 ? rng_() : rng_() & ((std::uint64_t{1} << n) - 1); }
  std::uint8_t u8() { return static_cast<std::uint8_t>(bits(8)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(bits(16)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(bits(32)); }
  std::uint64_t u64() { return bits(64); }
  std::uint64_t in(std::uint64_t lo, std::uint64_t hi) {
    return std::uniform_int_distribution<std::uint64_t>(lo, hi)(rng_);
  }
  float real(double lo, double hi) { return static_cast<float>(std::uniform_real_distribution<double>(lo, hi)(rng_)); }

  Message message(Type t) {
    Message m = make(t, u16());
    switch (t) {
      case Type::hello: m.hello.protocol_version = static_cast<std::uint16_t>(in(1, 0xFFFF)); break;
      case Type::sync: m.sync.host_time_us = u64(); break;
      case Type::notes: {
        Notes& b = m.notes;
        b.count = static_cast<std::uint8_t>(in(1, kNotesPerBatch));
        b.track = u8();
        b.base_tick = u32();
        for (std::size_t i = 0; i < b.count; ++i)
          b.notes[i] = CompactNote{u8(), static_cast<std::uint8_t>(in(0, 31)),
                                   static_cast<std::uint32_t>(in(1, 0xFFFFFF)), u32(), u16()};
        break;
      }
      case Type::long_note:
        m.long_note = LongNote{u8(),  static_cast<std::uint8_t>(in(0, 31)),
                               u64(), static_cast<std::uint32_t>(in(1, 0xFFFFFFFF)),
                               u32(), u16()};
        break;
      case Type::preset:
        m.preset.slot = static_cast<std::uint8_t>(in(16, 31));
        m.preset.adsr = envelope::Adsr{real(0, 5000), real(0, 5000), real(0, 5000),
                                       real(0, 1),    real(0, 1),    static_cast<envelope::Shape>(in(0, 2))};
        break;
      case Type::settings: {
        Settings& s = m.settings;
        s.policy = static_cast<PolicyCode>(in(0, 2));
        s.gain = real(0, 1);
        s.peak_force_n = real(0.01, 20);
        double d[3], n2 = 0;
        do {
          n2 = 0;
          for (double& c : d) {
            c = std::uniform_real_distribution<double>(-1, 1)(rng_);
            n2 += c * c;
          }
        } while (n2 < 0.01);
        for (int i = 0; i < 3; ++i) s.direction[i] = static_cast<float>(d[i] / std::sqrt(n2));
        s.end_fade_ms = real(0, 1000);
        s.watchdog_ms = static_cast<std::uint16_t>(in(10, 0xFFFF));
        s.ramp_in_ms = u16();
        s.t_min_n = real(0, 5);
        s.t_max_n = real(5.5, 20);
        break;
      }
      case Type::transport:
        m.transport.op = static_cast<TransportOp>(in(0, 3));
        m.transport.tick = m.transport.op == TransportOp::seek ? u64() : 0;
        break;
      case Type::estop: break;
      case Type::live: {
        Live& b = m.live;
        b.count = static_cast<std::uint8_t>(in(1, kNotesPerBatch));
        b.track = u8();
        for (std::size_t i = 0; i < b.count; ++i) {
          const auto op = static_cast<LiveOp>(in(1, 3));
          LiveEvent& e = b.events[i];
          e = LiveEvent{op, u8(), 0, 0, 0};
          if (op == LiveOp::on) e = LiveEvent{op, e.key, static_cast<std::uint8_t>(in(0, 31)), u32(), u16()};
          if (op == LiveOp::bend) e.freq_q20 = u32();
        }
        break;
      }
      case Type::hello_reply:
        m.hello_reply = HelloReply{static_cast<std::uint16_t>(in(1, 0xFFFF)),
                                   u8(),
                                   u8(),
                                   u8(),
                                   static_cast<Board>(in(0, 2)),
                                   static_cast<std::uint32_t>(in(1, 0xFFFFFFFF)),
                                   static_cast<std::uint8_t>(in(1, 255)),
                                   u16(),
                                   u8(),
                                   static_cast<std::uint8_t>(in(0, kKnownBoardFlags))};
        break;
      case Type::sync_reply: m.sync_reply = SyncReply{u64(), u64(), u32()}; break;
      case Type::status: {
        Status& s = m.status;
        s.tick = u64();
        s.queue_free = u16();
        s.last_seq = u16();
        s.late = u32();
        s.stolen = u32();
        s.rejected = u32();
        s.started = u32();
        s.faults = static_cast<std::uint32_t>(bits(8));
        s.state = static_cast<State>(in(0, 4));
        s.active_voices = u8();
        s.output = real(-1, 1);
        s.force_n = real(-100, 100);
        s.grip_known = static_cast<std::uint8_t>(in(0, 1));
        for (float& g : s.grip_m)
          g = s.grip_known != 0 ? real(-static_cast<double>(kGripRangeM), static_cast<double>(kGripRangeM)) : 0.0f;
        break;
      }
      case Type::started: {
        Started& b = m.started;
        b.count = static_cast<std::uint8_t>(in(1, kNotesPerBatch));
        for (std::size_t i = 0; i < b.count; ++i)
          b.entries[i] = StartedEntry{u16(), static_cast<std::uint8_t>(in(0, 4)), u32(), u32()};
        break;
      }
      case Type::error: m.error = Error{static_cast<ErrorCode>(in(1, 9)), u16(), u8()}; break;
    }
    return m;
  }

 private:
  std::mt19937_64 rng_;
};

TEST(Protocol, RoundTripsRandomMessagesOfEveryType) {
  Gen gen(20240601);
  for (Type t : kAllTypes) {
    for (int i = 0; i < 2000; ++i) {
      const Message m = gen.message(t);
      ASSERT_EQ(validate(m), ErrorCode::none) << name(t);
      const Bytes b = encoded(m);
      EXPECT_EQ(b[0], static_cast<std::uint8_t>(t));
      EXPECT_EQ(b[1] | (b[2] << 8), m.seq);
      Message back;
      ASSERT_EQ(decode_bytes(b, back), ErrorCode::none) << name(t) << " #" << i;
      ASSERT_TRUE(back == m) << name(t) << " #" << i;
      for (std::size_t k = documented_end(m); k < kReportSize; ++k) ASSERT_EQ(b[k], 0) << name(t) << " byte " << k;
    }
  }
}

// Message equality must notice every wire byte (otherwise the round-trip test above proves nothing).
TEST(Protocol, EqualityNoticesEveryPayloadByte) {
  Gen gen(7);
  for (Type t : kAllTypes) {
    const Message m = gen.message(t);
    const Bytes b = encoded(m);
    int compared = 0;
    for (std::size_t k = 1; k < documented_end(m); ++k) {
      for (int bit = 0; bit < 8; ++bit) {
        Bytes c = b;
        c[k] = static_cast<std::uint8_t>(c[k] ^ (1u << bit));
        Message other;
        if (decode_bytes(c, other) != ErrorCode::none) continue;
        ++compared;
        EXPECT_FALSE(other == m) << name(t) << " byte " << k << " bit " << bit;
      }
    }
    EXPECT_GT(compared, 0) << name(t);
  }
}

// ---- byte-exact layouts, expected bytes written from the documented offsets ----
TEST(Protocol, NotesLayoutIsByteExact) {
  Message m = make(Type::notes, 0x1234);
  m.notes.count = 2;
  m.notes.track = 7;
  m.notes.base_tick = 0x11223344;
  m.notes.notes[0] = CompactNote{0x05, 0x10, 0x0A0B0C, 250u << 20, 0xABCD};  // 250 Hz exactly in Q12.20
  m.notes.notes[1] = CompactNote{0xFF, 0x03, 0xFFFFFF, 0x89ABCDEF, 0xFFFF};
  Bytes want{};
  const std::uint8_t head[] = {0x03, 0x34, 0x12, 0x02, 0x07, 0x44, 0x33, 0x22, 0x11};
  const std::uint8_t note0[] = {0x05, 0x10, 0x0C, 0x0B, 0x0A, 0x00, 0x00, 0xA0, 0x0F, 0xCD, 0xAB};
  const std::uint8_t note1[] = {0xFF, 0x03, 0xFF, 0xFF, 0xFF, 0xEF, 0xCD, 0xAB, 0x89, 0xFF, 0xFF};
  std::memcpy(want.data(), head, sizeof head);
  std::memcpy(want.data() + 9, note0, sizeof note0);
  std::memcpy(want.data() + 20, note1, sizeof note1);
  EXPECT_EQ(encoded(m), want);
  Message back;
  ASSERT_EQ(decode_bytes(want, back), ErrorCode::none);
  EXPECT_TRUE(back == m);
  EXPECT_EQ(back.notes.notes[0].freq_q20 * (1.0 / (1 << 20)), 250.0);
}

TEST(Protocol, LiveLayoutIsByteExact) {
  Message m = make(Type::live, 0x0102);
  m.live.count = 2;
  m.live.track = 9;
  m.live.events[0] = LiveEvent{LiveOp::on, 0x3C, 0x11, 0x0A0B0C0D, 0xBEEF};
  m.live.events[1] = LiveEvent{LiveOp::bend, 0x7F, 0, 0x89ABCDEF, 0};
  Bytes want{};
  const std::uint8_t head[] = {0x09, 0x02, 0x01, 0x02, 0x09};
  const std::uint8_t on[] = {0x01, 0x3C, 0x11, 0x0D, 0x0C, 0x0B, 0x0A, 0xEF, 0xBE};
  const std::uint8_t bend[] = {0x03, 0x7F, 0x00, 0xEF, 0xCD, 0xAB, 0x89, 0x00, 0x00};
  std::memcpy(want.data(), head, sizeof head);
  std::memcpy(want.data() + 5, on, sizeof on);
  std::memcpy(want.data() + 14, bend, sizeof bend);
  EXPECT_EQ(encoded(m), want);
  Message back;
  ASSERT_EQ(decode_bytes(want, back), ErrorCode::none);
  EXPECT_TRUE(back == m);
}

TEST(Protocol, StatusLayoutIsByteExact) {
  Message m = make(Type::status, 0xBEEF);
  Status& s = m.status;
  s.tick = 0x0102030405060708;
  s.queue_free = 0x0A0B;
  s.last_seq = 0x0C0D;
  s.late = 0x11121314;
  s.stolen = 0x21222324;
  s.rejected = 0x31323334;
  s.started = 0x41424344;
  s.faults = fault_estop | fault_output_limit | fault_string_slack;  // 0x85
  s.state = State::playing;
  s.active_voices = 16;
  s.output = 0.5f;      // 0x3F000000
  s.force_n = -2.0f;    // 0xC0000000
  s.grip_m[0] = 0.25f;  // 0x3E800000
  s.grip_m[1] = -1.5f;  // 0xBFC00000
  s.grip_m[2] = 2.0f;   // 0x40000000
  s.grip_known = 1;
  const std::uint8_t bytes[] = {
      0x83, 0xEF, 0xBE,                                // type, seq
      0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01,  // 3–10 tick
      0x0B, 0x0A, 0x0D, 0x0C,                          // 11–12 queue free, 13–14 last seq
      0x14, 0x13, 0x12, 0x11, 0x24, 0x23, 0x22, 0x21,  // 15–18 late, 19–22 stolen
      0x34, 0x33, 0x32, 0x31, 0x44, 0x43, 0x42, 0x41,  // 23–26 rejected, 27–30 started
      0x85, 0x00, 0x00, 0x00,                          // 31–34 faults
      0x01, 0x10,                                      // 35 state, 36 voices
      0x00, 0x00, 0x00, 0x3F, 0x00, 0x00, 0x00, 0xC0,  // 37–40 output, 41–44 force
      0x00, 0x00, 0x80, 0x3E, 0x00, 0x00, 0xC0, 0xBF,  // 45–48 grip x, 49–52 grip y
      0x00, 0x00, 0x00, 0x40, 0x01,                    // 53–56 grip z, 57 grip known
  };
  static_assert(sizeof bytes == 58);
  Bytes want{};
  std::memcpy(want.data(), bytes, sizeof bytes);
  EXPECT_EQ(encoded(m), want);
  Message back;
  ASSERT_EQ(decode_bytes(want, back), ErrorCode::none);
  EXPECT_TRUE(back == m);
}

TEST(Protocol, LongNoteAndSettingsLayoutsAreByteExact) {
  Message n = make(Type::long_note, 1);
  n.long_note = LongNote{9, 17, 0x0102030405060708, 0xA1A2A3A4, 0xB1B2B3B4, 0xC1C2};
  const std::uint8_t nb[] = {0x04, 0x01, 0x00, 9,    17,   0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02,
                             0x01, 0xA4, 0xA3, 0xA2, 0xA1, 0xB4, 0xB3, 0xB2, 0xB1, 0xC2, 0xC1};
  Bytes want{};
  std::memcpy(want.data(), nb, sizeof nb);
  EXPECT_EQ(encoded(n), want);

  Message s = make(Type::settings, 2);
  s.settings = Settings{PolicyCode::latest, 0.5f, 2.0f, {0.0f, 0.0f, -1.0f}, 0.25f, 300, 0x1234, 0.25f, 6.0f};
  const std::uint8_t sb[] = {0x06, 0x02, 0x00, 0x02, 0x00, 0x00, 0x00, 0x3F,                          // gain 0.5
                             0x00, 0x00, 0x00, 0x40,                                                  // peak 2.0
                             0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0xBF,  // 0,0,-1
                             0x00, 0x00, 0x80, 0x3E,                                                  // end fade 0.25
                             0x2C, 0x01, 0x34, 0x12,                           // watchdog 300, ramp-in 0x1234
                             0x00, 0x00, 0x80, 0x3E, 0x00, 0x00, 0xC0, 0x40};  // t_min 0.25, t_max 6
  want = Bytes{};
  std::memcpy(want.data(), sb, sizeof sb);
  EXPECT_EQ(encoded(s), want);
}

// ---- padding ----
TEST(Protocol, EverySingleBytePaddingCorruptionIsDetected) {
  Gen gen(99);
  int checked = 0;
  for (Type t : kAllTypes) {
    const int variants = (t == Type::notes || t == Type::started) ? static_cast<int>(kNotesPerBatch) : 1;
    for (int v = 1; v <= variants; ++v) {
      Message m = gen.message(t);
      while ((t == Type::notes && m.notes.count != v) || (t == Type::started && m.started.count != v))
        m = gen.message(t);
      const Bytes b = encoded(m);
      for (std::size_t k = documented_end(m); k < kReportSize; ++k) {
        for (int value = 1; value < 256; ++value) {
          Bytes c = b;
          c[k] = static_cast<std::uint8_t>(value);
          Message out;
          ASSERT_EQ(decode_bytes(c, out), ErrorCode::nonzero_padding) << name(t) << " byte " << k << " = " << value;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 100000);
}

// ---- range checks: every field, both through encode (validate) and through decode of mutated bytes ----
struct BadField {
  std::string what;
  Type type;
  std::size_t offset;               // where the field lives (docs/protocol.md)
  std::vector<std::uint8_t> bytes;  // its out-of-range value on the wire (empty: not expressible in bytes)
  std::function<void(Message&)> mutate;
  ErrorCode expect;
};

// A valid message of each type with known contents to mutate.
Message base(Type t) {
  Message m = make(t, 42);
  if (t == Type::notes) {
    m.notes.count = 3;
    for (auto& n : m.notes.notes) n = CompactNote{1, 2, 100, 150u << 20, 30000};
  } else if (t == Type::started) {
    m.started.count = 2;
  } else if (t == Type::live) {
    m.live.count = 3;
    m.live.events[0] = LiveEvent{LiveOp::on, 60, 2, 440u << 20, 40000};
    m.live.events[1] = LiveEvent{LiveOp::bend, 60, 0, 450u << 20, 0};
    m.live.events[2] = LiveEvent{LiveOp::off, 60, 0, 0, 0};
  } else if (t == Type::error) {
    m.error.code = ErrorCode::bad_value;
  }
  return m;
}

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

std::vector<BadField> bad_fields() {
  using E = ErrorCode;
  std::vector<BadField> v;
  auto add = [&](std::string what, Type t, std::size_t off, std::vector<std::uint8_t> b,
                 std::function<void(Message&)> mut, E e) {
    v.push_back({what, t, off, b, mut, e});
  };

  add(
      "hello version 0", Type::hello, 3, le(0, 2), [](Message& m) { m.hello.protocol_version = 0; }, E::bad_value);

  for (int c : {0, 6, 255})
    add(
        "notes count " + std::to_string(c), Type::notes, 3, le(c, 1),
        [c](Message& m) { m.notes.count = static_cast<std::uint8_t>(c); }, E::bad_length_field);
  add(
      "note 0 preset 32", Type::notes, 10, le(32, 1), [](Message& m) { m.notes.notes[0].preset = 32; }, E::bad_slot);
  add(
      "note 2 preset 200", Type::notes, 9 + 22 + 1, le(200, 1), [](Message& m) { m.notes.notes[2].preset = 200; },
      E::bad_slot);
  add(
      "note 1 duration 0", Type::notes, 9 + 11 + 2, le(0, 3), [](Message& m) { m.notes.notes[1].duration_ticks = 0; },
      E::bad_value);
  add(
      "note duration 2^24", Type::notes, 0, {}, [](Message& m) { m.notes.notes[0].duration_ticks = 1u << 24; },
      E::bad_value);

  add(
      "long preset 32", Type::long_note, 4, le(32, 1), [](Message& m) { m.long_note.preset = 32; }, E::bad_slot);
  add(
      "long duration 0", Type::long_note, 13, le(0, 4), [](Message& m) { m.long_note.duration_ticks = 0; },
      E::bad_value);

  for (int s : {0, 10, 15, 32, 255})
    add(
        "preset slot " + std::to_string(s), Type::preset, 3, le(s, 1),
        [s](Message& m) { m.preset.slot = static_cast<std::uint8_t>(s); }, E::bad_slot);
  add(
      "preset shape 3", Type::preset, 4, le(3, 1),
      [](Message& m) { m.preset.adsr.shape = static_cast<envelope::Shape>(3); }, E::bad_value);
  const struct {
    const char* field;
    std::size_t off;
    float envelope::Adsr::*member;
    std::vector<float> bad;
  } adsr_fields[] = {{"attack", 5, &envelope::Adsr::attack_ms, {-1.0f, kNaN, kInf, 1.1e7f}},
                     {"decay", 9, &envelope::Adsr::decay_ms, {-0.001f, kNaN, -kInf, 2e7f}},
                     {"release", 13, &envelope::Adsr::release_ms, {-5.0f, kNaN, kInf, 1e8f}},
                     {"sustain", 17, &envelope::Adsr::sustain, {-0.01f, 1.01f, kNaN, kInf}},
                     {"final", 21, &envelope::Adsr::final_ratio, {-0.01f, 1.5f, kNaN, -kInf}}};
  for (const auto& a : adsr_fields)
    for (float x : a.bad)
      add(
          std::string("preset ") + a.field + " " + std::to_string(x), Type::preset, a.off, le_f32(x),
          [member = a.member, x](Message& m) { m.preset.adsr.*member = x; }, E::bad_value);

  add(
      "policy 3", Type::settings, 3, le(3, 1), [](Message& m) { m.settings.policy = static_cast<PolicyCode>(3); },
      E::bad_value);
  const struct {
    const char* field;
    std::size_t off;
    float Settings::*member;
    std::vector<float> bad;
  } settings_fields[] = {{"gain", 4, &Settings::gain, {-0.01f, 1.01f, kNaN, kInf}},
                         {"peak force", 8, &Settings::peak_force_n, {0.0f, -1.0f, 20.01f, kNaN, kInf}},
                         {"end fade", 24, &Settings::end_fade_ms, {-1.0f, 1000.5f, kNaN, kInf}},
                         {"t_min", 32, &Settings::t_min_n, {-0.1f, 6.0f, 7.0f, kNaN, -kInf}},
                         {"t_max", 36, &Settings::t_max_n, {0.3f, 0.1f, 20.01f, kNaN, kInf}}};
  for (const auto& s : settings_fields)
    for (float x : s.bad)
      add(
          std::string("settings ") + s.field + " " + std::to_string(x), Type::settings, s.off, le_f32(x),
          [member = s.member, x](Message& m) { m.settings.*member = x; }, E::bad_value);
  const std::array<float, 3> bad_directions[] = {{0, 0, 0},    {0, 1.0015f, 0}, {0, 0.9985f, 0},   {kNaN, 1, 0},
                                                 {0, kInf, 0}, {1, 1, 0},       {0.6f, 0.6f, 0.6f}};
  for (const auto& d : bad_directions) {
    std::vector<std::uint8_t> b;
    for (float c : d)
      for (std::uint8_t x : le_f32(c)) b.push_back(x);
    add(
        "direction " + std::to_string(d[0]) + "," + std::to_string(d[1]) + "," + std::to_string(d[2]), Type::settings,
        12, b, [d](Message& m) { std::copy(d.begin(), d.end(), m.settings.direction); }, E::bad_value);
  }
  add(
      "watchdog 9", Type::settings, 28, le(9, 2), [](Message& m) { m.settings.watchdog_ms = 9; }, E::bad_value);
  add(
      "watchdog 0", Type::settings, 28, le(0, 2), [](Message& m) { m.settings.watchdog_ms = 0; }, E::bad_value);

  add(
      "transport op 4", Type::transport, 3, le(4, 1), [](Message& m) { m.transport.op = static_cast<TransportOp>(4); },
      E::bad_value);
  add(
      "play with a tick", Type::transport, 4, le(5, 8), [](Message& m) { m.transport.tick = 5; }, E::bad_value);

  for (int c : {0, 6, 255})
    add(
        "live count " + std::to_string(c), Type::live, 3, le(c, 1),
        [c](Message& m) { m.live.count = static_cast<std::uint8_t>(c); }, E::bad_length_field);
  for (int op : {0, 4, 255})
    add(
        "live op " + std::to_string(op), Type::live, 5 + 9, le(op, 1),
        [op](Message& m) { m.live.events[1].op = static_cast<LiveOp>(op); }, E::bad_value);
  add(
      "live on preset 32", Type::live, 7, le(32, 1), [](Message& m) { m.live.events[0].preset = 32; }, E::bad_slot);
  add(
      "live bend with a preset", Type::live, 5 + 9 + 2, le(1, 1), [](Message& m) { m.live.events[1].preset = 1; },
      E::bad_value);
  add(
      "live bend with an amplitude", Type::live, 5 + 9 + 7, le(1, 2), [](Message& m) { m.live.events[1].amp_q16 = 1; },
      E::bad_value);
  add(
      "live off with a frequency", Type::live, 5 + 18 + 3, le(1, 4), [](Message& m) { m.live.events[2].freq_q20 = 1; },
      E::bad_value);
  add(
      "live off with a preset", Type::live, 5 + 18 + 2, le(3, 1), [](Message& m) { m.live.events[2].preset = 3; },
      E::bad_value);
  add(
      "live off with an amplitude", Type::live, 5 + 18 + 7, le(9, 2), [](Message& m) { m.live.events[2].amp_q16 = 9; },
      E::bad_value);

  add(
      "reply version 0", Type::hello_reply, 3, le(0, 2), [](Message& m) { m.hello_reply.protocol_version = 0; },
      E::bad_value);
  add(
      "board 3", Type::hello_reply, 8, le(3, 1), [](Message& m) { m.hello_reply.board = static_cast<Board>(3); },
      E::bad_value);
  add(
      "tick_hz 0", Type::hello_reply, 9, le(0, 4), [](Message& m) { m.hello_reply.tick_hz = 0; }, E::bad_value);
  add(
      "voices 0", Type::hello_reply, 13, le(0, 1), [](Message& m) { m.hello_reply.voices = 0; }, E::bad_value);
  add(
      "board flag 0x10", Type::hello_reply, 17, le(0x10, 1), [](Message& m) { m.hello_reply.board_flags = 0x10; },
      E::bad_value);

  add(
      "state 5", Type::status, 35, le(5, 1), [](Message& m) { m.status.state = static_cast<State>(5); }, E::bad_value);
  for (std::uint32_t bit : {8u, 31u})
    add(
        "fault bit " + std::to_string(bit), Type::status, 31, le(std::uint64_t{1} << bit, 4),
        [bit](Message& m) { m.status.faults = 1u << bit; }, E::bad_value);
  for (float x : {1.01f, -1.5f, kNaN, kInf})
    add(
        "output " + std::to_string(x), Type::status, 37, le_f32(x), [x](Message& m) { m.status.output = x; },
        E::bad_value);
  for (float x : {kNaN, kInf, -kInf})
    add(
        "force " + std::to_string(x), Type::status, 41, le_f32(x), [x](Message& m) { m.status.force_n = x; },
        E::bad_value);

  // The grip: a position only when known, finite and within the range; "known" is 0 or 1.
  add(
      "grip known 2", Type::status, 57, le(2, 1), [](Message& m) { m.status.grip_known = 2; }, E::bad_value);
  add(
      "grip position while not known", Type::status, 45, le_f32(0.1f), [](Message& m) { m.status.grip_m[0] = 0.1f; },
      E::bad_value);
  for (float x : {kNaN, kInf, -kInf, 4.01f, -5.0f}) {
    std::vector<std::uint8_t> b;  // bytes 45–57: x = the bad value, y = z = 0, known = 1
    for (std::uint8_t c : le_f32(x)) b.push_back(c);
    b.insert(b.end(), 8, 0);
    b.push_back(1);
    add(
        "grip x " + std::to_string(x), Type::status, 45, b,
        [x](Message& m) {
          m.status.grip_m[0] = x;
          m.status.grip_known = 1;
        },
        E::bad_value);
  }

  for (int c : {0, 6, 200})
    add(
        "started count " + std::to_string(c), Type::started, 3, le(c, 1),
        [c](Message& m) { m.started.count = static_cast<std::uint8_t>(c); }, E::bad_length_field);
  add(
      "started index 5", Type::started, 4 + 11 + 2, le(5, 1), [](Message& m) { m.started.entries[1].index = 5; },
      E::bad_value);

  add(
      "error code none", Type::error, 3, le(0, 1), [](Message& m) { m.error.code = ErrorCode::none; }, E::bad_value);
  add(
      "error code 10", Type::error, 3, le(10, 1), [](Message& m) { m.error.code = static_cast<ErrorCode>(10); },
      E::bad_value);
  return v;
}

TEST(Protocol, EveryOutOfRangeFieldIsRejectedWithItsCode) {
  for (const BadField& c : bad_fields()) {
    SCOPED_TRACE(c.what);
    const Message good = base(c.type);
    ASSERT_EQ(validate(good), ErrorCode::none);

    Message bad = good;
    c.mutate(bad);
    EXPECT_EQ(validate(bad), c.expect);
    Report r;
    std::memset(r, 0xAA, sizeof r);
    EXPECT_FALSE(encode(bad, r));
    for (std::uint8_t b : r) ASSERT_EQ(b, 0) << "a refused encode zero-fills";

    if (c.bytes.empty()) continue;
    Bytes wire = encoded(good);
    ASSERT_LE(c.offset + c.bytes.size(), kReportSize);
    std::copy(c.bytes.begin(), c.bytes.end(), wire.begin() + static_cast<std::ptrdiff_t>(c.offset));
    Message out;
    EXPECT_EQ(decode_bytes(wire, out), c.expect);
  }
}

// The edges of every range are accepted (and survive the trip).
TEST(Protocol, RangeEdgesAreAccepted) {
  auto check = [](Type t, const std::function<void(Message&)>& edit, const char* what) {
    Message m = base(t);
    edit(m);
    EXPECT_EQ(validate(m), ErrorCode::none) << what;
    Message back;
    EXPECT_EQ(decode_bytes(encoded(m), back), ErrorCode::none) << what;
    EXPECT_TRUE(back == m) << what;
  };
  check(
      Type::notes,
      [](Message& m) {
        m.notes.count = 5;
        m.notes.notes[4].duration_ticks = kMaxCompactDuration;
      },
      "u24 max");
  check(
      Type::notes,
      [](Message& m) {
        m.notes.count = 1;
        m.notes.notes[0].preset = 31;
        m.notes.notes[0].duration_ticks = 1;
      },
      "slot 31, 1 tick");
  check(
      Type::long_note,
      [](Message& m) {
        m.long_note.duration_ticks = 0xFFFFFFFF;
        m.long_note.start_tick = ~0ull;
      },
      "u32 max");
  check(
      Type::preset, [](Message& m) { m.preset.slot = 16; }, "slot 16");
  check(
      Type::preset,
      [](Message& m) {
        m.preset.slot = 31;
        m.preset.adsr = {1e7f, 0, 1e7f, 0, 0, envelope::Shape::damped};
      },
      "slot 31, 1e7 ms, zero levels");
  check(
      Type::settings,
      [](Message& m) {
        m.settings.gain = 0;
        m.settings.end_fade_ms = 0;
        m.settings.t_min_n = 0;
        m.settings.watchdog_ms = 10;
      },
      "lower edges");
  check(
      Type::settings,
      [](Message& m) {
        m.settings.gain = 1;
        m.settings.peak_force_n = 20;
        m.settings.end_fade_ms = 1000;
        m.settings.t_max_n = 20;
        m.settings.ramp_in_ms = 0;
      },
      "upper edges");
  check(
      Type::settings,
      [](Message& m) {
        m.settings.direction[0] = 0;
        m.settings.direction[1] = 1.0009f;
        m.settings.direction[2] = 0;
      },
      "|d| = 1.0009");
  check(
      Type::settings,
      [](Message& m) {
        m.settings.direction[0] = 0.6f;
        m.settings.direction[1] = -0.8f;
        m.settings.direction[2] = 0;
      },
      "(0.6,-0.8,0)");
  check(
      Type::status,
      [](Message& m) {
        m.status.output = -1;
        m.status.faults = kKnownFaults;
        m.status.state = State::fault;
      },
      "output -1, all faults");
  check(
      Type::status,
      [](Message& m) {
        m.status.output = 1;
        m.status.force_n = -1e30f;
      },
      "output 1");
  check(
      Type::status,
      [](Message& m) {
        m.status.grip_known = 1;
        m.status.grip_m[0] = kGripRangeM;
        m.status.grip_m[2] = -kGripRangeM;
      },
      "grip at ±range");
  check(
      Type::transport,
      [](Message& m) {
        m.transport.op = TransportOp::seek;
        m.transport.tick = ~0ull;
      },
      "seek anywhere");
  check(
      Type::error,
      [](Message& m) {
        m.error.code = ErrorCode::bad_slot;
        m.error.type = 0xFF;
      },
      "last code");
}

// Notes of hours: a compact note holds 16,777,215 ticks (4.66 h at 1 kHz); longer ones need a LongNote.
TEST(Protocol, TenHourNoteNeedsALongNote) {
  const std::uint32_t ten_hours_at_1khz = 10u * 3600u * 1000u;
  Message compact = base(Type::notes);
  compact.notes.notes[0].duration_ticks = ten_hours_at_1khz;
  EXPECT_EQ(validate(compact), ErrorCode::bad_value);
  Message long_note = base(Type::long_note);
  long_note.long_note.duration_ticks = ten_hours_at_1khz;
  Message back;
  ASSERT_EQ(decode_bytes(encoded(long_note), back), ErrorCode::none);
  EXPECT_EQ(back.long_note.duration_ticks, ten_hours_at_1khz);
}

// ---- arbitrary input ----
TEST(Protocol, MillionRandomReportsDecodeSafelyAndReencodeExactly) {
  Gen gen(123456789);
  std::mt19937_64 rng(987654321);
  std::map<Type, int> accepted;
  int successes = 0;
  for (int i = 0; i < 1'000'000; ++i) {
    Bytes b{};
    switch (i % 3) {
      case 0:  // uniformly random bytes
        for (auto& x : b) x = static_cast<std::uint8_t>(rng());
        break;
      case 1: {  // a known type, random payload of random length, zero tail
        b[0] = static_cast<std::uint8_t>(kAllTypes[rng() % std::size(kAllTypes)]);
        const std::size_t len = 1 + rng() % (kReportSize - 1);
        for (std::size_t k = 1; k <= len && k < kReportSize; ++k) b[k] = static_cast<std::uint8_t>(rng());
        break;
      }
      default: {  // a valid report with 1–3 random bytes overwritten
        b = encoded(gen.message(kAllTypes[rng() % std::size(kAllTypes)]));
        for (int n = 1 + static_cast<int>(rng() % 3); n > 0; --n)
          b[rng() % kReportSize] = static_cast<std::uint8_t>(rng());
        break;
      }
    }
    Message m;
    const ErrorCode e = decode_bytes(b, m);
    if (e != ErrorCode::none) {
      ASSERT_NE(e, ErrorCode::wrong_direction);  // decode never judges direction
      continue;
    }
    ++successes;
    ++accepted[m.type];
    Bytes again{};
    ASSERT_TRUE(encode(m, *reinterpret_cast<Report*>(again.data())));
    ASSERT_EQ(again, b) << "decode then encode must reproduce the input (input #" << i << ")";
  }
  // The mutated-valid third keeps most reports decodable: every type must have been exercised.
  for (Type t : kAllTypes) EXPECT_GT(accepted[t], 300) << name(t);
  RecordProperty("successful_decodes", successes);
  std::printf("1e6 inputs: %d decoded (each re-encoded byte-identically)\n", successes);
}

TEST(Protocol, AllZeroAndAllFFReports) {
  Bytes zeros{}, ffs{};
  ffs.fill(0xFF);
  Message m;
  EXPECT_EQ(decode_bytes(zeros, m), ErrorCode::unknown_type);
  EXPECT_EQ(decode_bytes(ffs, m), ErrorCode::unknown_type);

  // A known type byte followed by all zeros / all 0xFF. Field checks come before the padding check.
  using E = ErrorCode;
  const struct {
    Type t;
    E zeros, ffs;
  } cases[] = {
      {Type::hello, E::bad_value, E::nonzero_padding},          // version 0 / version 0xFFFF then padding
      {Type::sync, E::none, E::nonzero_padding},                // any time; padding
      {Type::notes, E::bad_length_field, E::bad_length_field},  // count 0 / 255
      {Type::long_note, E::bad_value, E::bad_slot},             // duration 0 / preset 255
      {Type::preset, E::bad_slot, E::bad_slot},                 // slot 0 / 255
      {Type::settings, E::bad_value, E::bad_value},             // gain… / policy 255
      {Type::transport, E::none, E::bad_value},                 // play at 0 / op 255
      {Type::estop, E::none, E::nonzero_padding},
      {Type::live, E::bad_length_field, E::bad_length_field},  // count 0 / 255
      {Type::hello_reply, E::bad_value, E::bad_value},         // version 0 / board 255
      {Type::sync_reply, E::none, E::nonzero_padding},
      {Type::status, E::none, E::bad_value},  // idle, output 0 / state 255
      {Type::started, E::bad_length_field, E::bad_length_field},
      {Type::error, E::bad_value, E::bad_value},  // code none / 255
  };
  for (const auto& c : cases) {
    Bytes z = zeros, f = ffs;
    z[0] = f[0] = static_cast<std::uint8_t>(c.t);
    EXPECT_EQ(decode_bytes(z, m), c.zeros) << name(c.t) << " + zeros";
    EXPECT_EQ(decode_bytes(f, m), c.ffs) << name(c.t) << " + 0xFF";
  }
}

TEST(Protocol, UnknownTypesAreRejectedEverywhere) {
  int known = 0;
  for (int t = 0; t < 256; ++t) {
    Bytes b{};
    b[0] = static_cast<std::uint8_t>(t);
    Message m;
    const bool listed =
        std::find(std::begin(kAllTypes), std::end(kAllTypes), static_cast<Type>(t)) != std::end(kAllTypes);
    EXPECT_EQ(is_known_type(static_cast<std::uint8_t>(t)), listed) << t;
    if (listed) {
      ++known;
      continue;
    }
    EXPECT_EQ(decode_bytes(b, m), ErrorCode::unknown_type) << t;
    Message odd;
    odd.type = static_cast<Type>(t);
    Report r;
    EXPECT_FALSE(encode(odd, r)) << t;
  }
  EXPECT_EQ(known, 14);
}

// A serial frame carries a report without its trailing zeros, except a greeting, which goes whole (a
// peer of an older version reads all 64 bytes).
TEST(Protocol, WireSizeLeavesOutPaddingButNotFromGreetings) {
  for (const Type t : {Type::hello, Type::hello_reply}) {
    Report r;
    ASSERT_TRUE(encode(make(t, 1), r));
    EXPECT_EQ(wire_size(r), kReportSize) << name(t);
  }
  Message live = make(Type::live, 0x0102);
  live.live.count = 1;
  live.live.events[0] = {LiveOp::on, 60, 0, 440u << 20, 0x8000};
  Report r;
  ASSERT_TRUE(encode(live, r));
  const std::size_t n = wire_size(r);
  EXPECT_LT(n, 24u) << "one event: a few bytes of header and nine of event";
  EXPECT_NE(r[n - 1], 0);
  for (std::size_t i = n; i < kReportSize; ++i) EXPECT_EQ(r[i], 0) << "byte " << i;
  Report estop;
  ASSERT_TRUE(encode(make(Type::estop, 0), estop));
  EXPECT_GE(wire_size(estop), 1u);
}

TEST(Protocol, DirectionNamesAndBuilders) {
  for (Type t : kAllTypes) {
    EXPECT_EQ(is_host_to_device(t), static_cast<std::uint8_t>(t) <= 0x3F) << name(t);
    const Message m = make(t, 77);
    EXPECT_EQ(m.type, t);
    EXPECT_EQ(m.seq, 77);
    EXPECT_STRNE(name(t), "unknown_type");
  }
  EXPECT_TRUE(is_host_to_device(Type::notes));
  EXPECT_FALSE(is_host_to_device(Type::status));
  EXPECT_STREQ(name(ErrorCode::nonzero_padding), "nonzero_padding");
  EXPECT_STREQ(name(ErrorCode::bad_slot), "bad_slot");
  EXPECT_STREQ(name(ErrorCode::not_playing), "not_playing");
  EXPECT_STREQ(name(Type::long_note), "long_note");
  EXPECT_STREQ(name(Type::live), "live");
}

}  // namespace
}  // namespace hmp::protocol
