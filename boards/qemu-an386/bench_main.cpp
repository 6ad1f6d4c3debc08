// Benchmark image (tools/bench/firmware-tick.sh): instructions per device tick of the real board code
// (An386Board::on_tick: the firmware core's tick, the board's output and report hand-off) with 0, 1, 4,
// 8 and 16 sounding voices, counted under QEMU -icount (instruction_counter.hpp). The ticks are called
// from thread mode with interrupts masked around each one instead of from SysTick, so that each can be
// measured; in between, the UART TX interrupt sends the reports the tick queued (not counted: it runs
// below the tick's priority on the real board).
//
// The notes are realistic, not the cheapest: every voice plays back-to-back 1-second notes with Table 1
// envelopes (attack, decay, sustain and the exponential release all occur), different frequencies, and
// amplitudes whose sum exceeds full scale, so the limiter works too. Notes arrive as Notes reports
// through on_packet, ahead of their start, as from a host. Output: one line per voice count,
//   result voices=V tick_hz=H ticks=N mean=M max=X min=Y
// plus a calibration line (1000 nops should count 1000). Option hz=N sets the tick rate.
//
// Then the same with the SPIDAR drive (design §8: the full tick ≤ 12,000): the board gets simulated motors
// (BenchMotors), whose encoders report, between ticks and not counted, the counts of a grip circling 5 mm
// around the centre at 0.5 Hz with a 0.1 mm, 173 Hz wobble, so the pose moves and the QP's warm starts
// are exercised; lines `result drive=1 voices=V …` for 0 and 16 voices. At a tick faster than 1 kHz, then
// the split drive (firmware/drive.hpp: the pose and QP planned at 1 kHz by the main loop, the rest in the
// tick): lines `result drive=split …` for the tick, and `plan …` for the slow part, counted on its own.
#include <new>

#include "an386_board.hpp"
#include "console.hpp"
#include "instruction_counter.hpp"
#include "options.hpp"
#include "registers.hpp"
#include "semihosting.hpp"
#include "shared/envelope/envelope.hpp"
#include "shared/spidar/geometry.hpp"
#include "shared/synth/frequency.hpp"
#include "shared/synth/voice.hpp"

