#pragma once
// A minimal SoundFont 2.04 writer for tests: one looped mono sample and any number of presets
// (bank 0), each with its own instrument whose one zone plays the sample over all keys and velocities
// with the caller's volume envelope. Written from the SoundFont 2.04 specification: little-endian
// RIFF, every pdta list ending in its terminal record, bag and generator indices counted in order.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace hmp::test {

// A mono 16-bit sample with one loop [loop_start, loop_end) and its pitch (shdr fields).
struct Sf2Sample {
  int rate = 48000;
  std::vector<std::int16_t> data;  // without the 46 zero points the writer appends
  std::uint32_t loop_start = 0, loop_end = 0;
  std::uint8_t key = 60;       // byOriginalPitch
  std::int8_t correction = 0;  // chPitchCorrection, cents
  double freq_hz = 0;          // the loop's exact frequency (after rounding its length)
};

// A sine of `periods` whole periods as the loop, so that the loop is seamless. The loop length is
// rounded to whole frames (freq_hz is the exact result; 440 Hz × 11 periods at 48 kHz is exactly
// 1200 frames). The spec wants ≥ 8 valid points before the loop and after it and a loop of ≥ 32
// points: the sine simply runs on for 8 frames on both sides. Amplitude: half of full scale.
inline Sf2Sample sine_sample(int rate = 48000, double freq_hz = 440.0, int periods = 11) {
  Sf2Sample s;
  s.rate = rate;
  const auto loop = static_cast<std::uint32_t>(std::lround(periods * rate / freq_hz));
  if (loop < 32) throw std::invalid_argument("sine_sample: loop shorter than 32 frames");
  s.freq_hz = static_cast<double>(periods) * rate / loop;
  const double exact_key = 69.0 + 12.0 * std::log2(s.freq_hz / 440.0);
  s.key = static_cast<std::uint8_t>(std::clamp(std::lround(exact_key), 0L, 127L));
  // Cents to add on playback so that `key` sounds at its equal-tempered pitch (0 for 440 Hz).
  s.correction = static_cast<std::int8_t>(std::lround(100.0 * (s.key - exact_key)));
  constexpr std::uint32_t kGuard = 8;
  s.loop_start = kGuard;
  s.loop_end = kGuard + loop;  // first point after the loop; it equals the loop's first point
  const double pi = std::acos(-1.0);
  for (std::uint32_t i = 0; i < loop + 2 * kGuard; ++i) {
    const double phase = 2 * pi * periods * (static_cast<double>(i) - kGuard) / loop;
    s.data.push_back(static_cast<std::int16_t>(std::lround(16384.0 * std::sin(phase))));
  }
  return s;
}

// Envelope times in seconds; sustain as attenuation in centibels (0 = full level … 1440).
struct VolumeEnvelope {
  double delay_s = 0, attack_s = 0, hold_s = 0, decay_s = 0;
  double sustain_cb = 0;
  double release_s = 0;
};

struct Sf2Preset {
  std::uint16_t program = 0;  // bank is always 0
  std::string name;           // ≤ 19 characters are kept
  VolumeEnvelope env;
  double attenuation_cb = 0;  // initialAttenuation
};

// Seconds → absolute timecents, 1200·log2(s); 0 and anything under 1 ms give the spec's minimum
// −12000 (which also is the default), and 8000 (~100 s) is the maximum of attack/decay/release.
inline std::int16_t timecents(double seconds) {
  if (!(seconds > 0)) return -12000;
  const long tc = std::lround(1200.0 * std::log2(seconds));
  return static_cast<std::int16_t>(std::clamp(tc, -12000L, 8000L));
}
// What a timecent value in the file stands for, in seconds: 2^(tc/1200).
inline double timecent_seconds(std::int16_t tc) { return std::exp2(tc / 1200.0); }

namespace sf2_detail {
using Bytes = std::vector<std::uint8_t>;
inline void u8(Bytes& b, unsigned v) { b.push_back(static_cast<std::uint8_t>(v)); }
inline void u16(Bytes& b, unsigned v) { u8(b, v & 0xFF), u8(b, (v >> 8) & 0xFF); }
inline void u32(Bytes& b, std::uint32_t v) { u16(b, v & 0xFFFF), u16(b, v >> 16); }
inline void tag(Bytes& b, const char* id) { b.insert(b.end(), id, id + 4); }
// A fixed-size name field (achPresetName etc.): zero padded, always zero terminated.
inline void name20(Bytes& b, const std::string& s) {
  for (std::size_t i = 0; i < 20; ++i) u8(b, i < 19 && i < s.size() ? s[i] : 0);
}
// A chunk: id, size, data, and a pad byte when the size is odd (RIFF rule).
inline void chunk(Bytes& out, const char* id, const Bytes& data) {
  tag(out, id), u32(out, static_cast<std::uint32_t>(data.size()));
  out.insert(out.end(), data.begin(), data.end());
  if (data.size() % 2 != 0) u8(out, 0);
}
inline Bytes list(const char* type, const Bytes& body) {
  Bytes b;
  tag(b, type);
  b.insert(b.end(), body.begin(), body.end());
  return b;
}
// INFO strings: zero terminated, padded to an even length.
inline Bytes zstr(const std::string& s) {
  Bytes b(s.begin(), s.end());
  b.resize(s.size() % 2 == 0 ? s.size() + 2 : s.size() + 1, 0);
  return b;
}
// Generator operators used (spec §8.1.2).
enum Gen : unsigned {
  delayVolEnv = 33,
  attackVolEnv = 34,
  holdVolEnv = 35,
  decayVolEnv = 36,
  sustainVolEnv = 37,
  releaseVolEnv = 38,
  instrument = 41,
  keyRange = 43,
  velRange = 44,
  initialAttenuation = 48,
  sampleID = 53,
  sampleModes = 54,
};
inline void gen(Bytes& b, unsigned op, int amount) { u16(b, op), u16(b, static_cast<std::uint16_t>(amount)); }
inline void range(Bytes& b, unsigned op, unsigned lo, unsigned hi) { u16(b, op), u8(b, lo), u8(b, hi); }
inline void bag(Bytes& b, std::size_t gen_index) { u16(b, static_cast<unsigned>(gen_index)), u16(b, 0); }
}  // namespace sf2_detail

