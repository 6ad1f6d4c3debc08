// e2e-timing, audio–haptic skew (design §10: ≤ 1 ms end to end). `hmp play`'s player runs in this process
// with its real audio path (FluidSynth, the GM SoundFont, the audio clock fitted from the card's
// callbacks) on a virtual sound card (host/audio/virtual_card.hpp: 100 ppm fast crystal, 256 × 4
// frames of buffering) and the simulated device in real time. Both sides have a known truth:
//   - the card knows when each frame it played is heard; its recording gives where each note's sound
//     starts (first sample at −60 dB of the note's peak, the onset definition of docs/host.md);
//   - the simulated device's tick k is due at a known host time (SimTransport::tick_due_at), and its
//     Started reports say on which tick each note began.
// skew = haptic onset − audio onset, for every note. The song is made here: one track of isolated
// notes (so that each onset can be found in the mix) on six instruments with different attacks, at
// times that fall anywhere between audio blocks and device ticks. Effects are off (a reverb tail would
// hide the next onset). A real card adds the error of its driver's latency report, which no software
// measurement can see.
//
// Usage: bench_audio_haptic_skew NOTES   (JSON lines on stdout, design §2; ~0.6 s a note)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "host/audio/audio_events.hpp"
#include "host/audio/audio_player.hpp"
#include "host/audio/soundfont.hpp"
#include "host/midi/smf_reader.hpp"
#include "host/player/device_link.hpp"
#include "host/player/player.hpp"
#include "host/transport/sim_transport.hpp"
#include "tests/support/audio_onset.hpp"
#include "tools/bench/arguments.hpp"

