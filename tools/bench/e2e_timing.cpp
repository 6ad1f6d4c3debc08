// e2e-timing, clock part (design §10): how far the player's estimate of the device clock is from the
// simulated device's real clock while a song plays. The simulated device runs in this process, so its
// tick counter can be read directly, with no link in between: at host time t the device has processed
// tick k = floor(true position) (or a little less when its thread is late), so over a window the
// smallest (estimate − k) is the estimate's error. The player's own notes use the same estimate: their
// onset error against the song's host time is this error plus the rounding to a tick (≤ ½ tick).
//
// Usage: bench_e2e_timing SONG TRACK SECONDS   (JSON lines on stdout, design §2)
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "host/audio/audio_player.hpp"
#include "host/midi/smf_reader.hpp"
#include "host/player/device_link.hpp"
#include "host/player/player.hpp"
#include "host/transport/sim_transport.hpp"
#include "tools/bench/arguments.hpp"

namespace {

void emit(const char* metric, double value, const char* unit, const std::string& params) {
  std::printf("{\"bench\":\"e2e-timing\",\"metric\":\"%s\",\"value\":%.6g,\"unit\":\"%s\",\"params\":{%s}}\n", metric,
              value, unit, params.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s SONG TRACK SECONDS\n", argv[0]);
    return 2;
  }
  const auto track = static_cast<std::uint32_t>(hmp::bench::count_argument("TRACK", argv[2], 0, 65535));
  const double seconds = hmp::bench::number_argument("SECONDS", argv[3], 0.001, 86400);
  const hmp::midi::Song song = hmp::midi::load_song(argv[1]).song;

  hmp::transport::SimTransport sim;
  hmp::player::DeviceLink link(sim);
  link.connect();
  hmp::audio::AudioOptions silent;
  silent.enabled = false;
  hmp::audio::AudioPlayer audio(silent);
  hmp::player::PlayerOptions options;
  options.track = track;
  options.to_us = static_cast<std::int64_t>(seconds * 1e6);
  std::vector<hmp::player::StartedNote> started;
  options.on_started = [&](const hmp::player::StartedNote& n) { started.push_back(n); };
  hmp::player::Player player(link, audio, song, options);

  std::atomic<bool> done{false};
  std::thread run([&] {
    player.run();
    done = true;
  });
  // One window per second: the smallest (estimate − processed tick) of ~50 readings.
  std::vector<double> window_errors;
  double window_min = 1e9;
  auto window_end = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (!done) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto [now, tick] =
        sim.with_device([](hmp::sim::SimDevice& d) { return std::make_pair(hmp::player::steady_us(), d.tick()); });
    const std::optional<double> estimate = link.position(now);
    if (estimate && link.sync_samples() >= 4) window_min = std::min(window_min, *estimate - static_cast<double>(tick));
    if (std::chrono::steady_clock::now() >= window_end) {
      if (window_min < 1e8) window_errors.push_back(window_min);
      window_min = 1e9;
      window_end += std::chrono::seconds(1);
    }
  }
  run.join();

  const double tick_ms = 1000.0 / link.hello().tick_hz;
  const std::string params = "\"device\":\"sim\",\"track\":" + std::to_string(track) +
                             ",\"seconds\":" + std::to_string(static_cast<int>(seconds)) +
                             ",\"windows\":" + std::to_string(window_errors.size());
  double max_abs = 0, mean = 0;
  for (const double e : window_errors) {
    max_abs = std::max(max_abs, std::fabs(e));
    mean += e;
  }
  if (!window_errors.empty()) mean /= static_cast<double>(window_errors.size());
  emit("sync_error_max_abs", max_abs * tick_ms, "ms", params);
  emit("sync_error_mean", mean * tick_ms, "ms", params);
  // Audio-haptic skew from the haptic side: clock error plus rounding to the tick grid (silent audio
  // clock = host clock; with a sound card add the audio side, docs/host.md).
  emit("haptic_skew_bound", max_abs * tick_ms + 0.5 * tick_ms, "ms", params);
  emit("sync_best_transit", link.best_transit_us(), "us", params);
  std::uint64_t late = 0, max_err = 0;
  for (const auto& n : started) {
    const std::uint64_t e = n.actual_tick - n.scheduled_tick;
    max_err = std::max(max_err, e);
    late += e > 0 ? 1 : 0;
  }
  emit("onset_error_max", static_cast<double>(max_err), "ticks",
       params + ",\"notes\":" + std::to_string(started.size()));
  return late == 0 ? 0 : 1;
}
