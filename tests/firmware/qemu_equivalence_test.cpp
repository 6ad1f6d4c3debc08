// The firmware image under QEMU (board qemu-an386, Cortex-M4F) plays a real song exactly like the native
// build of the same core (design §8, §10, §13):
//   - the notes of the demo song's eight instrument tracks, merged (chords, many voices at once), go to
//     the image over the emulated UART in framed reports, with the credit-based flow control of
//     docs/protocol.md and a Sync every 100 ms, like a real host;
//   - one corrupted frame is slipped into the stream: it must be dropped and counted, nothing else may
//     change (it carries a copy of the next report, so if it got through its notes would play twice);
//   - the image traces every tick's output and every report it was handed, with the tick it arrived in;
//   - the simulated board (boards/sim: the same core built for the host) is fed those reports at those
//     ticks, and the two outputs must agree within 1e-6 on every tick; every note must start on the tick
//     the host scheduled (Started reports: actual == scheduled, none late).
// Runs at the image's build rate and, with its hz=10000 option, at 10 kHz. Needs qemu-system-arm and the
// image (HMP_QEMU_ELF, built by scripts/test); skipped when either is missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <utility>

#include "boards/sim/sim_device.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/midi/smf_reader.hpp"
#include "host/transport/handshake.hpp"
#include "host/transport/host_session.hpp"
#include "shared/framing/framing.hpp"
#include "tests/firmware/qemu_runner.hpp"

namespace hmp::test {
namespace {

namespace p = hmp::protocol;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr const char* kSong = HMP_REPO_DIR "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid";
constexpr float kTolerance = 1e-6f;

// One note report before it is numbered, and the device ticks its notes start on.
struct Batch {
  p::Message msg;
  std::vector<std::uint64_t> starts;
  std::uint64_t base = 0;
};

struct SongNotes {
  std::vector<Batch> batches;  // in sending order (by base tick)
  std::size_t notes = 0;
  std::uint64_t last_end = 0;  // device tick after the last note
  int max_overlap = 0;         // most notes sounding on one tick
};

// A stretch of the song: the notes of every track that start within `seconds` from `from_s`, moved so
// that `from_s` falls on device tick t0. Reports of up to five notes of one track within 255 ticks
// (longer notes: LongNote).
SongNotes song_notes(std::uint32_t tick_hz, double from_s, double seconds, std::uint64_t t0) {
  const midi::ReadResult song = midi::load_song(kSong);
  haptics::HapticOptions opts;
  opts.tick_hz = tick_hz;
  SongNotes out;
  const std::uint64_t from_tick = haptics::seconds_to_tick(std::llround(from_s * 1e6), tick_hz);
  std::vector<std::pair<std::uint64_t, int>> edges;
  for (std::uint32_t t = 0; t < song.song.tracks.size(); ++t) {
    if (song.song.tracks[t].note_count == 0) continue;
    const haptics::HapticTrack track = haptics::build_haptic_track(song.song, t, opts);
    EXPECT_TRUE(track.uploads.empty()) << "auto envelopes are built-in presets";
    Batch batch;
    auto flush = [&] {
      if (batch.starts.empty()) return;
      out.batches.push_back(batch);
      batch = Batch{};
    };
    for (const haptics::HapticNote& h : track.notes) {
      if (h.start_s < from_s) continue;
      if (h.start_s >= from_s + seconds) break;
      synth::Note n = h.note;
      n.start_tick = n.start_tick - from_tick + t0;
      ++out.notes;
      out.last_end = std::max(out.last_end, n.start_tick + n.duration_ticks);
      edges.emplace_back(n.start_tick, +1);
      edges.emplace_back(n.start_tick + n.duration_ticks, -1);
      if (n.duration_ticks > p::kMaxCompactDuration) {
        flush();
        batch.msg = p::make(p::Type::long_note, 0);
        batch.msg.long_note = {n.track, n.preset, n.start_tick, n.duration_ticks, n.freq_q20, n.amp_q16};
        batch.base = n.start_tick;
        batch.starts.push_back(n.start_tick);
        flush();
        continue;
      }
      if (!batch.starts.empty() && (batch.starts.size() == p::kNotesPerBatch || n.start_tick - batch.base > 255))
        flush();
      if (batch.starts.empty()) {
        batch.msg = p::make(p::Type::notes, 0);
        batch.msg.notes.track = n.track;
        batch.msg.notes.base_tick = static_cast<std::uint32_t>(n.start_tick);
        batch.base = n.start_tick;
      }
      p::CompactNote& c = batch.msg.notes.notes[batch.msg.notes.count++];
      c = {static_cast<std::uint8_t>(n.start_tick - batch.base), n.preset, n.duration_ticks, n.freq_q20, n.amp_q16};
      batch.starts.push_back(n.start_tick);
    }
    flush();
  }
  std::stable_sort(out.batches.begin(), out.batches.end(),
                   [](const Batch& a, const Batch& b) { return a.base < b.base; });
  std::sort(edges.begin(), edges.end());  // at equal ticks the ends (−1) come first
  int sounding = 0;
  for (const auto& e : edges) out.max_overlap = std::max(out.max_overlap, sounding += e.second);
  return out;
}

// What the device has told the host so far.
struct DeviceView {
  transport::HostSession session;  // numbering and credit (fed every Status)
  std::optional<p::Status> status;
  std::vector<p::StartedEntry> started;
  std::vector<p::Error> errors;
  std::size_t undecodable = 0;

