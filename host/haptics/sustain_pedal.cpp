#include "host/haptics/sustain_pedal.hpp"

#include <algorithm>
#include <array>
#include <limits>

namespace hmp::haptics {
namespace {

struct Held {
  std::uint64_t down = 0, up = 0;  // the pedal is down on [down, up)
};

// Per channel, the spans the pedal is down, in time order (a lift that never comes: the song's end).
std::array<std::vector<Held>, 16> pedal_spans(const midi::Song& song) {
  std::array<std::vector<Held>, 16> spans;
  std::array<bool, 16> down{};
  for (const midi::Control& c : song.controls) {
    if (c.kind != midi::Control::Kind::controller) continue;
    const bool sustain = c.number == 64, reset = c.number == 121;
    if (!sustain && !reset) continue;
    const std::size_t ch = c.channel & 0x0F;
    const bool now_down = sustain && c.value >= 64;
    if (now_down && !down[ch]) spans[ch].push_back({c.tick, std::numeric_limits<std::uint64_t>::max()});
    if (!now_down && down[ch]) spans[ch].back().up = c.tick;
    down[ch] = now_down;
  }
  for (auto& channel : spans) {
    for (Held& h : channel) h.up = std::min(h.up, std::max(song.end_tick, h.down));
  }
  return spans;
}

}  // namespace

std::vector<std::uint64_t> pedal_end_ticks(const midi::Song& song, const std::vector<midi::Note>& notes) {
  const auto spans = pedal_spans(song);
  // The starts of each key on each channel, sorted: a held note stops where its key is struck again.
  std::vector<std::vector<std::uint64_t>> starts(16 * 128);
  for (const midi::Note& n : notes) starts[(n.channel & 0x0FU) * 128 + (n.key & 0x7FU)].push_back(n.start_tick);
  for (auto& s : starts) std::sort(s.begin(), s.end());

  std::vector<std::uint64_t> ends(notes.size());
  for (std::size_t i = 0; i < notes.size(); ++i) {
    const midi::Note& n = notes[i];
    ends[i] = n.end_tick;
    const std::vector<Held>& held = spans[n.channel & 0x0F];
    // The span holding the release: the last one that went down at or before it.
    auto it = std::upper_bound(held.begin(), held.end(), n.end_tick,
                               [](std::uint64_t t, const Held& h) { return t < h.down; });
    if (it == held.begin()) continue;
    --it;
    if (n.end_tick >= it->up) continue;  // the pedal was up again by the release
    // The first strike of the key at or after the release (a strike while the key was still held does not
    // end the note's pedalled part; one after it does).
    const std::vector<std::uint64_t>& key_starts = starts[(n.channel & 0x0FU) * 128 + (n.key & 0x7FU)];
    const auto next = std::lower_bound(key_starts.begin(), key_starts.end(), std::max(n.end_tick, n.start_tick + 1));
    const std::uint64_t cut = next == key_starts.end() ? std::numeric_limits<std::uint64_t>::max() : *next;
    ends[i] = std::max(n.end_tick, std::min(it->up, cut));
  }
  return ends;
}

}  // namespace hmp::haptics
