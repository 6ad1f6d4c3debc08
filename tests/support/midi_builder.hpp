#pragma once
// Tiny hand-written Standard MIDI File builder for the midi_* tests: every byte is spelled out by the test
// (deltas, statuses, lengths), so a test can also write what a correct writer never would.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace midi_test {

using Bytes = std::vector<std::uint8_t>;

inline void put_vlq(Bytes& b, std::uint32_t v) {
  std::uint8_t tmp[5];
  int n = 0;
  tmp[n++] = static_cast<std::uint8_t>(v & 0x7F);
  while ((v >>= 7) != 0) tmp[n++] = static_cast<std::uint8_t>(0x80 | (v & 0x7F));
  while (n > 0) b.push_back(tmp[--n]);
}

inline void put_be(Bytes& b, std::uint32_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

inline void append(Bytes& to, const Bytes& from) { to.insert(to.end(), from.begin(), from.end()); }

// Events of one track; each call takes the delta time before the event.
class Events {
 public:
  Events& raw(std::uint32_t delta, std::initializer_list<std::uint8_t> bytes) {
    put_vlq(data, delta);
    data.insert(data.end(), bytes);
    return *this;
  }
  Events& bytes(std::initializer_list<std::uint8_t> bytes) {  // no delta
    data.insert(data.end(), bytes);
    return *this;
  }
  Events& on(std::uint32_t delta, int ch, int key, int vel = 100) {
    return raw(delta, {u8(0x90 | ch), u8(key), u8(vel)});
  }
  Events& off(std::uint32_t delta, int ch, int key, int vel = 64) {
    return raw(delta, {u8(0x80 | ch), u8(key), u8(vel)});
  }
  Events& program(std::uint32_t delta, int ch, int program) { return raw(delta, {u8(0xC0 | ch), u8(program)}); }
  Events& meta(std::uint32_t delta, int type, const Bytes& body) {
    put_vlq(data, delta);
    data.push_back(0xFF);
    data.push_back(u8(type));
    put_vlq(data, static_cast<std::uint32_t>(body.size()));
    append(data, body);
    return *this;
  }
  Events& name(std::uint32_t delta, const std::string& text) {
    return meta(delta, 0x03, Bytes(text.begin(), text.end()));
  }
  Events& tempo(std::uint32_t delta, std::uint32_t us_per_quarter) {
    return meta(delta, 0x51, {u8(us_per_quarter >> 16), u8(us_per_quarter >> 8), u8(us_per_quarter)});
  }
  Events& end(std::uint32_t delta = 0) { return meta(delta, 0x2F, {}); }

  Bytes data;

 private:
  static std::uint8_t u8(int v) { return static_cast<std::uint8_t>(v); }
};

// A chunk with a 4-letter id; `declared` overrides the length field.
inline Bytes chunk(const char* id, const Bytes& body, long long declared = -1) {
  Bytes b(id, id + 4);
  put_be(b, declared < 0 ? static_cast<std::uint32_t>(body.size()) : static_cast<std::uint32_t>(declared), 4);
  append(b, body);
  return b;
}

inline Bytes header(int format, int ntrks, int division, std::uint32_t length = 6) {
  Bytes body;
  put_be(body, static_cast<std::uint32_t>(format), 2);
  put_be(body, static_cast<std::uint32_t>(ntrks), 2);
  put_be(body, static_cast<std::uint32_t>(division), 2);
  while (body.size() < length) body.push_back(0);  // extension bytes of a longer MThd
  return chunk("MThd", body, length);
}

inline Bytes smf(int format, int division, const std::vector<Events>& tracks) {
  Bytes b = header(format, static_cast<int>(tracks.size()), division);
  for (const Events& t : tracks) append(b, chunk("MTrk", t.data));
  return b;
}

// RIFF RMID wrapper around an SMF (optionally with another sub-chunk before `data`).
inline Bytes rmid(const Bytes& smf_bytes, const Bytes& chunk_before = {}) {
  Bytes body{'R', 'M', 'I', 'D'};
  append(body, chunk_before);
  Bytes data{'d', 'a', 't', 'a'};
  const auto n = static_cast<std::uint32_t>(smf_bytes.size());
  for (int i = 0; i < 4; ++i) data.push_back(static_cast<std::uint8_t>(n >> (8 * i)));  // little-endian
  append(data, smf_bytes);
  if (n % 2 != 0) data.push_back(0);
  append(body, data);
  Bytes b{'R', 'I', 'F', 'F'};
  const auto size = static_cast<std::uint32_t>(body.size());
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(size >> (8 * i)));
  append(b, body);
  return b;
}

}  // namespace midi_test