  void take(const p::Report& r) {
    p::Message m;
    if (p::decode(r, m) != p::ErrorCode::none) {
      ++undecodable;
      return;
    }
    if (m.type == p::Type::status) {
      status = m.status;
      session.on_status(m.status);
    }
    if (m.type == p::Type::error) errors.push_back(m.error);
    if (m.type == p::Type::started)
      started.insert(started.end(), m.started.entries, m.started.entries + m.started.count);
  }
  // Waits up to `timeout` for one report, then takes whatever else is already there.
  void pump(transport::Transport& link, transport::Timeout timeout) {
    p::Report r;
    for (auto t = timeout; link.receive(r, t) == transport::Received::report; t = transport::Timeout{0}) take(r);
  }
};

struct Outcome {
  std::uint32_t tick_hz = 0;
  SongNotes song;
  std::map<std::pair<std::uint16_t, std::uint8_t>, std::uint64_t> scheduled;  // (seq, index) → start tick
  std::vector<std::array<std::uint8_t, p::kReportSize>> sent;                 // intact reports, in order
  DeviceView device;
  FirmwareRun run;
  std::optional<int> exit_code;
};

// Plays `seconds` of the song from `from_s` on the image booted with `options`.
Outcome play_on_qemu(const std::string& image, const std::string& options, double from_s, double seconds) {
  Outcome o;
  QemuFirmware qemu(image, options);
  transport::SerialTransport& link = qemu.link();
  transport::HostSession& session = o.device.session;
  auto send = [&](p::Message m) {
    p::Report r;
    session.number(m, r);
    EXPECT_TRUE(link.send(r)) << link.closed_reason();
    std::array<std::uint8_t, p::kReportSize> copy;
    std::copy(std::begin(r), std::end(r), copy.begin());
    o.sent.push_back(copy);
    return m.seq;
  };

  const std::uint16_t hello_seq = session.take_seq();
  const auto id = transport::say_hello(link, hello_seq, 10s);
  if (!id || !id->status) {
    ADD_FAILURE() << "no HelloReply/Status from the image:\n" << qemu.log_text();
    return o;
  }
  {
    // Every copy of the Hello say_hello sent (a slow tick rate answers after its resend period).
    p::Report hello;
    p::encode(p::make(p::Type::hello, hello_seq), hello);
    for (int i = 0; i < id->hellos_sent; ++i) {
      o.sent.push_back({});
      std::copy(std::begin(hello), std::end(hello), o.sent.back().begin());
    }
  }
  EXPECT_EQ(id->hello.board, p::Board::qemu_an386);
  o.tick_hz = id->hello.tick_hz;
  o.device.status = id->status;
  session.restart(id->status);

  p::Message settings = p::make(p::Type::settings, 0);
  settings.settings.watchdog_ms = 60000;  // a slow test machine must not trip it; the host syncs anyway
  send(settings);
  // Notes start one second from now: the first reports are there long before.
  const std::uint64_t t0 = id->status->tick + o.tick_hz;
  o.song = song_notes(o.tick_hz, from_s, seconds, t0);
  p::Message play = p::make(p::Type::transport, 0);
  play.transport.op = p::TransportOp::play;
  send(play);

  const std::size_t corrupt_before = std::min<std::size_t>(7, o.song.batches.size() - 1);
  std::size_t next = 0;
  auto last_sync = Clock::now();
  const auto give_up = Clock::now() + std::chrono::duration<double>(seconds + 30.0);
  while (Clock::now() < give_up && link.is_open()) {
    while (session.credit() > 0 && next < o.song.batches.size()) {
      Batch& b = o.song.batches[next];
      if (next == corrupt_before) {
        // The same report it is about to send, framed, with one byte flipped: it may neither become 0x00
        // (which would split it into two frames) nor leave the frame intact.
        b.msg.seq = session.next_seq();
        p::Report r;
        p::encode(b.msg, r);
        std::uint8_t frame[framing::kMaxFrame];
        const std::size_t len = framing::encode(r, sizeof r, frame, sizeof frame);
        std::size_t at = len / 2;
        while (frame[at] == 0x00 || frame[at] == 0x01) ++at;
        frame[at] ^= 0x01;
        EXPECT_EQ(::send(qemu.raw_fd(), frame, len, MSG_NOSIGNAL), static_cast<ssize_t>(len));
      }
      const std::uint16_t q = send(b.msg);
      for (std::size_t i = 0; i < b.starts.size(); ++i) o.scheduled[{q, static_cast<std::uint8_t>(i)}] = b.starts[i];
      ++next;
    }
    if (Clock::now() - last_sync >= 100ms) {
      p::Message sync = p::make(p::Type::sync, 0);
      sync.sync.host_time_us = static_cast<std::uint64_t>(
          std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count());
      send(sync);
      last_sync = Clock::now();
    }
    o.device.pump(link, 20ms);
    if (next == o.song.batches.size() && o.device.status->tick > o.song.last_end + o.tick_hz / 5) break;
  }
  // The host goes quiet; the image exits after exit-idle-ms and prints its summary. Until then the host
  // keeps reading: QEMU writes the UART's bytes one at a time, and an unread socket fills after a few
  // hundred of them (the device would then have to drop reports).
  const auto exit_deadline = Clock::now() + 30s;
  while (!(o.exit_code = qemu.wait(0ms)) && Clock::now() < exit_deadline) o.device.pump(link, 20ms);
  o.device.pump(link, 0ms);
  o.run = parse_firmware_log(qemu.log_text());
  if (!o.exit_code) ADD_FAILURE() << "QEMU did not exit";
  return o;
}

void check_equivalence(const std::string& options, double from_s, double seconds) {
  if (const std::string why = qemu_missing(); !why.empty()) GTEST_SKIP() << why;
  const Outcome o = play_on_qemu(qemu_image_path(), options, from_s, seconds);
  ASSERT_TRUE(o.exit_code.has_value());
  ASSERT_EQ(*o.exit_code, 0);
  const FirmwareRun& run = o.run;
  for (const std::string& problem : run.problems) ADD_FAILURE() << problem;
  for (const std::string& line : run.log) std::cout << "  firmware " << line << "\n";
  std::cout << "  " << o.tick_hz << " Hz: " << o.song.notes << " notes in " << o.song.batches.size()
            << " reports, up to " << o.song.max_overlap << " at once, " << run.outputs.size() << " ticks traced\n";
  ASSERT_GT(o.song.notes, 25u);
  EXPECT_GE(o.song.max_overlap, 4) << "the song segment should have chords";

  // The link: every intact report arrived once, in order, and the corrupted frame was dropped and counted.
  EXPECT_EQ(run.counters.at("trace.dropped"), 0u);
  EXPECT_EQ(run.counters.at("link.frames"), o.sent.size());
  EXPECT_EQ(run.counters.at("link.crc_errors") + run.counters.at("link.malformed"), 1u);
  EXPECT_EQ(run.counters.at("link.oversized") + run.counters.at("link.wrong_size"), 0u);
  EXPECT_EQ(run.counters.at("link.inbox_refused"), 0u);
  ASSERT_EQ(run.reports.size(), o.sent.size());
  for (std::size_t i = 0; i < o.sent.size(); ++i) ASSERT_EQ(run.reports[i].bytes, o.sent[i]) << "report " << i;

  // The core: every note started, on its tick, nothing refused, no fault.
  EXPECT_EQ(run.counters.at("core.started"), o.song.notes);
  EXPECT_EQ(run.counters.at("core.late"), 0u);
  EXPECT_EQ(run.counters.at("core.rejected"), 0u);
  EXPECT_EQ(run.counters.at("core.faults"), 0u);
  EXPECT_EQ(run.counters.at("core.inbox_full"), 0u);
  EXPECT_EQ(run.counters.at("core.tx_dropped"), 0u);
  EXPECT_TRUE(o.device.errors.empty());
  EXPECT_EQ(o.device.undecodable, 0u);
  // Started reports still in flight when the image exited are lost; all notes ended before that.
  ASSERT_EQ(o.device.started.size(), o.song.notes);
  std::map<std::pair<std::uint16_t, std::uint8_t>, int> seen;
  for (const p::StartedEntry& e : o.device.started) {
    const std::pair<std::uint16_t, std::uint8_t> key{e.seq, e.index};
    const auto it = o.scheduled.find(key);
    ASSERT_NE(it, o.scheduled.end()) << "Started for a note never sent: seq " << e.seq;
    EXPECT_EQ(++seen[key], 1) << "note started twice: seq " << e.seq << " index " << int(e.index);
    EXPECT_EQ(e.scheduled_tick, static_cast<std::uint32_t>(it->second));
    EXPECT_EQ(e.actual_tick, e.scheduled_tick) << "seq " << e.seq << " index " << int(e.index);
  }

  // The native build, fed the same reports at the same ticks.
  ASSERT_GE(run.outputs.size(), o.song.last_end);
  sim::SimDevice sim(o.tick_hz);
  std::vector<float> native(run.outputs.size());
  for (const FirmwareRun::Received& r : run.reports) {
    ASSERT_GE(r.tick, sim.tick()) << "reports out of tick order";
    ASSERT_LE(r.tick, native.size()) << "a report after the last traced tick";
    sim.advance(r.tick - sim.tick(), native.data() + sim.tick());
    p::Report bytes;
    std::copy(r.bytes.begin(), r.bytes.end(), bytes);
    ASSERT_TRUE(sim.send_to_device(bytes));
  }
  ASSERT_LE(sim.tick(), native.size());
  sim.advance(native.size() - sim.tick(), native.data() + sim.tick());

  std::size_t worst = 0, sounding = 0;
  float peak = 0.0f;
  for (std::size_t i = 0; i < native.size(); ++i) {
    if (std::fabs(run.outputs[i] - native[i]) > std::fabs(run.outputs[worst] - native[worst])) worst = i;
    sounding += run.outputs[i] != 0.0f ? 1 : 0;
    peak = std::max(peak, std::fabs(run.outputs[i]));
  }
  const float diff = std::fabs(run.outputs[worst] - native[worst]);
  std::cout << "  max |qemu - native| = " << diff << " at tick " << worst + 1 << "; peak " << peak << ", " << sounding
            << " non-zero ticks\n";
  EXPECT_LE(diff, kTolerance) << "tick " << worst + 1 << ": qemu " << run.outputs[worst] << ", native "
                              << native[worst];
  EXPECT_GT(peak, 0.1f);
  EXPECT_GT(sounding, native.size() / 2) << "the comparison must cover sound, not silence";
  EXPECT_EQ(sim.core().stats().started, o.song.notes);
  EXPECT_EQ(sim.core().engine().counters().stolen, run.counters.at("core.stolen"));
}

// 55–65 s into the movement all eight parts play: ~25 notes a second, up to 11 at once, more reports than
// the device's queue takes at once (the credit rule is exercised).
constexpr double kFromS = 55.0;

TEST(QemuEquivalence, SongAtTheBuildTickRateMatchesTheNativeBuild) {
  check_equivalence("trace exit-idle-ms=300", kFromS, 10.0);
}

// Shorter: at 10 kHz QEMU wakes from wfi 10 000 times a second and its virtual clock falls to about half
// of real time (boards/qemu-an386/README.md).
TEST(QemuEquivalence, SongAtTenKilohertzMatchesTheNativeBuild) {
  check_equivalence("trace exit-idle-ms=300 hz=10000", kFromS, 2.0);
}

}  // namespace
}  // namespace hmp::test
