#pragma once
// A minimal host for the firmware tests: builds host reports, numbers them by the session rules every host
// follows (transport::HostSession), hands them to the simulated device, and sorts what comes back by
// type. Written against the protocol API only, so the tests see the device exactly as a real host would.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "boards/sim/sim_device.hpp"
#include "host/transport/host_session.hpp"
#include "shared/protocol/protocol.hpp"
#include "shared/synth/engine.hpp"
#include "shared/synth/frequency.hpp"

namespace hmp::test {

namespace p = hmp::protocol;

struct Replies {
  std::vector<p::HelloReply> hellos;
  std::vector<p::SyncReply> syncs;
  std::vector<p::Status> statuses;
  std::vector<p::StartedEntry> started;
  std::vector<p::Error> errors;
  std::size_t started_reports = 0;
};

// A note as a test writes it: absolute start tick, frequency in Hz, amplitude in [0, 1].
struct TestNote {
  std::uint64_t start = 0;
  std::uint32_t duration = 100;
  double hz = 100.0;
  double amp = 0.5;
  std::uint8_t preset = static_cast<std::uint8_t>(envelope::Preset::square);
};

inline synth::Note to_synth(const TestNote& n) {
  synth::Note s;
  s.start_tick = n.start;
  s.duration_ticks = n.duration;
  s.freq_q20 = synth::freq_to_q20(n.hz);
  s.amp_q16 = synth::amp_to_q16(n.amp);
  s.preset = n.preset;
  return s;
}

class HostLink {
 public:
  explicit HostLink(sim::SimDevice& dev) : dev_(dev) {}

  // Numbers, encodes (must succeed: HostSession throws otherwise) and delivers one report; returns its seq.
  std::uint16_t send(p::Message m) {
    p::Report r;
    const std::uint16_t seq = session_.number(m, r);
    dev_.deliver(r);
    return seq;
  }
  std::uint16_t hello(std::uint16_t version = p::kProtocolVersion) {
    p::Message m = p::make(p::Type::hello, 0);
    m.hello.protocol_version = version;
    return send(m);
  }
  // One Hello numbered once and delivered `times` times, as transport::say_hello resends it to a board
  // that has not answered yet; `between` ticks run after each copy.
  std::uint16_t repeated_hello(int times, std::uint64_t between) {
    p::Message m = p::make(p::Type::hello, 0);
    m.hello.protocol_version = p::kProtocolVersion;
    m.seq = session_.take_seq();
    p::Report r;
    EXPECT_TRUE(p::encode(m, r));
    for (int i = 0; i < times; ++i) {
      dev_.deliver(r);
      dev_.advance(between);
    }
    return m.seq;
  }
  std::uint16_t sync(std::uint64_t host_us) {
    p::Message m = p::make(p::Type::sync, 0);
    m.sync.host_time_us = host_us;
    return send(m);
  }
  std::uint16_t settings(const p::Settings& s) {
    p::Message m = p::make(p::Type::settings, 0);
    m.settings = s;
    return send(m);
  }
  std::uint16_t transport(p::TransportOp op, std::uint64_t tick = 0) {
    p::Message m = p::make(p::Type::transport, 0);
    m.transport.op = op;
    m.transport.tick = tick;
    return send(m);
  }
  std::uint16_t play() { return transport(p::TransportOp::play); }
  // The usual opening of a test: Hello, exact_settings() (no ramp-in, gain 1: output comparable
  // with the engine sample for sample), Transport play.
  void open_exact();
  std::uint16_t estop() { return send(p::make(p::Type::estop, 0)); }
  std::uint16_t preset(std::uint8_t slot, const envelope::Adsr& adsr) {
    p::Message m = p::make(p::Type::preset, 0);
    m.preset.slot = slot;
    m.preset.adsr = adsr;
    return send(m);
  }
  // One Notes report (1–5 notes whose starts lie within base … base+255).
  std::uint16_t notes(const std::vector<TestNote>& batch, std::uint8_t track = 0) {
    p::Message m = p::make(p::Type::notes, 0);
    m.notes.count = static_cast<std::uint8_t>(batch.size());
    m.notes.track = track;
    std::uint64_t base = batch.empty() ? 0 : batch[0].start;
    for (const TestNote& n : batch) base = n.start < base ? n.start : base;
    m.notes.base_tick = static_cast<std::uint32_t>(base);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      EXPECT_LE(batch[i].start - base, 255u) << "test put notes too far apart into one batch";
      const synth::Note s = to_synth(batch[i]);
      m.notes.notes[i].offset = static_cast<std::uint8_t>(batch[i].start - base);
      m.notes.notes[i].preset = s.preset;
      m.notes.notes[i].duration_ticks = s.duration_ticks;
      m.notes.notes[i].freq_q20 = s.freq_q20;
      m.notes.notes[i].amp_q16 = s.amp_q16;
    }
    return send(m);
  }
  // Any number of notes, in reports of up to five.
  void all_notes(const std::vector<TestNote>& notes) {
    for (std::size_t i = 0; i < notes.size(); i += p::kNotesPerBatch) {
      const std::size_t end = i + p::kNotesPerBatch < notes.size() ? i + p::kNotesPerBatch : notes.size();
      this->notes(std::vector<TestNote>(notes.begin() + static_cast<std::ptrdiff_t>(i),
                                        notes.begin() + static_cast<std::ptrdiff_t>(end)));
    }
  }
  std::uint16_t long_note(const TestNote& n) {
    p::Message m = p::make(p::Type::long_note, 0);
    const synth::Note s = to_synth(n);
    m.long_note.start_tick = s.start_tick;
    m.long_note.duration_ticks = s.duration_ticks;
    m.long_note.freq_q20 = s.freq_q20;
    m.long_note.amp_q16 = s.amp_q16;
    m.long_note.preset = s.preset;
    return send(m);
  }