namespace {

namespace p = hmp::protocol;
using hmp::board::An386Board;
using hmp::board::Line;

alignas(An386Board) unsigned char g_board_storage[sizeof(An386Board)];
An386Board* g_board = nullptr;
std::uint16_t g_seq = 0;

void send(p::Message m) {
  m.seq = ++g_seq;
  p::Report r;
  p::encode(m, r);
  g_board->core().on_packet(r);
}

void tick(void*) { g_board->on_tick(); }

// The drive rows: simulated motors, and the counts of a moving grip written before each tick.
hmp::board::BenchMotors g_motors;
bool g_drive = false;
const hmp::spidar::Frame<float> g_frame = hmp::spidar::x3_frame<float>();
float g_rest[8];

void set_counts(std::uint64_t tick, std::uint32_t tick_hz) {
  constexpr float kPi = 3.14159265f;
  const float circle = kPi * static_cast<float>(tick % (2u * tick_hz)) / static_cast<float>(tick_hz);
  const float wobble = 2.0f * kPi * 173.0f * static_cast<float>(tick % tick_hz) / static_cast<float>(tick_hz);
  hmp::spidar::Pose<float> pose;
  pose.position = {0.005f * __builtin_cosf(circle), 0.0001f * __builtin_sinf(wobble), 0.005f * __builtin_sinf(circle)};
  hmp::spidar::StringGeometry<float> s;
  hmp::spidar::compute_strings(g_frame, pose, s);
  const float metres_per_count = 2.0f * kPi * 0.005f / 2048.0f;  // 512 lines × 4 on a 5 mm pulley
  for (int i = 0; i < 8; ++i) {
    g_motors.counts[i] = static_cast<std::int32_t>(__builtin_lroundf((s.length[i] - g_rest[i]) / metres_per_count));
  }
}

// Envelopes with every phase (Table 1), cycled over the voices.
constexpr hmp::envelope::Preset kPresets[] = {hmp::envelope::Preset::violin,  hmp::envelope::Preset::cello,
                                              hmp::envelope::Preset::trumpet, hmp::envelope::Preset::harpsichord,
                                              hmp::envelope::Preset::flute,   hmp::envelope::Preset::organ,
                                              hmp::envelope::Preset::guitar,  hmp::envelope::Preset::contrabass};

// What else a tick did besides the voices (and the drive), as a set of bits: the heaviest tick of each
// combination, so that a max can be traced to its cause (detail lines max_by_kind_…).
enum KindBit { kStart = 1, kReport = 2, kStatus = 4, kRequest = 8, kKinds = 16 };
constexpr const char* kKindNames[] = {"note_start", "report", "status", "prepare_request"};

struct Result {
  std::uint64_t sum = 0;
  std::int32_t max = 0, min = 0x7FFFFFFF;
  std::uint32_t ticks = 0;
  std::int32_t kind_max[kKinds] = {};
  // The split drive's plans (the main loop's work, not the tick's).
  std::uint64_t plan_sum = 0;
  std::int32_t plan_max = 0;
  std::uint32_t plans = 0;
};

void plan(void*) { g_board->core().plan_drive(); }

Result run(const hmp::board::InstructionCounter& counter, std::uint32_t voices, std::uint32_t tick_hz) {
  send(p::make(p::Type::hello, 0));  // a fresh session: queue flushed, voices silent
  p::Message settings = p::make(p::Type::settings, 0);
  settings.settings.ramp_in_ms = 0;
  settings.settings.watchdog_ms = 60000;  // no host syncs here
  send(settings);
  p::Message play = p::make(p::Type::transport, 0);
  play.transport.op = p::TransportOp::play;
  send(play);

  const std::uint32_t note_ticks = tick_hz;  // 1 s notes, back to back on every voice
  const std::uint64_t t0 = g_board->core().tick() + 20;
  const std::uint64_t measure_from = t0 + note_ticks;  // every voice is sounding from here on
  const std::uint64_t measure_to = measure_from + 2 * note_ticks;
  const std::uint32_t lead = note_ticks / 10;  // notes are sent this far ahead of their start
  std::uint64_t next_start[16] = {};
  for (std::uint32_t v = 0; v < voices; ++v) next_start[v] = t0 + v * note_ticks / voices;

  Result r;
  while (g_board->core().tick() < measure_to) {
    const std::uint64_t now = g_board->core().tick();
    std::uint32_t sent = 0;  // the core takes up to 4 reports per tick
    for (std::uint32_t v = 0; v < voices && sent < 4; ++v) {
      if (next_start[v] > now + lead) continue;
      p::Message m = p::make(p::Type::notes, 0);
      m.notes.count = 1;
      m.notes.track = static_cast<std::uint8_t>(v);
      m.notes.base_tick = static_cast<std::uint32_t>(next_start[v]);
      p::CompactNote& n = m.notes.notes[0];
      n.preset = static_cast<std::uint8_t>(kPresets[v % (sizeof kPresets / sizeof kPresets[0])]);
      n.duration_ticks = note_ticks;
      n.freq_q20 = hmp::synth::freq_to_q20(50.0 + 12.5 * v);
      n.amp_q16 = hmp::synth::amp_to_q16(0.3);
      send(m);
      next_start[v] += note_ticks;
      ++sent;
    }
    if (g_drive) set_counts(now, tick_hz);
    const std::uint32_t primask = hmp::board::irq_save();
    if (now >= measure_from) {
      const hmp::fw::Core& core = g_board->core();
      const std::uint32_t started = core.stats().started, packets = core.stats().packets;
      const std::uint16_t reports = core.reports_sent();
      const std::uint32_t requests = core.stats().prepare_requests;
      const std::int32_t n = counter.measure(&tick, nullptr);
      r.sum += static_cast<std::uint64_t>(n < 0 ? 0 : n);
      r.max = n > r.max ? n : r.max;
      r.min = n < r.min ? n : r.min;
      ++r.ticks;
      int kind = 0;
      if (core.stats().started != started) kind |= kStart;
      if (core.stats().packets != packets) kind |= kReport;
      if (core.reports_sent() != reports) kind |= kStatus;
      if (core.stats().prepare_requests != requests) kind |= kRequest;
      r.kind_max[kind] = n > r.kind_max[kind] ? n : r.kind_max[kind];
    } else {
      tick(nullptr);
    }
    if (now >= measure_from && g_board->core().drive().split()) {
      // The split drive's plan, when the tick has asked for one: counted apart (it runs in the main loop).
      const std::uint32_t before = g_board->core().stats().drive_plan_late;
      const std::int32_t n = counter.measure(&plan, nullptr);
      if (n > 60) {  // a call that found nothing to plan costs a few dozen
        r.plan_sum += static_cast<std::uint64_t>(n);
        r.plan_max = n > r.plan_max ? n : r.plan_max;
        ++r.plans;
      }
      if (g_board->core().stats().drive_plan_late != before) Line().text("WARNING: a plan was late").print();
    }
    while (g_board->poll()) {  // the main loop's share (not counted): reports, voices of the next notes
    }
    hmp::board::irq_restore(primask);  // the TX interrupt sends what the tick queued
  }
  const std::uint8_t active = g_board->core().engine().active_voices();
  if (active != voices) Line().text("WARNING: ").u32(active).text(" voices sounding, expected ").u32(voices).print();
  return r;
}

// Where a tick's instructions go: the pieces of the per-voice work and of a note start, measured alone
// (printed as `detail` lines; docs/performance.md).
struct Probe {
  hmp::envelope::Envelope env;
  hmp::synth::Voice voice;
  hmp::synth::Note note;
  hmp::synth::SynthConfig cfg;
  std::uint32_t n = 0;
  std::uint32_t phase = 0;
  volatile float sink = 0.0f;
};
Probe g_probe;

void envelope_start(void*) {
  g_probe.env.start(hmp::envelope::builtin(hmp::envelope::Preset::violin), 0.5f, g_probe.note.duration_ticks,
                    static_cast<float>(g_probe.cfg.tick_hz), g_probe.cfg.end_fade_ms);
}
void voice_start(void*) {
  g_probe.voice.start(g_probe.note, hmp::envelope::builtin(hmp::envelope::Preset::violin), g_probe.cfg, 0);
}
void envelope_at(void*) { g_probe.sink = g_probe.env.at(g_probe.n); }
void sine(void*) { g_probe.sink = hmp::synth::sine(g_probe.cfg.sine, g_probe.phase); }

void details(const hmp::board::InstructionCounter& counter, std::uint32_t tick_hz) {
  g_probe.cfg.tick_hz = tick_hz;
  g_probe.note.duration_ticks = tick_hz;  // 1 s, violin: attack 66 ms, decay 376 ms, release 225 ms
  g_probe.note.freq_q20 = hmp::synth::freq_to_q20(123.4);
  g_probe.note.amp_q16 = hmp::synth::amp_to_q16(0.5);
  g_probe.note.preset = static_cast<std::uint8_t>(hmp::envelope::Preset::violin);
  const std::uint32_t primask = hmp::board::irq_save();
  const std::int32_t env_start = counter.measure(&envelope_start, nullptr);
  const std::int32_t voice_start_n = counter.measure(&voice_start, nullptr);
  const std::uint32_t ms = tick_hz / 1000;
  const std::uint32_t at_tick[] = {30 * ms, 200 * ms, 600 * ms, 900 * ms, tick_hz - 1};
  const char* at_name[] = {"attack", "decay", "sustain", "release", "last_tick"};
  std::int32_t at_cost[5];
  for (int i = 0; i < 5; ++i) {
    g_probe.n = at_tick[i];
    at_cost[i] = counter.measure(&envelope_at, nullptr);
  }
  g_probe.phase = 0x12345678u;
  const std::int32_t sine_cost = counter.measure(&sine, nullptr);
  hmp::board::irq_restore(primask);
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line().text("detail: envelope_start=").i32(env_start).text(" voice_start=").i32(voice_start_n)
      .text(" sine=").i32(sine_cost).print();
  // clang-format on
  Line line;
  line.text("detail: envelope_at");
  for (int i = 0; i < 5; ++i) line.text(" ").text(at_name[i]).text("=").i32(at_cost[i]);
  line.print();
}

// The two heaviest ticks a host can cause: the one that takes four full Notes reports (20 notes) from
// the inbox, and the one that starts 16 notes at once while 16 voices sound (every start steals).
void worst_ticks(const hmp::board::InstructionCounter& counter, std::uint32_t tick_hz) {
  run(counter, 0, tick_hz);  // a fresh playing session
  const auto chord = [&](std::uint64_t start, std::uint32_t first_voice) {
    for (std::uint32_t r = 0; r < 4; ++r) {
      p::Message m = p::make(p::Type::notes, 0);
      m.notes.count = static_cast<std::uint8_t>(p::kNotesPerBatch);
      m.notes.base_tick = static_cast<std::uint32_t>(start);
      for (std::uint32_t i = 0; i < p::kNotesPerBatch; ++i) {
        const std::uint32_t v = first_voice + r * p::kNotesPerBatch + i;
        p::CompactNote& n = m.notes.notes[i];
        n.preset = static_cast<std::uint8_t>(kPresets[v % (sizeof kPresets / sizeof kPresets[0])]);
        n.duration_ticks = tick_hz;
        n.freq_q20 = hmp::synth::freq_to_q20(50.0 + 5.0 * v);
        n.amp_q16 = hmp::synth::amp_to_q16(0.3);
      }
      send(m);
    }
  };
  const auto measured_tick = [&] {
    const std::uint32_t primask = hmp::board::irq_save();
    const std::int32_t n = counter.measure(&tick, nullptr);
    while (g_board->poll()) {
    }
    hmp::board::irq_restore(primask);
    return n;
  };
  // 20 notes on one tick: the first 16 sound (and steal each other's voices), then 20 more.
  const std::uint64_t now = g_board->core().tick();
  chord(now + 50, 0);
  const std::int32_t take_reports = measured_tick();
  while (g_board->core().tick() + 1 < now + 50) measured_tick();
  measured_tick();  // 20 notes due: 16 start (the most per tick), 4 on the next tick
  measured_tick();
  chord(now + 100, 20);
  while (g_board->core().tick() + 1 < now + 100) measured_tick();
  const std::int32_t start_16 = measured_tick();
  Line().text("detail: worst take_4_reports=").i32(take_reports).text(" start_16_notes=").i32(start_16).print();
}

void print_kinds(const char* group, const Result& r) {
  Line line;
  line.text("detail: ").text(group);
  for (int k = 0; k < kKinds; ++k) {
    if (r.kind_max[k] == 0) continue;
    line.text(" ");
    if (k == 0) line.text("plain");
    for (int bit = 0, first = 1; bit < 4; ++bit) {
      if (!(k & (1 << bit))) continue;
      if (!first) line.text("+");
      line.text(kKindNames[bit]);
      first = 0;
    }
    line.text("=").i32(r.kind_max[k]);
  }
  line.print();
}

}  // namespace

