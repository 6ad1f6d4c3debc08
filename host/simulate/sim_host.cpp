// sim_host: the protocol host of the in-process simulated device, and a track's notes in a window.
#include "host/simulate/sim_host.hpp"

#include <algorithm>

namespace hmp::simulate {

void SimHost::send(protocol::Message m) {
  protocol::Report r;
  session_.number(m, r);
  dev_.deliver(r);
}

void SimHost::collect() {
  protocol::Report r;
  while (dev_.poll_report(r)) {
    protocol::Message m;
    if (protocol::decode(r, m) == protocol::ErrorCode::none && m.type == protocol::Type::status) {
      session_.on_status(m.status);
    }
  }
}

std::vector<synth::Note> window_notes(const haptics::HapticTrack& track, std::uint64_t first, std::uint64_t end,
                                      std::uint64_t base) {
  std::vector<synth::Note> out;
  for (synth::Note n : track.device_notes()) {
    const std::uint64_t stop = n.start_tick + n.duration_ticks;
    if (stop <= first || n.start_tick >= end) continue;
    const std::uint64_t start = std::max(n.start_tick, first);
    n.duration_ticks = static_cast<std::uint32_t>(std::min(stop, end) - start);
    n.start_tick = start - first + base;
    out.push_back(n);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const synth::Note& a, const synth::Note& b) { return a.start_tick < b.start_tick; });
  return out;
}

}  // namespace hmp::simulate