  // Every report the device sent since the last call, decoded (each must decode) and sorted by type.
  Replies collect() {
    Replies out;
    p::Report r;
    while (dev_.poll_report(r)) {
      p::Message m;
      const p::ErrorCode e = p::decode(r, m);
      EXPECT_EQ(e, p::ErrorCode::none) << "device sent an undecodable report";
      if (e != p::ErrorCode::none) continue;
      switch (m.type) {
        case p::Type::hello_reply: out.hellos.push_back(m.hello_reply); break;
        case p::Type::sync_reply: out.syncs.push_back(m.sync_reply); break;
        case p::Type::status:
          out.statuses.push_back(m.status);
          session_.on_status(m.status);
          break;
        case p::Type::error: out.errors.push_back(m.error); break;
        case p::Type::started:
          ++out.started_reports;
          for (std::uint8_t i = 0; i < m.started.count; ++i) out.started.push_back(m.started.entries[i]);
          break;
        default: ADD_FAILURE() << "device sent a host report type " << p::name(m.type);
      }
    }
    return out;
  }

  // The device's latest Status (runs ticks until one arrives).
  p::Status status() {
    for (int i = 0; i < 10000; ++i) {
      dev_.advance(1);
      const Replies r = collect();
      if (!r.statuses.empty()) return r.statuses.back();
    }
    ADD_FAILURE() << "no status report";
    return {};
  }

  // Runs `ticks` ticks like a live host: a Sync every 100 ms keeps the device's watchdog fed.
  // Returns the output of every tick.
  std::vector<float> run(std::size_t ticks) {
    const std::size_t chunk = dev_.core().tick_hz() / 10;
    std::vector<float> out(ticks);
    for (std::size_t done = 0; done < ticks;) {
      const std::size_t n = ticks - done < chunk ? ticks - done : chunk;
      dev_.advance(n, out.data() + done);
      done += n;
      if (done < ticks) sync(0);
    }
    return out;
  }

  std::uint16_t seq() const { return session_.last_sent(); }
  // Note reports the device will still accept, as of the Statuses collect() has seen.
  int credit() const { return session_.credit(); }

 private:
  sim::SimDevice& dev_;
  transport::HostSession session_;
};

// Settings that make the device output exactly the engine's sample (no ramp-in), for sample comparisons.
inline p::Settings exact_settings(p::PolicyCode policy = p::PolicyCode::sum) {
  p::Settings s;
  s.policy = policy;
  s.ramp_in_ms = 0;
  s.gain = 1.0f;
  return s;
}

inline void HostLink::open_exact() {
  hello();
  settings(exact_settings());
  play();
}

// The device's output equals the reference tick for tick from tick `first` (exactly: both run the same
// float arithmetic); a failure names the first tick that differs.
inline ::testing::AssertionResult same_output(const std::vector<float>& got, const std::vector<float>& want,
                                              std::uint64_t first) {
  if (got.size() < want.size()) {
    return ::testing::AssertionFailure() << "device gave " << got.size() << " samples, " << want.size() << " wanted";
  }
  for (std::size_t i = 0; i < want.size(); ++i) {
    if (got[i] != want[i]) {
      return ::testing::AssertionFailure() << "tick " << first + i << ": device " << got[i] << ", engine " << want[i];
    }
  }
  return ::testing::AssertionSuccess();
}

// The reference: the shared Engine driven directly, starting each note on its tick, one sample per tick
// for ticks first … first+count−1.
inline std::vector<float> reference_output(const std::vector<TestNote>& notes, std::uint64_t first, std::size_t count,
                                           std::uint32_t tick_hz, synth::Polyphony policy = synth::Polyphony::sum) {
  synth::SynthConfig cfg;
  cfg.tick_hz = tick_hz;
  synth::Engine engine(cfg);
  engine.set_polyphony(policy);
  std::vector<float> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    for (const TestNote& n : notes) {
      if (n.start == first + i) engine.start(to_synth(n));
    }
    out[i] = engine.tick();
  }
  return out;
}

}  // namespace hmp::test
