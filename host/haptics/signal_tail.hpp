#pragma once
// The last moments of a haptic track's signal, for the view's vibration strip: the samples the device
// plays in the ticks just before a song time, rendered with the shared engine (signal_renderer.hpp) from
// only the notes that can still sound then, so a frame's cost does not grow with the song.
#include <cstdint>
#include <memory>
#include <vector>

#include "host/haptics/haptic_track.hpp"
#include "host/haptics/signal_renderer.hpp"
#include "shared/synth/tick_rate.hpp"

namespace hmp::haptics {

class SignalTail {
 public:
  SignalTail(std::shared_ptr<const HapticTrack> track, const HapticOptions& opts);
  const HapticTrack* track() const { return track_.get(); }
  // Fills out[0 .. n) with the samples of the ticks (song_us's tick − n, song_us's tick], n ≤ max.
  int samples(std::int64_t song_us, float* out, int max) const;

 private:
  std::shared_ptr<const HapticTrack> track_;
  std::vector<synth::Note> notes_;  // the track's device notes, by start
  std::uint64_t longest_ = 0;       // the longest note's ticks (how far back a sounding note can start)
  RenderSettings settings_;
  std::uint32_t tick_hz_ = synth::kNominalTickHz;
};

}  // namespace hmp::haptics
