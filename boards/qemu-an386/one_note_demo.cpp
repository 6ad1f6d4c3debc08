// Demo image for qemu-an386 (hmp_fw_qemu_an386_demo): the SysTick interrupt plays one note through the
// shared synthesis engine alone (no firmware core, no UART), then main() checks the samples against an
// independent reference, prints a summary over semihosting and exits with 0 only if every check passed.
// A self-check of the toolchain, startup code and float ABI; tests.cmake runs it (qemu_boot_one_note).
#include <cmath>
#include <cstdint>

#include "console.hpp"
#include "registers.hpp"
#include "semihosting.hpp"
#include "shared/envelope/envelope.hpp"
#include "shared/synth/engine.hpp"
#include "shared/synth/frequency.hpp"

namespace {

using hmp::board::Line;

using hmp::board::kCoreHz;  // MPS2 AN386 system clock
constexpr std::uint32_t kTickHz = HMP_TICK_HZ;
static_assert(kCoreHz % kTickHz == 0 && kCoreHz / kTickHz - 1 <= 0xFFFFFFu, "SysTick cannot make this rate");

// The note: an integer frequency keeps the reference phase exact ((f·n) mod tick_hz); 50 Hz also puts
// samples on the crests, so the peak equals the amplitude. One second plus a silent tail.
constexpr std::uint32_t kNoteHz = 50;
constexpr double kNoteAmp = 0.5;
constexpr std::uint32_t kNoteTicks = kTickHz;
constexpr std::uint32_t kTailTicks = 20;
constexpr std::uint32_t kTotalTicks = kNoteTicks + kTailTicks;
constexpr auto kPreset = hmp::envelope::Preset::square;  // E = amplitude for the whole note (design §6)

// Tolerances. Precision against the design §7 budget is tested on the host; here we only need to catch a
// cross build that computes something else (wrong float ABI, libm, startup or optimiser trouble).
constexpr float kSampleTolerance = 1e-4f;
constexpr float kPeakTolerance = 1e-3f;

using hmp::board::reg;
namespace systick = hmp::board::systick;

// Startup probes: one in .data, one in .bss, one set by a constructor that cannot be folded into
// static data (it reads a volatile), so each part of the C runtime set-up is checked separately.
constexpr std::uint32_t kDataPattern = 0x600DDA7Au;
std::uint32_t g_data_probe = kDataPattern;
std::uint32_t g_bss_probe;
volatile std::uint32_t g_ctor_seed = 41;
struct CtorProbe {
  std::uint32_t value;
  CtorProbe() : value(g_ctor_seed + 1) {}
};
CtorProbe g_ctor_probe;

hmp::synth::Engine g_engine{hmp::synth::SynthConfig{kTickHz}};
hmp::synth::Note g_note;
float g_samples[kTotalTicks];
volatile std::uint32_t g_tick = 0;
volatile bool g_start_ok = false;

// Reference sample, written independently of shared/synth: a·sin(2π f n / tick_hz) with the phase
// reduced exactly in integers and mapped to (−π, π] where sinf is most accurate.
float reference(float amp, std::uint32_t n) {
  auto k = static_cast<std::int64_t>((static_cast<std::uint64_t>(kNoteHz) * n) % kTickHz);
  if (2 * k > static_cast<std::int64_t>(kTickHz)) k -= kTickHz;
  constexpr float kTwoPi = 6.28318530717958647692f;
  return amp * std::sin(kTwoPi * static_cast<float>(k) / static_cast<float>(kTickHz));
}

std::uint32_t fnv1a(const float* v, std::uint32_t count) {
  std::uint32_t h = 2166136261u;
  for (std::uint32_t i = 0; i < count; ++i) {
    std::uint32_t bits;
    __builtin_memcpy(&bits, &v[i], sizeof bits);
    for (int b = 0; b < 4; ++b) {
      h ^= (bits >> (8 * b)) & 0xFFu;
      h *= 16777619u;
    }
  }
  return h;
}

int g_failures = 0;
void check(bool ok, const char* what) {
  if (ok) return;
  ++g_failures;
  Line().text("CHECK FAILED: ").text(what).print();
}

}  // namespace

// One device tick: start the note on tick 0, then synthesize. Runs until the tail is recorded.
extern "C" void SysTick_Handler() {
  const std::uint32_t n = g_tick;
  if (n >= kTotalTicks) return;
  if (n == 0) g_start_ok = g_engine.start(g_note);
  g_samples[n] = g_engine.tick();
  g_tick = n + 1;
}

