// 10^6 random, malformed and hostile reports (seeded, a few seconds): the device never crashes, its
// output never leaves the configured limit, every invalid report is counted and answered, and it still
// works afterwards. Which reports are invalid is decided here, from the protocol's decoder and the
// device contract in docs/firmware.md (not by asking the firmware).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/firmware/host_link.hpp"

namespace hmp::test {
namespace {

// Which reports the device must refuse as invalid, tracking uploaded presets and the version lock as it
// goes. (Refusals for lack of queue room depend on timing; the device counts those separately.)
class Oracle {
 public:
  explicit Oracle(std::uint32_t tick_hz) : tick_hz_(tick_hz) {
    for (std::uint8_t i = 0; i < envelope::kBuiltinCount; ++i) slot_used_[i] = true;
  }
  bool invalid(const p::Report& r) {
    p::Message m;
    if (p::decode(r, m) != p::ErrorCode::none) return true;
    if (!p::is_host_to_device(m.type)) return true;
    if (m.type == p::Type::hello) {
      locked_ = m.hello.protocol_version != p::kProtocolVersion;
      return locked_;
    }
    if (locked_ && m.type != p::Type::sync && m.type != p::Type::estop) return true;
    switch (m.type) {
      case p::Type::notes:
        for (std::uint8_t i = 0; i < m.notes.count; ++i)
          if (!playable(m.notes.notes[i].preset, m.notes.notes[i].freq_q20)) return true;
        return false;
      case p::Type::long_note: return !playable(m.long_note.preset, m.long_note.freq_q20);
      case p::Type::preset: slot_used_[m.preset.slot] = true; return false;
      default: return false;
    }
  }

 private:
  bool playable(std::uint8_t slot, std::uint32_t freq_q20) const {
    // 0 < f < tick_hz / 2, in Q12.20 Hz.
    const double hz = static_cast<double>(freq_q20) / 1048576.0;
    return slot_used_[slot] && hz > 0.0 && hz < static_cast<double>(tick_hz_) / 2.0;
  }
  std::uint32_t tick_hz_;
  bool locked_ = false;
  bool slot_used_[envelope::kSlotCount] = {};
};

class Generator {
 public:
  Generator(std::uint64_t seed, const sim::SimDevice& dev) : rng_(seed), dev_(dev) {}

  void next(p::Report& r) {
    const unsigned kind = pick(100);
    if (kind < 40) return random_bytes(r);
    p::Message m = valid_message();
    if (!p::encode(m, r)) return random_bytes(r);
    if (kind < 75) mutate(r);
  }

 private:
  unsigned pick(unsigned n) { return static_cast<unsigned>(rng_() % n); }
  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng_); }

  void random_bytes(p::Report& r) {
    for (std::size_t i = 0; i < p::kReportSize; i += 8) {
      const std::uint64_t v = rng_();
      for (std::size_t k = 0; k < 8; ++k) r[i + k] = static_cast<std::uint8_t>(v >> (8 * k));
    }
    if (pick(4) == 0) r[0] = static_cast<std::uint8_t>(1 + pick(8));  // a plausible type byte
    if (pick(4) == 0)  // mostly zero padding: gets further into the decoder
      for (std::size_t i = 3 + pick(40); i < p::kReportSize; ++i) r[i] = 0;
  }

  void mutate(p::Report& r) {
    for (unsigned n = 1 + pick(3); n > 0; --n) {
      const std::size_t at = pick(p::kReportSize);
      switch (pick(3)) {
        case 0: r[at] = static_cast<std::uint8_t>(r[at] ^ (1u << pick(8))); break;
        case 1: r[at] = static_cast<std::uint8_t>(rng_()); break;
        default: r[at] = 0xFF; break;
      }
    }
  }

  // Mostly a built-in preset; sometimes any slot, uploaded or empty.
  std::uint8_t slot() {
    return static_cast<std::uint8_t>(pick(4) == 0 ? pick(envelope::kSlotCount) : pick(envelope::kBuiltinCount));
  }

  std::uint32_t freq() {
    switch (pick(10)) {
      case 0: return static_cast<std::uint32_t>(rng_());  // anything, mostly above Nyquist
      case 1: return pick(2) == 0 ? 0u : static_cast<std::uint32_t>(dev_.core().tick_hz()) << 19;  // edges
      default: return synth::freq_to_q20(uniform(20.0f, 400.0f));
    }
  }

