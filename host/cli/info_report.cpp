// hmp info: what is in a song (design §3), the table or the JSON object. See info_report.hpp.
#include "host/cli/info_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "host/cli/run_command.hpp"
#include "host/common/error.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/midi/smf_reader.hpp"
#include "host/midi/gm.hpp"
#include "host/midi/key_name.hpp"

namespace hmp::cli {

namespace {

std::string channels_text(const midi::Track& t) {
  std::string out;
  for (std::uint8_t c = 0; c < 16; ++c) {
    if (t.has_channel(c)) out += (out.empty() ? "" : ",") + std::to_string(c + 1);
  }
  return out.empty() ? "-" : out;
}

// JND steps the track's keys span under the `rank` mapping with the default ranges (design §5).
double rank_jnd_steps(const midi::Track& t) {
  return mapping::Mapper(mapping::Mode::rank, mapping::Ranges{}, t.keys).jnd_steps();
}

// The frequencies the mapping gives a track's pitched keys, lowest and highest (design §5): under the song
// scope a bass track's span sits low in the range and a treble one's high.
struct FrequencySpan {
  bool any = false;
  double lo = 0, hi = 0;
};

// `song_keys`: the song's pitched keys (haptics::pitched_keys), found once for every track.
FrequencySpan frequency_span(const midi::Song& s, const midi::Track& t, const haptics::HapticOptions& opts,
                             const mapping::KeySet& song_keys) {
  // A track without drum notes has exactly its own keys as pitched keys: no pass over the song needed.
  const mapping::KeySet own = t.has_channel(midi::kDrumChannel) ? haptics::pitched_keys(s, t.index) : t.keys;
  const bool song_scope = haptics::key_scope_of(opts) == haptics::KeyScope::song;
  const mapping::Mapper mapper(opts.mapping, opts.ranges, song_scope ? song_keys : own);
  FrequencySpan span;
  for (int k = own.min(); k >= 0 && k <= own.max(); ++k) {
    if (!own.contains(static_cast<std::uint8_t>(k))) continue;
    const double f = mapper.map(static_cast<std::uint8_t>(k)).freq_hz;
    span.lo = span.any ? std::min(span.lo, f) : f;
    span.hi = span.any ? std::max(span.hi, f) : f;
    span.any = true;
  }
  if (!span.any && t.note_count > 0) {  // drums only
    span.lo = span.hi = haptics::drum_haptic(opts.ranges).freq_hz;
    span.any = true;
  }
  return span;
}

// The preset the track's first program plays with under --envelope ("-" where --envelope measured has
// none for it: playing it would say so).
std::string envelope_of(const midi::Track& t, const haptics::HapticOptions& opts) {
  if (t.note_count == 0) return "";
  try {
    return haptics::note_preset_name(opts, t.program(), t.channel());
  } catch (const BadInput&) {
    return "-";
  }
}

std::string span_text(const FrequencySpan& f) {
  if (!f.any) return "-";
  return f.lo == f.hi ? fmt::format("{:.0f}", f.lo) : fmt::format("{:.0f}–{:.0f}", f.lo, f.hi);
}

nlohmann::json track_json(const midi::Song& s, const midi::Track& t, const haptics::HapticOptions& opts,
                          const mapping::KeySet& song_keys) {
  nlohmann::json channels = nlohmann::json::array();
  for (std::uint8_t c = 0; c < 16; ++c) {
    if (t.has_channel(c)) channels.push_back(c + 1);
  }
  nlohmann::json programs = nlohmann::json::array();
  for (const midi::ProgramUse& p : t.programs) {
    programs.push_back({{"channel", p.channel + 1},
                        {"program", p.program},
                        {"name", midi::gm_instrument_name(p.program, p.channel)},
                        {"notes", p.notes}});
  }
  const FrequencySpan span = frequency_span(s, t, opts, song_keys);
  return {{"index", t.index},
          {"name", t.name},
          {"channels", channels},
          {"program", t.program()},
          {"instrument", midi::gm_instrument_name(t.program(), t.channel())},
          {"programs", programs},
          {"note_count", t.note_count},
          {"key_min", t.key_min()},
          {"key_max", t.key_max()},
          {"distinct_keys", t.distinct_keys()},
          {"envelope", envelope_of(t, opts)},
          {"freq_min_hz", span.any ? nlohmann::json(span.lo) : nlohmann::json()},
          {"freq_max_hz", span.any ? nlohmann::json(span.hi) : nlohmann::json()},
          {"rank_jnd_steps", rank_jnd_steps(t)},
          {"jnd_per_key_step", t.distinct_keys() > 1 ? rank_jnd_steps(t) / (t.distinct_keys() - 1) : 0.0},
          {"controllers", midi::controllers_used(s, t.index)},
          {"end_s", static_cast<double>(t.end_us) * 1e-6}};
}

}  // namespace

int run_info(const InfoOptions& o) {
  const midi::ReadResult r = midi::load_song(o.song);
  const midi::Song& s = r.song;
  const haptics::HapticOptions opts = resolve(o.haptic);
  const mapping::KeySet song_keys = haptics::pitched_keys(s);
  const char* scope = haptics::name(haptics::key_scope_of(opts));

  if (o.json) {
    nlohmann::json j;
    j["file"] = o.song;
    j["format"] = s.format;
    j["division"] = s.division.smpte
                        ? nlohmann::json{{"smpte_fps", s.division.fps}, {"ticks_per_frame", s.division.ticks_per_frame}}
                        : nlohmann::json{{"ticks_per_quarter", s.division.ticks_per_quarter}};
    j["duration_s"] = s.duration_s();
    j["mapping"] = {{"mode", mapping::name(opts.mapping)},
                    {"key_scope", scope},
                    {"freq_range_hz", {opts.ranges.f_min_hz, opts.ranges.f_max_hz}}};
    j["song_keys"] = {{"key_min", song_keys.min()}, {"key_max", song_keys.max()}, {"distinct_keys", song_keys.count()}};
    j["tracks"] = nlohmann::json::array();
    for (const midi::Track& t : s.tracks) j["tracks"].push_back(track_json(s, t, opts, song_keys));
    j["tempo_changes"] = nlohmann::json::array();
    for (const midi::TempoChange& c : s.tempo_changes) {
      j["tempo_changes"].push_back({{"tick", c.tick}, {"time_s", static_cast<double>(c.us) * 1e-6}, {"bpm", c.bpm()}});
    }
    j["warnings"] = nlohmann::json::array();
    for (const midi::Warning& w : r.warnings) j["warnings"].push_back(w.message);
    if (o.notes) {
      j["notes"] = nlohmann::json::array();
      for (const midi::Note& n : s.notes) {
        j["notes"].push_back({{"track", n.track},
                              {"channel", n.channel + 1},
                              {"key", n.key},
                              {"velocity", n.velocity},
                              {"start_s", s.start_s(n)},
                              {"end_s", s.end_s(n)}});
      }
    }
    fmt::print("{}\n", j.dump());
    return kExitOk;
  }

  fmt::print("{}\n", o.song);
  fmt::print("  format {}, {}, duration {:.3f} s, {} track(s), {} note(s)\n", s.format,
             s.division.smpte ? fmt::format("SMPTE {} fps × {} ticks", s.division.fps, s.division.ticks_per_frame)
                              : fmt::format("{} ticks per quarter", s.division.ticks_per_quarter),
             s.duration_s(), s.tracks.size(), s.notes.size());
  fmt::print("  pitched keys of the song: {}, kε {} (GM channel 10's drum keys left out)\n",
             song_keys.count() ? midi::key_name(song_keys.min()) + "–" + midi::key_name(song_keys.max()) : "none",
             song_keys.count());
  fmt::print("  mapping {}, keys of the {}: {:g}–{:g} Hz\n", mapping::name(opts.mapping), scope, opts.ranges.f_min_hz,
             opts.ranges.f_max_hz);
  fmt::print("\n  {:>3}  {:<24} {:<8} {:<26} {:>6}  {:<9} {:>4}  {:<12} {:>9}  {:>8}\n", "#", "name", "channel",
             "instrument (GM program)", "notes", "keys", "kε", "envelope", "felt Hz", "JND/step");
  for (const midi::Track& t : s.tracks) {
    const std::string instrument =
        t.note_count ? fmt::format("{} ({})", midi::gm_instrument_name(t.program(), t.channel()), t.program()) : "-";
    const std::string keys = t.note_count ? midi::key_name(t.key_min()) + "–" + midi::key_name(t.key_max()) : "-";
    fmt::print("  {:>3}  {:<24.24} {:<8} {:<26.26} {:>6}  {:<9} {:>4}  {:<12} {:>9}  {:>8.2f}\n", t.index, t.name,
               channels_text(t), instrument, t.note_count, keys, t.distinct_keys(),
               t.note_count ? envelope_of(t, opts) : "-", span_text(frequency_span(s, t, opts, song_keys)),
               t.distinct_keys() > 1 ? rank_jnd_steps(t) / (t.distinct_keys() - 1) : 0.0);
  }
  bool any_controller = false;
  for (const midi::Track& t : s.tracks) {
    const std::vector<std::string> used = midi::controllers_used(s, t.index);
    if (used.empty()) continue;
    if (!any_controller) fmt::print("\n  controllers (on each track's channels; the song's sound follows them):\n");
    any_controller = true;
    std::string line;
    for (const std::string& u : used) line += (line.empty() ? "" : ", ") + u;
    fmt::print("  {:>3}  {}\n", t.index, line);
  }
  fmt::print("\n  tempo:");
  const std::size_t shown = std::min<std::size_t>(s.tempo_changes.size(), 8);
  for (std::size_t i = 0; i < shown; ++i) {
    fmt::print(" {:.4g} bpm at {:.3f} s{}", s.tempo_changes[i].bpm(), static_cast<double>(s.tempo_changes[i].us) * 1e-6,
               i + 1 < shown ? ";" : "");
  }
  if (s.tempo_changes.size() > shown) fmt::print(" … ({} changes in all)", s.tempo_changes.size());
  if (s.tempo_changes.empty()) fmt::print(" none (SMPTE time)");
  fmt::print("\n");
  if (!r.warnings.empty()) {
    fmt::print("\n  {} warning(s):\n", r.warnings.size());
    for (const midi::Warning& w : r.warnings) fmt::print("    {}\n", w.message);
  }
  fmt::print(
      "\n  felt Hz: the frequencies the mapping gives the track's pitched keys (drums, and --mapping constant: one "
      "frequency).\n");
  fmt::print(
      "  JND/step: frequency just-noticeable differences (18 %) between adjacent keys under --mapping rank\n"
      "  (below 1: neighbouring keys feel alike; the full 50–250 Hz range spans {:.1f} JND).\n",
      std::log(250.0 / 50.0) / std::log(1.18));
  return kExitOk;
}

}  // namespace hmp::cli