int main() {
  Line().text("HMP qemu-an386 one-note demo").print();
  const bool fpu_on = (reg(hmp::board::scb::kCpacr) & (0xFu << 20)) == (0xFu << 20);
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line()
      .text("startup: data=").text(g_data_probe == kDataPattern ? "ok" : "BAD")
      .text(" bss=").text(g_bss_probe == 0 ? "ok" : "BAD")
      .text(" ctors=").text(g_ctor_probe.value == 42 ? "ok" : "BAD")
      .text(" fpu=").text(fpu_on ? "ok" : "BAD")
      .print();
  // clang-format on
  check(g_data_probe == kDataPattern, ".data initialised from its load image");
  check(g_bss_probe == 0, ".bss zeroed");
  check(g_ctor_probe.value == 42, "static constructors ran");
  check(fpu_on, "FPU enabled");

  g_note.start_tick = 0;
  g_note.duration_ticks = kNoteTicks;
  g_note.freq_q20 = hmp::synth::freq_to_q20(kNoteHz);
  g_note.amp_q16 = hmp::synth::amp_to_q16(kNoteAmp);
  g_note.preset = static_cast<std::uint8_t>(kPreset);
  const float amp = static_cast<float>(g_note.amp_q16) / 65535.0f;  // what the device can represent
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line().text("config: tick_hz=").u32(kTickHz).text(" note_hz=").u32(kNoteHz)
      .text(" amp=").fixed(amp).text(" preset=").text(hmp::envelope::name(kPreset))
      .text(" ticks=").u32(kNoteTicks).text(" tail=").u32(kTailTicks).print();
  // clang-format on

  // Ticks come from SysTick, as in the firmware; the core sleeps in between.
  reg(systick::kRvr) = kCoreHz / kTickHz - 1;
  reg(systick::kCvr) = 0;
  reg(systick::kCsr) = systick::kEnable | systick::kTickInt | systick::kCoreClock;
  while (g_tick < kTotalTicks) asm volatile("wfi" ::: "memory");
  reg(systick::kCsr) = 0;
  check(g_start_ok, "engine accepted the note");

  Line first;
  first.text("first:");
  for (std::uint32_t n = 0; n < 12; ++n) first.text(" ").fixed(g_samples[n]);
  first.print();

  // The end fade (design §6) shapes the last few ticks; there only the envelope bound applies.
  const auto fade_ticks = static_cast<std::uint32_t>(hmp::synth::SynthConfig{}.end_fade_ms * kTickHz / 1000.0f) + 1;
  float lo = 0.0f, hi = 0.0f, max_err = 0.0f;
  std::uint32_t up_crossings = 0, bound_violations = 0, tail_nonzero = 0;
  for (std::uint32_t n = 0; n < kTotalTicks; ++n) {
    const float y = g_samples[n];
    if (!(y == y)) ++bound_violations;  // NaN
    lo = y < lo ? y : lo;
    hi = y > hi ? y : hi;
    if (n > 0 && g_samples[n - 1] < 0.0f && y >= 0.0f) ++up_crossings;
    if (n >= kNoteTicks) {
      if (y != 0.0f) ++tail_nonzero;
      continue;
    }
    const float ref = reference(amp, n);
    if (n + fade_ticks < kNoteTicks) {
      const float err = std::fabs(y - ref);
      max_err = err > max_err ? err : max_err;
    } else if (std::fabs(y) > std::fabs(ref) + kSampleTolerance) {
      ++bound_violations;
    }
  }
  const float peak = hi > -lo ? hi : -lo;
  const std::uint32_t expected_crossings = kNoteHz * kNoteTicks / kTickHz;
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line().text("stats: min=").fixed(lo).text(" max=").fixed(hi).text(" peak=").fixed(peak)
      .text(" up_crossings=").u32(up_crossings).text(" max_err=").fixed(max_err, 7)
      .text(" checksum=").hex(fnv1a(g_samples, kTotalTicks)).print();
  // clang-format on
  const auto& c = g_engine.counters();
  // Laid out by hand (one log line, its fields side by side), so the formatter leaves it:
  // clang-format off
  Line().text("counters: started=").u32(c.started).text(" stolen=").u32(c.stolen)
      .text(" rejected=").u32(c.rejected).text(" active_after=").u32(g_engine.active_voices()).print();
  // clang-format on

  check(std::fabs(peak - amp) <= kPeakTolerance, "peak equals the note amplitude");
  check(std::fabs(hi + lo) <= kPeakTolerance, "waveform symmetric (max = -min)");
  check(max_err <= kSampleTolerance, "samples match a*sin(2 pi f n T) while the envelope is flat");
  check(bound_violations == 0, "end fade stays inside the envelope, no NaN");
  check(tail_nonzero == 0, "silence after the note ends");
  check(up_crossings + 1 >= expected_crossings && up_crossings <= expected_crossings + 1,
        "one upward zero crossing per period");
  check(c.started == 1 && c.stolen == 0 && c.rejected == 0, "engine counters");
  check(g_engine.active_voices() == 0, "voice released after the note");

  if (g_failures != 0) {
    Line().text("RESULT: FAIL (").u32(static_cast<std::uint32_t>(g_failures)).text(" checks)").print();
    return hmp::board::semihost::kExitCheckFailed;
  }
  Line().text("RESULT: PASS").print();
  return hmp::board::semihost::kExitOk;
}
