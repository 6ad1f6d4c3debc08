// libFuzzer target for the Standard MIDI File reader (design §4: "never crash or hang"). BadInput is the
// reader's documented way to refuse a file and is expected; anything else escaping (another exception),
// a sanitizer report, a run over -timeout or a memory blow-up is a finding. Songs that are read must also
// be self-consistent, which catches silent corruption the sanitizers cannot see.
#include <cstddef>
#include <cstdint>
#include <span>

#include "host/common/error.hpp"
#include "host/midi/smf_reader.hpp"

namespace midi = hmp::midi;

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

void check_song(const midi::Song& s) {
  std::size_t counted = 0;
  for (std::size_t i = 0; i < s.tracks.size(); ++i) {
    const midi::Track& t = s.tracks[i];
    check(t.index == i);
    check(t.end_tick <= s.end_tick && t.end_us <= s.duration_us);
    check(t.note_count == 0 || (t.key_min() >= 0 && t.key_min() <= t.key_max() && t.key_max() < 128));
    std::size_t uses = 0;
    for (const midi::ProgramUse& p : t.programs) uses += p.notes;
    check(uses == t.note_count);
    counted += t.note_count;
  }
  check(counted == s.notes.size());
  for (const midi::Note& n : s.notes) {
    check(n.track < s.tracks.size());
    check(n.channel < 16 && n.key < 128 && n.velocity >= 1 && n.velocity < 128 && n.program < 128);
    check(n.start_tick <= n.end_tick && n.end_tick <= s.tracks[n.track].end_tick);
    // Integer µs from a monotonic tempo map: never negative, never decreasing.
    const std::int64_t start_us = s.start_us(n), end_us = s.end_us(n);
    check(0 <= start_us && start_us <= end_us && end_us <= s.duration_us);
  }
  check(!s.tempo_changes.empty() || s.division.smpte);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const midi::ReadResult r = midi::read_smf(std::span<const std::uint8_t>(data, size));
    check_song(r.song);
    for (const midi::Warning& w : r.warnings) check(!w.message.empty());
  } catch (const hmp::BadInput& e) {
    check(e.what()[0] != '\0');  // errors say what and where
  }
  return 0;
}
