#include "host/player/play_log.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace hmp::player {

namespace {

nlohmann::json counters_json(const Counters& c) {
  return {{"notes_sent", c.notes_sent}, {"notes_played", c.notes_played}, {"late", c.late},
          {"stolen", c.stolen},         {"rejected", c.rejected},         {"skipped", c.skipped},
          {"cancelled", c.cancelled}};
}

}  // namespace

std::string started_line(std::size_t song, const StartedNote& n) {
  // start_s: the shortest text that reads back as the same double (the µs of the MIDI file).
  return fmt::format(R"({{"song":{},"track":{},"key":{},"start_s":{},"scheduled_tick":{},"actual_tick":{}}})", song,
                     n.origin.track, n.origin.key, n.origin.start_s, n.scheduled_tick, n.actual_tick);
}

std::string song_end_line(std::size_t index, const std::string& path, double played_s, double wall_s,
                          const Counters& c) {
  nlohmann::json j = counters_json(c);
  j["index"] = index;
  j["path"] = path;
  j["played_s"] = played_s;
  j["wall_s"] = std::round(wall_s * 10) / 10;
  // A path that is not UTF-8 is written with U+FFFD in place of its bad bytes rather than refused.
  return nlohmann::json{{"song_end", j}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string between_songs_line(double wall_s, std::optional<std::uint64_t> rss_kib) {
  return nlohmann::json{{"between_songs",
                         {{"wall_s", std::round(wall_s * 10) / 10},
                          {"rss_kib", rss_kib ? nlohmann::json(*rss_kib) : nlohmann::json(nullptr)}}}}
      .dump();
}

std::string summary_line(const Counters& c, const PlayLog::Totals& totals) {
  nlohmann::json j = counters_json(c);
  j["songs_played"] = totals.songs_played;
  j["files_skipped"] = totals.files_skipped;
  j["played_s"] = totals.played_s;
  j["audio_underruns"] = totals.audio_underruns ? nlohmann::json(*totals.audio_underruns) : nlohmann::json(nullptr);
  j["audio_realtime"] = totals.audio_realtime ? nlohmann::json(*totals.audio_realtime) : nlohmann::json(nullptr);
  nlohmann::json list = nlohmann::json::array();
  const auto rounded = [](double v) { return std::round(v * 1000) / 1000; };
  for (std::size_t i = 0; i < totals.audio_underrun_list.size() && i < PlayLog::kUnderrunsListed; ++i) {
    const audio::VirtualCard::Underrun& u = totals.audio_underrun_list[i];
    list.push_back({{"at_s", rounded(u.at_s)},
                    {"short_ms", rounded(u.short_ms)},
                    {"woke_late_ms", rounded(u.woke_late_ms)},
                    {"callback_ms", rounded(u.callback_ms)}});
  }
  j["audio_underrun_list"] = list;
  return nlohmann::json{{"summary", j}}.dump();
}

PlayLog::PlayLog(const std::string& path, bool force) : file_(output::open_for_writing(path, force)) {}

void PlayLog::write(const std::string& line) {
  if (file_) std::fprintf(file_.get(), "%s\n", line.c_str());
}

void PlayLog::started(const StartedNote& n) { write(started_line(song_, n)); }

void PlayLog::song_end(std::size_t index, const std::string& path, double played_s, const Counters& c) {
  const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - opened_;
  write(song_end_line(index, path, played_s, wall.count(), c));
  flush();
}

void PlayLog::between_songs(std::optional<std::uint64_t> rss_kib) {
  const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - opened_;
  write(between_songs_line(wall.count(), rss_kib));
}

void PlayLog::summary(const Counters& c, const Totals& totals) {
  write(summary_line(c, totals));
  flush();
}

void PlayLog::flush() {
  if (file_) std::fflush(file_.get());
}

void PlayLog::close() {
  if (file_) output::close_output(file_);
  file_.reset();
}

}  // namespace hmp::player
