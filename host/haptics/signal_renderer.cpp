#include "host/haptics/signal_renderer.hpp"

#include "host/common/error.hpp"

namespace hmp::haptics {

std::vector<float> render_signal(std::span<const synth::Note> notes, std::span<const UserPreset> presets,
                                 const RenderSettings& settings, std::uint64_t first_tick, std::uint64_t end_tick,
                                 const Progress& progress) {
  synth::Engine engine(settings.synth);
  engine.set_polyphony(settings.polyphony);
  for (const UserPreset& p : presets) {
    if (!engine.set_preset(p.slot, p.adsr))
      throw BadInput("invalid envelope preset for slot " + std::to_string(p.slot));
  }
  std::vector<float> out;
  if (end_tick <= first_tick) return out;
  out.reserve(static_cast<std::size_t>(end_tick - first_tick));

  // Notes that started before the window still sound in it: begin where the earliest of them starts.
  std::uint64_t tick = first_tick;
  for (const synth::Note& n : notes) {
    if (n.start_tick < first_tick && n.start_tick + n.duration_ticks > first_tick && n.start_tick < tick) {
      tick = n.start_tick;
    }
  }
  std::size_t next = 0;
  while (next < notes.size() && notes[next].start_tick < tick) ++next;  // ended before the window

  const std::uint64_t total = end_tick - tick;
  const std::uint64_t report_every = 1u << 16;
  for (; tick < end_tick; ++tick) {
    while (next < notes.size() && notes[next].start_tick == tick) engine.start(notes[next++]);
    const float y = engine.tick();
    if (tick >= first_tick) out.push_back(y);
    if (progress && (tick % report_every) == 0) progress(total - (end_tick - tick), total);
  }
  if (progress) progress(total, total);
  return out;
}

}  // namespace hmp::haptics
