// 10^6 random, malformed and hostile reports (seeded, a few seconds): the device never crashes, its
// output never leaves the configured limit, every invalid report is counted and answered, and it still
// works afterwards. Which reports are invalid is decided here, from the protocol's decoder and the
// device contract in docs/firmware.md (not by asking the firmware). Live reports are taken only while the
// device plays, which depends on when each report is taken (a watchdog may pause it): the device's
// Errors for them are matched, in order, with the oracle's verdict on each, and only the not_playing
// refusals of valid ones add to the refusals it expects.
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <random>

#include "shared/common/bytes.hpp"
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
    const bool bad = judge(r);
    if (r[0] == static_cast<std::uint8_t>(p::Type::live)) {
      const Verdict v = !bad       ? Verdict::valid
                        : decoded_ ? (locked_ ? Verdict::locked : Verdict::refused)
                                   : Verdict::malformed;
      live_.push_back({bytes::get_u16(&r[1]), v});
      ++live_count_[static_cast<int>(v)];
    }
    return bad;
  }

  // The device's Error for a report of the Live type: the earliest judged Live report of its seq whose
  // verdict the code fits; every one before it must be a valid one the device took. False if none fits.
  bool live_error(const p::Error& e) {
    for (std::size_t i = 0; i < live_.size(); ++i) {
      if (live_[i].seq == e.seq && fits(live_[i].verdict, e.code)) {
        for (std::size_t k = 0; k < i; ++k)
          if (live_[k].verdict != Verdict::valid) return false;  // refused, and not answered
        if (live_[i].verdict == Verdict::valid) ++valid_not_playing_;
        live_.erase(live_.begin(), live_.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        return true;
      }
    }
    return false;
  }
  // Judged Live reports still waiting for an Error that are not valid ones (which may have been taken).
  std::size_t live_unanswered() const {
    std::size_t n = 0;
    for (const Judged& j : live_) n += j.verdict != Verdict::valid;
    return n;
  }
  std::uint64_t valid_not_playing() const { return valid_not_playing_; }
  std::uint64_t live_valid() const { return live_count_[static_cast<int>(Verdict::valid)]; }
  std::uint64_t live_refused() const { return live_count_[static_cast<int>(Verdict::refused)]; }

 private:
  // What the device must do with a Live report while playing: take it, or refuse it for its events
  // (bad_slot, bad_value), its protocol version (version_mismatch) or its form (the decoder's verdict).
  enum class Verdict { valid, refused, locked, malformed };
  struct Judged {
    std::uint16_t seq;
    Verdict verdict;
  };
  static bool fits(Verdict v, p::ErrorCode code) {
    switch (v) {
      case Verdict::valid: return code == p::ErrorCode::not_playing;
      case Verdict::refused:
        return code == p::ErrorCode::not_playing || code == p::ErrorCode::bad_slot || code == p::ErrorCode::bad_value;
      case Verdict::locked: return code == p::ErrorCode::version_mismatch;
      case Verdict::malformed:  // the decoder's codes, bad_slot among them (a slot beyond the table)
        return code != p::ErrorCode::none && code != p::ErrorCode::version_mismatch &&
               code != p::ErrorCode::queue_full && code != p::ErrorCode::not_playing;
    }
    return false;
  }

  bool judge(const p::Report& r) {
    p::Message m;
    decoded_ = p::decode(r, m) == p::ErrorCode::none;
    if (!decoded_) return true;
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
      case p::Type::live:
        for (std::uint8_t i = 0; i < m.live.count; ++i) {
          const p::LiveEvent& e = m.live.events[i];
          if (e.op == p::LiveOp::on && !playable(e.preset, e.freq_q20)) return true;
          if (e.op == p::LiveOp::bend && !audible(e.freq_q20)) return true;
        }
        return false;
      default: return false;
    }
  }

  bool playable(std::uint8_t slot, std::uint32_t freq_q20) const { return slot_used_[slot] && audible(freq_q20); }
  // 0 < f < tick_hz / 2, in Q12.20 Hz.
  bool audible(std::uint32_t freq_q20) const {
    const double hz = static_cast<double>(freq_q20) / 1048576.0;
    return hz > 0.0 && hz < static_cast<double>(tick_hz_) / 2.0;
  }
  std::uint32_t tick_hz_;
  bool locked_ = false, decoded_ = false;
  bool slot_used_[envelope::kSlotCount] = {};
  std::deque<Judged> live_;  // Live reports judged, in the order sent, until their Error (if any) came
  std::uint64_t live_count_[static_cast<int>(Verdict::malformed) + 1] = {};  // by verdict
  std::uint64_t valid_not_playing_ = 0;
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
      default: return synth::freq_to_q20(static_cast<double>(uniform(20.0f, 400.0f)));
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
                                        {p::Type::hello, 8},   {p::Type::estop, 1},      {p::Type::live, 150}};
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
    // Seqs in turn, as a host sends them: the Errors for Live reports are told apart by them.
    p::Message m = p::make(type, next_seq_++);
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
      case p::Type::live:
        // A few keys on a few tracks, so that releases and bends find the notes held before them.
        m.live.count = static_cast<std::uint8_t>(1 + pick(5));
        m.live.track = static_cast<std::uint8_t>(pick(4));
        for (std::uint8_t i = 0; i < m.live.count; ++i) {
          p::LiveEvent& e = m.live.events[i];
          const unsigned op = pick(10);
          e.op = op < 5 ? p::LiveOp::on : (op < 8 ? p::LiveOp::off : p::LiveOp::bend);
          e.key = static_cast<std::uint8_t>(pick(8) == 0 ? pick(256) : 60 + pick(12));
          e.preset = e.op == p::LiveOp::on ? slot() : 0;
          e.freq_q20 = e.op == p::LiveOp::off ? 0 : freq();
          e.amp_q16 = e.op == p::LiveOp::on ? static_cast<std::uint16_t>(rng_()) : 0;
        }
        break;
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
  std::uint16_t next_seq_ = 0;
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
  std::uint64_t errors_answered = 0, sounding_ticks = 0, live_unmatched = 0;
  p::Report r;
  const auto drain = [&] {
    p::Report out;
    p::Message m;
    while (dev.poll_report(out)) {
      ASSERT_EQ(p::decode(out, m), p::ErrorCode::none);
      if (m.type != p::Type::error) continue;
      ++errors_answered;
      if (m.error.type == static_cast<std::uint8_t>(p::Type::live) && !oracle.live_error(m.error)) ++live_unmatched;
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
  EXPECT_EQ(st.rejected, expected_rejected + st.queue_full + oracle.valid_not_playing());
  EXPECT_EQ(live_unmatched, 0u) << "Errors for Live reports that no verdict of the oracle fits";
  EXPECT_EQ(oracle.live_unanswered(), 0u) << "Live reports the device should have refused";
  // Live reports taken while playing and refused while not, and refused for their events.
  EXPECT_GT(oracle.live_valid() - oracle.valid_not_playing(), 10000u);
  EXPECT_GT(oracle.valid_not_playing(), 100u);
  EXPECT_GT(oracle.live_refused(), 1000u);
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
  std::printf(
      "rejected %u, queue_full %u, started %u, late %u, stolen %u, ticks %llu (%llu sounding); Live: %llu valid "
      "(%llu refused, not playing), %llu with a bad event\n",
      st.rejected, st.queue_full, st.started, st.late, dev.core().engine().counters().stolen,
      static_cast<unsigned long long>(dev.tick()), static_cast<unsigned long long>(sounding_ticks),
      static_cast<unsigned long long>(oracle.live_valid()), static_cast<unsigned long long>(oracle.valid_not_playing()),
      static_cast<unsigned long long>(oracle.live_refused()));

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
