#include "host/cli/song_options.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "host/common/error.hpp"
#include "host/midi/gm.hpp"

namespace hmp::cli {

namespace {
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string describe(const midi::Track& t) {
  return std::to_string(t.index) + " \"" + t.name + "\" (" + midi::gm_instrument_name(t.program(), t.channel()) + ")";
}
}  // namespace

std::uint32_t select_track(const midi::Song& song, const std::string& query) {
  if (song.tracks.empty()) throw BadInput("the song has no tracks");
  char* end = nullptr;
  const long index = std::strtol(query.c_str(), &end, 10);
  if (!query.empty() && *end == '\0') {
    if (index < 0 || static_cast<std::size_t>(index) >= song.tracks.size()) {
      throw BadInput("--track " + query + ": no such track (0–" + std::to_string(song.tracks.size() - 1) + ")");
    }
    return static_cast<std::uint32_t>(index);
  }
  const std::string q = lower(query);
  std::vector<const midi::Track*> matches;
  for (const midi::Track& t : song.tracks) {
    const std::string name = lower(t.name);
    const std::string instrument = lower(midi::gm_instrument_name(t.program(), t.channel()));
    if (t.note_count > 0 && (name == q || instrument == q) && matches.empty()) {
      // An exact match is unambiguous even when other names contain the text.
      bool unique_exact = true;
      for (const midi::Track& o : song.tracks) {
        if (&o != &t && o.note_count > 0 && lower(o.name) == q) unique_exact = false;
      }
      if (unique_exact && name == q) return t.index;
    }
    if (t.note_count > 0 && (name.find(q) != std::string::npos || instrument.find(q) != std::string::npos)) {
      matches.push_back(&t);
    }
  }
  if (matches.size() == 1) return matches.front()->index;
  std::string list;
  for (const midi::Track* t : matches.empty() ? std::vector<const midi::Track*>{} : matches) list += "; " + describe(*t);
  if (matches.empty()) {
    for (const midi::Track& t : song.tracks) {
      if (t.note_count > 0) list += "; " + describe(t);
    }
    throw BadInput("--track '" + query + "': no track matches (tracks with notes: " + list.substr(2) + ")");
  }
  throw BadInput("--track '" + query + "' is ambiguous (candidates: " + list.substr(2) + ")");
}

TrackWindow load_track_window(const std::string& song, const std::string& track, const haptics::HapticOptions& opts,
                              std::optional<double> from_s, std::optional<double> to_s) {
  for (const auto& t : {from_s, to_s}) {
    if (t && !(std::isfinite(*t) && *t >= 0)) throw BadInput("--from/--to: must be seconds ≥ 0");
  }
  TrackWindow w;
  w.read = midi::load_song(song);
  for (const midi::Warning& warning : w.read.warnings) std::fprintf(stderr, "warning: %s\n", warning.message.c_str());
  w.track = select_track(w.read.song, track);
  w.haptic = haptics::build_haptic_track(w.read.song, w.track, opts);
  std::uint64_t song_end = haptics::seconds_to_tick(w.read.song.duration_us, opts.tick_hz);
  for (const haptics::HapticNote& n : w.haptic.notes) {
    song_end = std::max(song_end, n.note.start_tick + n.note.duration_ticks);
  }
  const auto to_tick = [&](double s) { return haptics::seconds_to_tick(std::llround(s * 1e6), opts.tick_hz); };
  w.first_tick = from_s ? to_tick(*from_s) : 0;
  w.end_tick = to_s ? to_tick(*to_s) : song_end;
  if (w.end_tick <= w.first_tick) throw BadInput("--from/--to: empty window");
  return w;
}

std::pair<double, double> parse_range(const std::string& option, const std::string& text) {
  const auto colon = text.find(':');
  auto num = [&](const std::string& s) {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(v)) throw BadInput(option + " " + text + ": expected MIN:MAX");
    return v;
  };
  if (colon == std::string::npos) throw BadInput(option + " " + text + ": expected MIN:MAX");
  return {num(text.substr(0, colon)), num(text.substr(colon + 1))};
}

void add_haptic_options(CLI::App* cmd, HapticCliOptions& o) {
  cmd->add_option("--mapping", o.mapping, "Pitch mapping: paper (default), rank, constant, legacy2013");
  cmd->add_option("--freq-range", o.freq_range, "Haptic frequency range MIN:MAX in Hz (default 50:250)");
  cmd->add_option("--amp-range-db", o.amp_range_db, "Amplitude range MIN:MAX in dB, MAX = full scale (default 7.5:30)");
  cmd->add_option("--envelope", o.envelope,
                  "auto (the instrument's own, = analogue), square, triangle, or any preset name");
  cmd->add_option("--polyphony", o.polyphony, "Overlapping notes: sum (default), highest, latest");
  cmd->add_option("--end-fade-ms", o.end_fade_ms, "Fade at each note's end in ms (default 2, 0 = paper-exact)");
  cmd->add_option("--tick-hz", o.tick_hz, "Device tick rate in Hz (default 1000)")->check(CLI::Range(100u, 100000u));
  cmd->add_option("--config", o.config_path, "TOML file: user presets, GM table, ranges, device settings")
      ->check(CLI::ExistingFile);
}

haptics::HapticOptions resolve(const HapticCliOptions& o) {
  haptics::HapticOptions h;
  if (o.config_path) haptics::apply_config(config::load(*o.config_path), h);
  if (o.mapping && !mapping::find_mode(o.mapping->c_str(), h.mapping)) {
    throw BadInput("--mapping " + *o.mapping + ": unknown (paper, rank, constant, legacy2013)");
  }
  if (o.mapping && h.mapping == mapping::Mode::legacy2013 && !o.freq_range) {
    h.ranges.f_min_hz = mapping::kLegacyFminHz;
    h.ranges.f_max_hz = mapping::kLegacyFmaxHz;
  }
  if (o.freq_range) std::tie(h.ranges.f_min_hz, h.ranges.f_max_hz) = parse_range("--freq-range", *o.freq_range);
  if (o.amp_range_db) std::tie(h.ranges.a_min_db, h.ranges.a_max_db) = parse_range("--amp-range-db", *o.amp_range_db);
  if (o.envelope) h.envelope = lower(*o.envelope);
  if (o.polyphony && !synth::find_polyphony(o.polyphony->c_str(), h.polyphony)) {
    throw BadInput("--polyphony " + *o.polyphony + ": unknown (sum, highest, latest)");
  }
  if (o.end_fade_ms) h.end_fade_ms = *o.end_fade_ms;
  if (o.tick_hz) h.tick_hz = *o.tick_hz;
  haptics::validate(h);
  return h;
}

}  // namespace hmp::cli
