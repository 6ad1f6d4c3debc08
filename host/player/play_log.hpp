#pragma once
// `hmp play --log FILE` (design §3): one JSON object per line for every note the device started, as its
// Started reports say, then one closing summary line. The file is opened through
// output::open_for_writing: an existing file is replaced only with --force (or a "yes" on a terminal).
#include <string>

#include "host/output/output_file.hpp"
#include "host/player/player.hpp"

namespace hmp::player {

class PlayLog {
 public:
  PlayLog() = default;                                     // no log: every call does nothing
  PlayLog(const std::string& path, bool force);            // throws BadInput (exists, no folder, …)
  bool enabled() const { return file_ != nullptr; }
  void started(const StartedNote& n);
  void summary(const Counters& c);
  void flush();
  // Closes the file: renamed from FILE.part into place (output_file.hpp); throws when the write failed.
  // A log never closed this way is renamed when it goes out of scope normally and removed when an
  // exception unwinds through it.
  void close();

 private:
  output::FilePtr file_;
};

std::string started_line(const StartedNote& n);  // {"track":T,"key":K,"start_s":S,"scheduled_tick":N,"actual_tick":M}
std::string summary_line(const Counters& c);     // {"summary":{"notes_sent":..,"notes_played":..,"late":..,"stolen":..,"rejected":..}}

}  // namespace hmp::player
