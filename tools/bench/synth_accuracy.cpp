// synth-accuracy: error and speed of one voice for each sine implementation (design §7).
// Error: the voice over a 10-minute note against the double-precision reference of design §6,
// E(x)·sin(2π f x) for the frequency the device represents; the max over several presets and
// frequencies at full amplitude. Speed: host ns per voice sample and per sine call (a proxy for the MCU).
// Prints JSON lines (see scripts/bench). Usage: bench_synth_accuracy [--note-s S] [--tick-hz HZ]…
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "shared/envelope/envelope.hpp"
#include "shared/synth/frequency.hpp"
#include "shared/synth/sine.hpp"
#include "shared/synth/voice.hpp"
#include "tests/support/reference_envelope.hpp"
#include "tools/bench/arguments.hpp"

namespace {

using namespace hmp;
using Clock = std::chrono::steady_clock;

constexpr double kTwoPi = 6.283185307179586476925;
constexpr synth::SineImpl kImpls[] = {synth::SineImpl::libm, synth::SineImpl::table, synth::SineImpl::poly};
// Square exposes the sine at full scale for the whole note; the others add every envelope phase.
constexpr envelope::Preset kPresets[] = {envelope::Preset::square, envelope::Preset::violin,
                                         envelope::Preset::harpsichord, envelope::Preset::triangle};
constexpr double kFrequencies[] = {50.0, 173.205080757, 249.9};

struct Run {
  std::uint32_t tick_hz;
  std::uint32_t ticks;
  float end_fade_ms;
};

synth::Note full_scale_note(double hz, std::uint32_t ticks) {
  synth::Note n;
  n.duration_ticks = ticks;
  n.freq_q20 = synth::freq_to_q20(hz);
  n.amp_q16 = synth::amp_to_q16(1.0);
  return n;
}

double max_error(synth::SineImpl impl, const Run& run) {
  const synth::SynthConfig cfg{run.tick_hz, run.end_fade_ms, impl};
  const double tick_ms = 1000.0 / run.tick_hz;
  const double d_ms = run.ticks * tick_ms;
  double worst = 0.0;
  for (envelope::Preset preset : kPresets) {
    for (double hz : kFrequencies) {
      const synth::Note note = full_scale_note(hz, run.ticks);
      const double f = synth::q20_to_hz(note.freq_q20);  // the frequency the device represents
      const double peak = static_cast<double>(synth::q16_to_amp(note.amp_q16));
      synth::Voice v;
      v.start(note, envelope::builtin(preset), cfg, 0);
      for (std::uint32_t n = 0; n < run.ticks; ++n) {
        const double x_ms = n * tick_ms;
        const double expected =
            reference::envelope(envelope::builtin(preset), peak, d_ms, x_ms, static_cast<double>(run.end_fade_ms)) *
            std::sin(kTwoPi * f * (x_ms / 1000.0));
        worst = std::max(worst, std::fabs(static_cast<double>(v.next()) - expected));
      }
    }
  }
  return worst;
}

double elapsed_ns(Clock::time_point t0) { return std::chrono::duration<double, std::nano>(Clock::now() - t0).count(); }

volatile float g_sink;  // keeps the timed loops from being optimised away

// Host ns per voice sample (sine + envelope + phase): the whole note, one voice.
double time_voice(synth::SineImpl impl, const Run& run) {
  const synth::SynthConfig cfg{run.tick_hz, run.end_fade_ms, impl};
  const synth::Note note = full_scale_note(173.205080757, run.ticks);
  const auto t0 = Clock::now();
  synth::Voice v;
  v.start(note, envelope::builtin(envelope::Preset::violin), cfg, 0);
  float acc = 0.0f;
  for (std::uint32_t n = 0; n < run.ticks; ++n) acc += v.next();
  g_sink = acc;
  return elapsed_ns(t0) / run.ticks;
}

// Host ns per sine call, throughput: independent calls into a buffer, so no dependency chain sets the pace.
double time_sine(synth::SineImpl impl) {
  static float out[1u << 16];
  constexpr std::uint32_t kRounds = 64;
  const auto t0 = Clock::now();
  std::uint32_t phase = 0;
  for (std::uint32_t r = 0; r < kRounds; ++r) {
    for (float& y : out) y = synth::sine(impl, phase += 0x9E3779B9u);
    g_sink = out[r];
  }
  return elapsed_ns(t0) / (kRounds * (1u << 16));
}

void emit(const char* metric, double value, const char* unit, synth::SineImpl impl, double note_s,
          std::uint32_t tick_hz) {
  std::printf(
      "{\"bench\":\"synth-accuracy\",\"metric\":\"%s\",\"value\":%.4g,\"unit\":\"%s\","
      "\"params\":{\"impl\":\"%s\",\"note_s\":%g,\"tick_hz\":%u}}\n",
      metric, value, unit, synth::name(impl), note_s, tick_hz);
  std::fflush(stdout);
}

[[noreturn]] void usage() {
  std::fprintf(stderr, "usage: bench_synth_accuracy [--note-s SECONDS] [--tick-hz HZ]...\n");
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  double note_s = 600.0;
  std::vector<std::uint32_t> rates;
  for (int i = 1; i < argc; i += 2) {  // every option takes a value
    if (i + 1 >= argc) usage();
    if (std::strcmp(argv[i], "--note-s") == 0) {
      note_s = hmp::bench::number_argument("--note-s", argv[i + 1], 0.001, 1e6);
    } else if (std::strcmp(argv[i], "--tick-hz") == 0) {
      rates.push_back(static_cast<std::uint32_t>(hmp::bench::count_argument("--tick-hz", argv[i + 1], 1, 100000)));
    } else {
      usage();
    }
  }
  if (rates.empty()) rates = {1000, 10000};

  constexpr std::size_t kImplCount = sizeof kImpls / sizeof kImpls[0];
  for (std::uint32_t tick_hz : rates) {
    const Run run{tick_hz, static_cast<std::uint32_t>(std::llround(note_s * tick_hz)),
                  synth::SynthConfig{}.end_fade_ms};
    // Timing: the implementations take turns, best of several rounds, so a busy neighbour on a shared
    // machine slows them alike and the fastest undisturbed run counts.
    double voice_ns[kImplCount], sine_ns[kImplCount];
    std::fill(voice_ns, voice_ns + kImplCount, 1e300);
    std::fill(sine_ns, sine_ns + kImplCount, 1e300);
    for (int round = 0; round < 7; ++round) {
      for (std::size_t i = 0; i < kImplCount; ++i) {
        voice_ns[i] = std::min(voice_ns[i], time_voice(kImpls[i], run));
        sine_ns[i] = std::min(sine_ns[i], time_sine(kImpls[i]));
      }
    }
    for (std::size_t i = 0; i < kImplCount; ++i) {
      emit("max_abs_error", max_error(kImpls[i], run), "full_scale", kImpls[i], note_s, tick_hz);
      emit("ns_per_sample", voice_ns[i], "ns", kImpls[i], note_s, tick_hz);
      emit("sine_ns_per_call", sine_ns[i], "ns", kImpls[i], note_s, tick_hz);
    }
  }
  return 0;
}
