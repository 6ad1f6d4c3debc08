#pragma once
// sim_host: what `hmp sim` sends to the in-process simulated device — the protocol host (the session rules
// of transport::HostSession: numbering and credit) and the haptic track's notes within a window.
#include <cstdint>
#include <vector>

#include "boards/sim/sim_device.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/transport/host_session.hpp"
#include "shared/protocol/protocol.hpp"

namespace hmp::simulate {

class SimHost {
 public:
  explicit SimHost(sim::SimDevice& dev) : dev_(dev) {}
  void send(protocol::Message m);
  // Reads what the device said; its Statuses give the room and the processed reports (the device's
  // faults are read from the core after the run).
  void collect();
  int credit() const { return session_.credit(); }

 private:
  sim::SimDevice& dev_;
  transport::HostSession session_;
};

// The notes overlapping song ticks [first, end), clipped to it and moved to start at device tick `base`,
// in start order (ties keep the track's order).
std::vector<synth::Note> window_notes(const haptics::HapticTrack& track, std::uint64_t first, std::uint64_t end,
                                      std::uint64_t base);

}  // namespace hmp::simulate
