// bench_live_latency DEVICE NOTES HMP LOG: the latency of `hmp live` from a JACK MIDI event to the device's
// Started report for its note (tools/bench/live-latency.sh starts the JACK server). This program is a JACK
// client with a MIDI output port; it starts `hmp live --input <that port> --device DEVICE --log LOG`, waits
// for hmp to connect, then writes NOTES note-ons (and their note-offs), one every 8 ms at the start of a
// JACK cycle, keeping each event's JACK time (jack_get_time as the cycle writes it: µs of
// CLOCK_MONOTONIC_RAW), turned into the clock of hmp's log (the steady clock, CLOCK_MONOTONIC, which NTP
// slews: 250 ms apart on the VM measured) by the two clocks read side by side before and after the run.
// The i-th note-on of the log is the i-th one sent (checked by key). Prints JSON lines: p50, p99 and max of each stage
// — JACK event → hmp's MIDI callback, callback → Live report sent, sent → Started report taken — and of the whole, over
// the notes.
#include <jack/jack.h>
#include <jack/midiport.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/common/child_process.hpp"
#include "host/common/percentile.hpp"
#include "tools/bench/arguments.hpp"

namespace {

struct Sender {
  jack_client_t* client = nullptr;
  jack_port_t* port = nullptr;
  int notes = 0;
  jack_nframes_t spacing_frames = 0, countdown = 0;
  std::atomic<bool> go{false};
  std::atomic<int> sent{0};
  int pending_off = -1;               // the key to release at the next cycle
  std::vector<jack_time_t> event_us;  // per note-on: its JACK time
};

int process(jack_nframes_t frames, void* arg) {
  auto* s = static_cast<Sender*>(arg);
  void* buffer = jack_port_get_buffer(s->port, frames);
  jack_midi_clear_buffer(buffer);
  if (!s->go.load(std::memory_order_acquire)) return 0;
  if (s->pending_off >= 0) {
    const jack_midi_data_t off[3] = {0x80, static_cast<jack_midi_data_t>(s->pending_off), 0};
    jack_midi_event_write(buffer, 0, off, 3);
    s->pending_off = -1;
  }
  const int i = s->sent.load(std::memory_order_relaxed);
  if (i >= s->notes) return 0;
  if (s->countdown > frames) {
    s->countdown -= frames;
    return 0;
  }
  s->countdown = s->spacing_frames;
  const auto key = static_cast<jack_midi_data_t>(36 + i % 48);
  const jack_midi_data_t on[3] = {0x90, key, 100};
  if (jack_midi_event_write(buffer, 0, on, 3) == 0) {
    s->event_us[static_cast<std::size_t>(i)] = jack_get_time();
    s->pending_off = key;
    s->sent.store(i + 1, std::memory_order_release);
  }
  return 0;
}

// steady_clock − JACK's clock, in µs, read side by side (the smaller of a few tries' read spans).
double clock_offset_us() {
  double best_span = 1e9, offset = 0;
  for (int i = 0; i < 5; ++i) {
    const auto a = std::chrono::steady_clock::now();
    const jack_time_t j = jack_get_time();
    const auto b = std::chrono::steady_clock::now();
    const double span = std::chrono::duration<double, std::micro>(b - a).count();
    if (span >= best_span) continue;
    best_span = span;
    const double mid = std::chrono::duration<double, std::micro>((a + (b - a) / 2).time_since_epoch()).count();
    offset = mid - static_cast<double>(j);
  }
  return offset;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::fprintf(stderr, "usage: %s DEVICE NOTES HMP LOG [SPACING_MS]\n", argv[0]);
    return 2;
  }
  const std::string device = argv[1], hmp = argv[3], log = argv[4];
  Sender s;
  s.notes = static_cast<int>(hmp::bench::count_argument("NOTES", argv[2], 1, 1000000));
  // Between note-ons.
  const double spacing_s = (argc == 6 ? hmp::bench::number_argument("SPACING_MS", argv[5], 0.01, 60000) : 8.0) / 1000.0;
  s.event_us.resize(static_cast<std::size_t>(s.notes));
  jack_status_t status{};
  s.client = jack_client_open("hmp-bench", JackNoStartServer, &status);
  if (s.client == nullptr) {
    std::fprintf(stderr, "live-latency: no JACK server\n");
    return 1;
  }
  s.port = jack_port_register(s.client, "keys", JACK_DEFAULT_MIDI_TYPE, JackPortIsOutput, 0);
  s.spacing_frames = static_cast<jack_nframes_t>(spacing_s * jack_get_sample_rate(s.client));
  jack_set_process_callback(s.client, process, &s);
  if (s.port == nullptr || jack_activate(s.client) != 0) {
    std::fprintf(stderr, "live-latency: could not activate the JACK client\n");
    return 1;
  }
  const double seconds = 4.0 + s.notes * spacing_s;
  std::string error;
  const pid_t child =
      hmp::start_child({{"hmp", "live", "--api", "jack", "--no-audio", "--no-view", "--input", "hmp-bench:keys",
                         "--device", device, "--seconds", std::to_string(seconds), "--log", log, "--force"},
                        hmp,
                        "",
                        "/dev/null",
                        "/dev/null",
                        "",
                        true},
                       error);
  if (child < 0) {
    std::fprintf(stderr, "live-latency: %s\n", error.c_str());
    return 1;
  }
  for (int i = 0; i < 600 && jack_port_connected(s.port) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  if (jack_port_connected(s.port) == 0) {
    std::fprintf(stderr, "live-latency: hmp did not connect to hmp-bench:keys\n");
    hmp::stop_child(child, std::chrono::milliseconds(1000));
    return 1;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the device's ramp-in
  const double offset_before = clock_offset_us();
  const jack_time_t jack_before = jack_get_time();
  s.go.store(true, std::memory_order_release);
  const int rc = hmp::wait_child(child);
  const double offset_after = clock_offset_us();
  const jack_time_t jack_after = jack_get_time();
  // The offset at a JACK time, linear between the two readings.
  const auto to_steady = [&](jack_time_t t) {
    const double span = static_cast<double>(jack_after - jack_before);
    const double f = span > 0 ? static_cast<double>(t - jack_before) / span : 0.0;
    return static_cast<double>(t) + offset_before + f * (offset_after - offset_before);
  };
  const jack_nframes_t period = jack_get_buffer_size(s.client), rate = jack_get_sample_rate(s.client);
  jack_client_close(s.client);
  if (rc != 0) {
    std::fprintf(stderr, "live-latency: hmp live exited %d\n", rc);
    return 1;
  }
  std::vector<double> to_callback, to_sent, to_started, total;
  std::ifstream in(log);
  std::string line;
  // Note i has key 36 + i % 48: a logged note-on is the next sent note with its key. Sent notes skipped
  // on the way never reached hmp (JACK drops a cycle's events when a client misses it: an xrun).
  int i = 0, unmatched = 0, lost = 0;
  while (std::getline(in, line)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j.contains("summary")) continue;
    const int key = j["key"].get<int>();
    int next = i;
    while (next < s.sent.load() && 36 + next % 48 != key) ++next;
    if (next >= s.sent.load()) {
      ++unmatched;
      continue;
    }
    lost += next - i;
    i = next;
    if (j["started_us"].is_null()) {
      ++unmatched;
      ++i;
      continue;
    }
    const double event = to_steady(s.event_us[static_cast<std::size_t>(i)]);
    const double received = j["received_us"].get<double>(), sent = j["sent_us"].get<double>();
    const double started = j["started_us"].get<double>();
    to_callback.push_back((received - event) / 1000.0);
    to_sent.push_back((sent - received) / 1000.0);
    to_started.push_back((started - sent) / 1000.0);
    total.push_back((started - event) / 1000.0);
    ++i;
  }
  const auto emit = [&](const char* stage, const std::vector<double>& v) {
    for (const auto& [metric, p] : {std::pair{"p50", 50.0}, {"p99", 99.0}, {"max", 100.0}}) {
      nlohmann::json j = {{"bench", "live-latency"},
                          {"metric", std::string(stage) + "_" + metric},
                          {"value", hmp::percentile(v, p)},
                          {"unit", "ms"},
                          {"params",
                           {{"device", device},
                            {"notes", v.size()},
                            {"spacing_ms", spacing_s * 1000.0},
                            {"sent", s.sent.load()},
                            {"unmatched", unmatched},
                            {"lost_by_jack", lost},
                            {"jack_period_frames", period},
                            {"jack_rate_hz", rate},
                            {"clock_offset_ms", offset_before / 1000.0},
                            {"clock_drift_us", offset_after - offset_before}}}};
      std::printf("%s\n", j.dump().c_str());
    }
  };
  emit("jack_to_callback", to_callback);
  emit("callback_to_sent", to_sent);
  emit("sent_to_started", to_started);
  emit("total", total);
  return unmatched == 0 ? 0 : 1;
}