extern "C" void UART0_RX_Handler() { g_board->on_uart_rx(); }
extern "C" void UART0_TX_Handler() { g_board->on_uart_tx(); }

int main() {
  const hmp::board::Options opt = hmp::board::read_options();
  if (opt.error != nullptr) return hmp::board::kExitBadOption;
  g_board = new (g_board_storage) An386Board(opt.tick_hz, false);
  g_board->start_link();
  hmp::board::InstructionCounter counter;
  counter.start();
  const std::uint32_t primask = hmp::board::irq_save();
  const std::int32_t nops = counter.calibration_check();
  hmp::board::irq_restore(primask);
  Line().text("calibration: nops=1000 measured=").i32(nops).print();

  details(counter, opt.tick_hz);

  constexpr std::uint32_t kVoiceCounts[] = {0, 1, 4, 8, 16};
  for (const std::uint32_t voices : kVoiceCounts) {
    const Result r = run(counter, voices, opt.tick_hz);
    const float mean = static_cast<float>(r.sum) / static_cast<float>(r.ticks);
    // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
    // clang-format off
    Line().text("result voices=").u32(voices).text(" tick_hz=").u32(opt.tick_hz).text(" ticks=").u32(r.ticks)
        .text(" mean=").fixed(mean, 1).text(" max=").i32(r.max).text(" min=").i32(r.min).print();
    // clang-format on
    if (voices == 16) print_kinds("max_by_kind_16_voices", r);
  }
  worst_ticks(counter, opt.tick_hz);

  const hmp::fw::Stats& s = g_board->core().stats();
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line().text("core: started=").u32(s.started).text(" late=").u32(s.late).text(" rejected=").u32(s.rejected)
      .text(" tx_dropped=").u32(s.tx_dropped).print();
  // clang-format on

  // The same board with motors: a fresh board (and core) whose seam has encoders and motor outputs.
  g_board->stop();
  g_board->~An386Board();
  hmp::spidar::rest_lengths(g_frame, g_rest);
  g_drive = true;
  g_board = new (g_board_storage) An386Board(opt.tick_hz, false, &g_motors);
  g_board->start_link();
  constexpr std::uint32_t kDriveVoiceCounts[] = {0, 16};
  for (const std::uint32_t voices : kDriveVoiceCounts) {
    const Result r = run(counter, voices, opt.tick_hz);
    const float mean = static_cast<float>(r.sum) / static_cast<float>(r.ticks);
    // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
    // clang-format off
    Line().text("result drive=1 voices=").u32(voices).text(" tick_hz=").u32(opt.tick_hz).text(" ticks=").u32(r.ticks)
        .text(" mean=").fixed(mean, 1).text(" max=").i32(r.max).text(" min=").i32(r.min).print();
    // clang-format on
    if (voices == 16) print_kinds("max_by_kind_16_voices_drive", r);
  }
  if (g_board->core().faults() != 0) Line().text("WARNING: drive faults ").hex(g_board->core().faults()).print();

  // The split drive, where the tick is faster than the plan's 1 kHz.
  if (opt.tick_hz > 1000) {
    g_board->stop();
    g_board->~An386Board();
    hmp::fw::DriveParams split;
    split.plan_hz = 1000;
    g_board = new (g_board_storage) An386Board(opt.tick_hz, false, &g_motors, split);
    g_board->start_link();
    for (const std::uint32_t voices : kDriveVoiceCounts) {
      const Result r = run(counter, voices, opt.tick_hz);
      const float mean = static_cast<float>(r.sum) / static_cast<float>(r.ticks);
      const float plan_mean = r.plans ? static_cast<float>(r.plan_sum) / static_cast<float>(r.plans) : 0.0f;
      // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
      // clang-format off
      Line().text("result drive=split voices=").u32(voices).text(" tick_hz=").u32(opt.tick_hz).text(" ticks=")
          .u32(r.ticks).text(" mean=").fixed(mean, 1).text(" max=").i32(r.max).text(" min=").i32(r.min)
          .text(" plans=").u32(r.plans).text(" plan_mean=").fixed(plan_mean, 1).text(" plan_max=").i32(r.plan_max)
          .print();
      // clang-format on
      if (voices == 16) print_kinds("max_by_kind_16_voices_split_drive", r);
    }
    if (g_board->core().faults() != 0)
      Line().text("WARNING: split drive faults ").hex(g_board->core().faults()).print();
  }
  return hmp::board::semihost::kExitOk;
}