  // Mostly notes and play, so that the device really plays between the disruptive reports (hello,
  // pause, stop, seek flush everything; an estop latches until the next stop or hello).
  p::Message valid_message() {
    struct Weighted {
      p::Type type;
      unsigned weight;
    };
    static constexpr Weighted kMix[] = {{p::Type::notes, 400}, {p::Type::long_note, 40}, {p::Type::sync, 100},
                                        {p::Type::preset, 30}, {p::Type::settings, 20},  {p::Type::transport, 100},
                                        {p::Type::hello, 8},   {p::Type::estop, 1}};
    unsigned total = 0;
    for (const Weighted& w : kMix) total += w.weight;
    unsigned roll = pick(total);
    p::Type type = p::Type::sync;
    for (const Weighted& w : kMix) {
      if (roll < w.weight) {
        type = w.type;
        break;
      }
      roll -= w.weight;
    }
    const std::uint64_t now = dev_.tick();
    p::Message m = p::make(type, static_cast<std::uint16_t>(rng_()));
    switch (m.type) {
      case p::Type::hello:
        m.hello.protocol_version = pick(4) == 0 ? static_cast<std::uint16_t>(1 + pick(5)) : p::kProtocolVersion;
        break;
      case p::Type::sync: m.sync.host_time_us = rng_(); break;
      case p::Type::notes:
        m.notes.count = static_cast<std::uint8_t>(1 + pick(5));
        m.notes.track = static_cast<std::uint8_t>(rng_());
        m.notes.base_tick = static_cast<std::uint32_t>(pick(8) == 0 ? rng_() : now - 100 + pick(500));
        for (std::uint8_t i = 0; i < m.notes.count; ++i) {
          p::CompactNote& n = m.notes.notes[i];
          n.offset = static_cast<std::uint8_t>(rng_());
          n.preset = slot();
          n.duration_ticks = pick(10) == 0 ? 1 + pick(p::kMaxCompactDuration) : 1 + pick(2000);
          n.freq_q20 = freq();
          n.amp_q16 = static_cast<std::uint16_t>(rng_());
        }
        break;
      case p::Type::long_note:
        m.long_note.start_tick = pick(4) == 0 ? rng_() : now + pick(300);
        m.long_note.preset = slot();
        m.long_note.duration_ticks = 1 + static_cast<std::uint32_t>(rng_() % 0xFFFFFFFFu);
        m.long_note.freq_q20 = freq();
        m.long_note.amp_q16 = static_cast<std::uint16_t>(rng_());
        break;
      case p::Type::preset:
        m.preset.slot =
            static_cast<std::uint8_t>(envelope::kFirstUserSlot + pick(envelope::kSlotCount - envelope::kFirstUserSlot));
        m.preset.adsr = {uniform(0, pick(2) ? 1e7f : 300.0f),
                         uniform(0, 500),
                         uniform(0, pick(2) ? 1e7f : 300.0f),
                         uniform(0, 1),
                         uniform(0, 1),
                         static_cast<envelope::Shape>(pick(3))};
        break;
      case p::Type::settings: {
        p::Settings& s = m.settings;
        s.policy = static_cast<p::PolicyCode>(pick(3));
        s.gain = uniform(0, 1);
        s.peak_force_n = uniform(0.01f, 20.0f);
        s.end_fade_ms = uniform(0, 1000);
        s.watchdog_ms = static_cast<std::uint16_t>(10 + pick(1000));
        s.ramp_in_ms = static_cast<std::uint16_t>(rng_());
        s.t_min_n = uniform(0, 5);
        s.t_max_n = uniform(s.t_min_n + 0.01f, 20);
        break;
      }
      case p::Type::transport:
        m.transport.op = pick(10) == 0 ? static_cast<p::TransportOp>(pick(4)) : p::TransportOp::play;
        m.transport.tick = m.transport.op == p::TransportOp::seek ? rng_() : 0;
        break;
      default: break;
    }
    return m;
  }

  std::mt19937_64 rng_;
  const sim::SimDevice& dev_;
};

void check_output(const sim::SimDevice& dev) {
  const float y = dev.last_output();
  ASSERT_TRUE(std::isfinite(y));
  ASSERT_LE(std::abs(y), dev.core().settings().gain);
}

TEST(FirmwareFuzz, MillionHostileReportsAreCountedAndNeverPushOutputPastLimits) {
  constexpr std::uint32_t kReports = 1'000'000;
  sim::SimDevice dev;
  HostLink host(dev);
  Oracle oracle(dev.core().tick_hz());
  Generator gen(20240611, dev);
  std::uint32_t expected_rejected = 0;
  std::uint64_t errors_answered = 0, sounding_ticks = 0;
  p::Report r;
  const auto drain = [&] {
    p::Report out;
    p::Message m;
    while (dev.poll_report(out)) {
      ASSERT_EQ(p::decode(out, m), p::ErrorCode::none);
      if (m.type == p::Type::error) ++errors_answered;
    }
  };
  for (std::uint32_t i = 0; i < kReports; ++i) {
    gen.next(r);
    if (oracle.invalid(r)) ++expected_rejected;
    while (!dev.core().inbox_has_room()) {
      dev.advance(1);
      check_output(dev);
      if (dev.last_output() != 0.0f) ++sounding_ticks;
      if (dev.tick() % 256 == 0) drain();
    }
    ASSERT_TRUE(dev.send_to_device(r));
  }
  dev.advance(fw::Core::kInboxCapacity);  // handle what is left
  drain();

  const fw::Stats& st = dev.core().stats();
  EXPECT_EQ(st.packets, kReports);
  EXPECT_EQ(st.rejected, expected_rejected + st.queue_full);
  EXPECT_EQ(st.engine_refused, 0u);
  EXPECT_EQ(st.inbox_full, 0u);
  EXPECT_EQ(st.tx_dropped, 0u);
  EXPECT_EQ(errors_answered, st.rejected);
  EXPECT_EQ(dev.core().faults() & p::fault_output_limit, 0u);
  // The mix must have exercised the device, not just its decoder.
  EXPECT_GT(expected_rejected, kReports / 2);
  EXPECT_LT(expected_rejected, kReports - kReports / 10);
  EXPECT_GT(st.started, 10000u);
  EXPECT_GT(sounding_ticks, 10000u);
  std::printf("rejected %u, queue_full %u, started %u, late %u, stolen %u, ticks %llu (%llu sounding)\n", st.rejected,
              st.queue_full, st.started, st.late, dev.core().engine().counters().stolen,
              static_cast<unsigned long long>(dev.tick()), static_cast<unsigned long long>(sounding_ticks));

  // Still a working device: a new session plays a note exactly like the engine.
  host.open_exact();
  dev.advance(2);
  const TestNote n{dev.tick() + 5, 300, 100.0, 0.5};
  host.notes({n});
  const std::uint64_t first = dev.tick() + 1;
  EXPECT_EQ(host.run(400), reference_output({n}, first, 400, dev.core().tick_hz()));
}

}  // namespace
}  // namespace hmp::test