namespace {

constexpr int kDivision = 25'000;  // ticks per quarter note: 20 µs per tick at 120 bpm
constexpr std::uint32_t kTempoUs = 500'000;
constexpr double kTickUs = static_cast<double>(kTempoUs) / kDivision;
constexpr std::int64_t kSpacingUs =
    1'500'000;  // note to note, ±50 ms: every release tail is below −60 dB by the next note
constexpr std::int64_t kLengthUs = 80'000;

void put_vlq(std::vector<std::uint8_t>& out, std::uint32_t v) {
  std::uint8_t bytes[5];
  int n = 0;
  do {
    bytes[n++] = static_cast<std::uint8_t>(v & 0x7F);
    v >>= 7;
  } while (v != 0);
  while (n-- > 0) out.push_back(static_cast<std::uint8_t>(bytes[n] | (n > 0 ? 0x80 : 0)));
}

// A format-0 file: one channel, isolated notes, each with a program change before it.
std::string write_song(int notes, std::uint32_t seed) {
  // Piano, xylophone, nylon guitar, trumpet, flute, violin: attacks from instant to slow. (An organ's
  // release tail is still at −60 dB of the next note 1.5 s later, which hides that note's onset.)
  const std::uint8_t programs[] = {0, 13, 24, 56, 73, 40};
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> jitter(-50'000, 50'000), key(52, 84);
  std::vector<std::uint8_t> track = {0x00,
                                     0xFF,
                                     0x51,
                                     0x03,
                                     static_cast<std::uint8_t>(kTempoUs >> 16),
                                     static_cast<std::uint8_t>(kTempoUs >> 8),
                                     static_cast<std::uint8_t>(kTempoUs)};
  std::uint32_t now = 0;
  for (int i = 0; i < notes; ++i) {
    const std::int64_t start_us = 700'000 + i * kSpacingUs + jitter(rng);
    const auto start = static_cast<std::uint32_t>(std::llround(static_cast<double>(start_us) / kTickUs));
    const auto end = start + static_cast<std::uint32_t>(kLengthUs / kTickUs);
    const auto k = static_cast<std::uint8_t>(key(rng));
    put_vlq(track, start - now);
    track.insert(track.end(), {0xC0, programs[i % 6], 0x00, 0x90, k, 100});
    put_vlq(track, end - start);
    track.insert(track.end(), {0x80, k, 0});
    now = end;
  }
  track.insert(track.end(), {0x00, 0xFF, 0x2F, 0x00});
  std::vector<std::uint8_t> file = {'M', 'T', 'h', 'd', 0, 0, 0, 6, 0, 0, 0, 1, kDivision >> 8, kDivision & 0xFF,
                                    'M', 'T', 'r', 'k'};
  const auto size = static_cast<std::uint32_t>(track.size());
  for (int shift = 24; shift >= 0; shift -= 8) file.push_back(static_cast<std::uint8_t>(size >> shift));
  file.insert(file.end(), track.begin(), track.end());
  const auto path = std::filesystem::temp_directory_path() / ("hmp-skew-" + std::to_string(::getpid()) + ".mid");
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
  return path.string();
}

void emit(const char* metric, double value, const char* unit, const std::string& params) {
  std::printf("{\"bench\":\"e2e-timing\",\"metric\":\"%s\",\"value\":%.6g,\"unit\":\"%s\",\"params\":{%s}}\n", metric,
              value, unit, params.c_str());
}

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(a - b).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s NOTES\n", argv[0]);
    return 2;
  }
  const auto notes = static_cast<int>(hmp::bench::count_argument("NOTES", argv[1], 1, 100000));
  if (!hmp::audio::find_soundfont()) {
    std::fprintf(stderr, "audio-haptic skew: no GM SoundFont installed (fluid-soundfont-gm): skipped\n");
    return 0;
  }
  const bool verbose = std::getenv("HMP_SKEW_VERBOSE") != nullptr;  // one stderr line a note
  const std::string path = write_song(notes, 20261121);
  const hmp::midi::Song song = hmp::midi::load_song(path).song;
  std::filesystem::remove(path);

  hmp::transport::SimTransport sim;
  hmp::player::DeviceLink link(sim);
  link.connect();
  hmp::audio::AudioOptions audio_options;
  audio_options.drivers = {"virtual"};
  audio_options.virtual_ppm = 100.0;
  audio_options.synth.reverb = audio_options.synth.chorus = false;
  const double song_s = static_cast<double>(notes * kSpacingUs + 2'000'000) * 1e-6;
  audio_options.virtual_record_frames = static_cast<std::size_t>(song_s * audio_options.synth.sample_rate);
  hmp::audio::AudioPlayer audio(audio_options);
  if (!audio.audible() || audio.virtual_card() == nullptr) {
    std::fprintf(stderr, "audio-haptic skew: the virtual card did not start (%s)\n", audio.silence_reason().c_str());
    return 1;
  }
  audio.set_events(hmp::audio::audio_events(song));

  hmp::player::PlayerOptions options;
  options.track = 0;
  std::vector<hmp::player::StartedNote> started;
  options.on_started = [&](const hmp::player::StartedNote& n) { started.push_back(n); };
  hmp::player::Player player(link, audio, song, options);
  player.run();

  const hmp::audio::VirtualCard& card = *audio.virtual_card();
  const std::vector<float> level = card.recording();
  const int rate = audio_options.synth.sample_rate;
  std::vector<double> skews_ms;
  for (const hmp::player::StartedNote& n : started) {
    const auto haptic = sim.tick_due_at(n.actual_tick);
    // Where to look: the card's frame heard at the haptic onset.
    const double frame_at_haptic =
        seconds_between(haptic, card.heard_at(0)) * rate * (1 + audio_options.virtual_ppm * 1e-6);
    const std::int64_t onset = hmp::test::onset_frame(level, std::llround(frame_at_haptic), rate);
    if (onset < 0) continue;
    skews_ms.push_back(seconds_between(haptic, card.heard_at(static_cast<double>(onset))) * 1e3);
    if (verbose) {
      std::fprintf(stderr, "note at %.3f s, key %d: device tick %llu, sound at card frame %lld, skew %+.3f ms\n",
                   n.origin.start_s, n.origin.key, static_cast<unsigned long long>(n.actual_tick),
                   static_cast<long long>(onset), skews_ms.back());
    }
  }
  std::sort(skews_ms.begin(), skews_ms.end());
  const std::string params =
      "\"device\":\"sim\",\"audio\":\"virtual card, +100 ppm, 256x4 frames at 48 kHz\",\"notes\":" +
      std::to_string(skews_ms.size()) + ",\"of\":" + std::to_string(notes);
  if (skews_ms.empty()) {
    std::fprintf(stderr, "audio-haptic skew: no onset found\n");
    return 1;
  }
  double mean = 0, max_abs = 0;
  for (const double s : skews_ms) {
    mean += s;
    max_abs = std::max(max_abs, std::fabs(s));
  }
  mean /= static_cast<double>(skews_ms.size());
  emit("audio_haptic_skew_max_abs", max_abs, "ms", params);
  emit("audio_haptic_skew_mean", mean, "ms", params);
  emit("audio_haptic_skew_min", skews_ms.front(), "ms", params);
  emit("audio_haptic_skew_max", skews_ms.back(), "ms", params);
  emit("card_underruns", static_cast<double>(card.underruns()), "count", params);
  emit("audio_clock_restarts", static_cast<double>(audio.clock_restarts()), "count", params);
  emit("audio_clock_speed_error", (audio.clock_speed() - 1.0) * 1e6, "ppm", params + ",\"true\":100");
  return max_abs <= 1.0 ? 0 : 1;
}