// The whole file in memory.
inline std::vector<std::uint8_t> build_sf2(const std::vector<Sf2Preset>& presets,
                                           const Sf2Sample& sample = sine_sample(),
                                           const std::string& bank_name = "hmp test bank") {
  using namespace sf2_detail;
  Bytes info, sdta, pdta;
  Bytes ifil;
  u16(ifil, 2), u16(ifil, 4);  // version 2.04
  chunk(info, "ifil", ifil);
  chunk(info, "isng", zstr("EMU8000"));
  chunk(info, "INAM", zstr(bank_name));

  Bytes smpl;  // the sample, then the 46 zero points the spec requires after every sample
  for (std::int16_t v : sample.data) u16(smpl, static_cast<std::uint16_t>(v));
  for (int i = 0; i < 46; ++i) u16(smpl, 0);
  chunk(sdta, "smpl", smpl);

  // Presets: one zone each (bag i), one generator each (gen i: instrument i, last in its zone).
  // Instruments: one zone each (bag i) of kGens generators, keyRange first and sampleID last.
  constexpr std::size_t kGens = 11;
  Bytes phdr, pbag, pmod, pgen, inst, ibag, imod, igen, shdr;
  const std::size_t n = presets.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Sf2Preset& p = presets[i];
    name20(phdr, p.name), u16(phdr, p.program), u16(phdr, 0);  // name, preset, bank
    u16(phdr, static_cast<unsigned>(i)), u32(phdr, 0), u32(phdr, 0), u32(phdr, 0);
    bag(pbag, i);
    gen(pgen, instrument, static_cast<int>(i));
    name20(inst, p.name), u16(inst, static_cast<unsigned>(i));
    bag(ibag, i * kGens);
    const VolumeEnvelope& e = p.env;
    range(igen, keyRange, 0, 127);
    range(igen, velRange, 0, 127);
    gen(igen, initialAttenuation, static_cast<int>(std::lround(p.attenuation_cb)));
    gen(igen, delayVolEnv, std::min<int>(timecents(e.delay_s), 5000));  // delay, hold: ≤ 5000
    gen(igen, attackVolEnv, timecents(e.attack_s));
    gen(igen, holdVolEnv, std::min<int>(timecents(e.hold_s), 5000));
    gen(igen, decayVolEnv, timecents(e.decay_s));
    gen(igen, sustainVolEnv, static_cast<int>(std::clamp(std::lround(e.sustain_cb), 0L, 1440L)));
    gen(igen, releaseVolEnv, timecents(e.release_s));
    gen(igen, sampleModes, 1);  // loop continuously, also during the release
    gen(igen, sampleID, 0);
  }
  // Terminal records: EOP/EOI point one past the last bag, the last bag one past the last generator;
  // the modulator lists hold only their terminal record.
  name20(phdr, "EOP"), u16(phdr, 0), u16(phdr, 0), u16(phdr, static_cast<unsigned>(n));
  u32(phdr, 0), u32(phdr, 0), u32(phdr, 0);
  bag(pbag, n);
  pmod.resize(10, 0);
  gen(pgen, 0, 0);
  name20(inst, "EOI"), u16(inst, static_cast<unsigned>(n));
  bag(ibag, n * kGens);
  imod.resize(10, 0);
  gen(igen, 0, 0);

  // The sample header, then EOS (all zero but its name).
  const auto end = static_cast<std::uint32_t>(sample.data.size());
  name20(shdr, "sine"), u32(shdr, 0), u32(shdr, end);  // start, end (one past the last point)
  u32(shdr, sample.loop_start), u32(shdr, sample.loop_end);
  u32(shdr, static_cast<std::uint32_t>(sample.rate)), u8(shdr, sample.key);
  u8(shdr, static_cast<std::uint8_t>(sample.correction)), u16(shdr, 0), u16(shdr, 1);  // link, mono
  name20(shdr, "EOS");
  shdr.resize(shdr.size() + 26, 0);

  const std::pair<const char*, const Bytes*> hydra[] = {{"phdr", &phdr}, {"pbag", &pbag}, {"pmod", &pmod},
                                                        {"pgen", &pgen}, {"inst", &inst}, {"ibag", &ibag},
                                                        {"imod", &imod}, {"igen", &igen}, {"shdr", &shdr}};
  for (const auto& [id, data] : hydra) chunk(pdta, id, *data);

  Bytes body;
  tag(body, "sfbk");
  chunk(body, "LIST", list("INFO", info));
  chunk(body, "LIST", list("sdta", sdta));
  chunk(body, "LIST", list("pdta", pdta));
  Bytes file;
  chunk(file, "RIFF", body);
  return file;
}

// Writes build_sf2(…) to `path`; throws std::runtime_error naming the path on failure.
inline void write_sf2(const std::string& path, const std::vector<Sf2Preset>& presets,
                      const Sf2Sample& sample = sine_sample()) {
  const std::vector<std::uint8_t> bytes = build_sf2(presets, sample);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out.flush()) throw std::runtime_error("cannot write SoundFont " + path);
}

}  // namespace hmp::test
