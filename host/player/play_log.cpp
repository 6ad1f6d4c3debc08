#include "host/player/play_log.hpp"

#include <fmt/format.h>

namespace hmp::player {

std::string started_line(const StartedNote& n) {
  // start_s: the shortest text that reads back as the same double (the µs of the MIDI file).
  return fmt::format(R"({{"track":{},"key":{},"start_s":{},"scheduled_tick":{},"actual_tick":{}}})", n.origin.track,
                     n.origin.key, n.origin.start_s, n.scheduled_tick, n.actual_tick);
}

std::string summary_line(const Counters& c) {
  return fmt::format(R"({{"summary":{{"notes_sent":{},"notes_played":{},"late":{},"stolen":{},"rejected":{}}}}})",
                     c.notes_sent, c.notes_played, c.late, c.stolen, c.rejected);
}

PlayLog::PlayLog(const std::string& path, bool force) : file_(output::open_for_writing(path, force)) {}

void PlayLog::started(const StartedNote& n) {
  if (file_) std::fprintf(file_.get(), "%s\n", started_line(n).c_str());
}

void PlayLog::summary(const Counters& c) {
  if (!file_) return;
  std::fprintf(file_.get(), "%s\n", summary_line(c).c_str());
  std::fflush(file_.get());
}

void PlayLog::flush() {
  if (file_) std::fflush(file_.get());
}

void PlayLog::close() {
  if (file_) output::close_output(file_);
  file_.reset();
}

}  // namespace hmp::player
