#pragma once
// Renders the haptic signal of a list of notes tick by tick with the same shared engine the firmware
// runs (shared/synth/engine.hpp): notes start on their tick, voices mix under the polyphony policy and
// the limiter. Used by `hmp tone` and `hmp render`.
// Output formats: host/export/signal_export.hpp.
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "shared/envelope/envelope.hpp"
#include "shared/synth/engine.hpp"

namespace hmp::haptics {

struct RenderSettings {
  synth::SynthConfig synth{};
  synth::Polyphony polyphony = synth::Polyphony::sum;
};

struct UserPreset {
  std::uint8_t slot = envelope::kFirstUserSlot;
  envelope::Adsr adsr{};
};

// progress(done_ticks, total_ticks) is called now and then for long renders; may be empty.
using Progress = std::function<void(std::uint64_t, std::uint64_t)>;

// Samples for ticks [first_tick, end_tick). `notes` must be sorted by start_tick. A note starting
// before first_tick is started at its own tick and advanced silently, so a window shows exactly what
// the full render would.
std::vector<float> render_signal(std::span<const synth::Note> notes, std::span<const UserPreset> presets,
                                 const RenderSettings& settings, std::uint64_t first_tick, std::uint64_t end_tick,
                                 const Progress& progress = {});

}  // namespace hmp::haptics
