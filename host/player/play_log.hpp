#pragma once
// `hmp play --log FILE` (design §3): one JSON object per line for every note the device started, as its
// Started reports say, one line at the end of each song, then one closing summary line. The file is opened through
// output::open_for_writing: an existing file is replaced only with --force (or a "yes" on a terminal).
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/audio/virtual_card.hpp"
#include "host/output/output_file.hpp"
#include "host/player/player.hpp"

namespace hmp::player {

class PlayLog {
 public:
  static constexpr std::size_t kUnderrunsListed = 20;
  // What the summary says of a playlist as a whole.
  struct Totals {
    std::size_t songs_played = 0, files_skipped = 0;
    double played_s = 0;                           // song seconds played (position reached − start)
    std::optional<std::uint64_t> audio_underruns;  // the virtual card's; unknown for a real card
    std::optional<bool> audio_realtime;            // whether the virtual card's thread had real-time priority
    std::vector<audio::VirtualCard::Underrun> audio_underrun_list;  // the first kUnderrunsListed of them
  };

  PlayLog() = default;                           // no log: every call does nothing
  PlayLog(const std::string& path, bool force);  // throws BadInput (exists, no folder, …)
  bool enabled() const { return file_ != nullptr; }
  void begin_song(std::size_t index) { song_ = index; }  // the playlist index the started lines carry
  void started(const StartedNote& n);
  void song_end(std::size_t index, const std::string& path, double played_s, const Counters& c);
  // Between two songs, once the last one's memory was handed back: what the process holds then is what
  // a long run keeps (unknown: null).
  void between_songs(std::optional<std::uint64_t> rss_kib);
  void summary(const Counters& c, const Totals& totals);
  void flush();
  // Closes the file: renamed from FILE.part into place (output_file.hpp); throws when the write failed.
  // A log never closed this way is renamed when it goes out of scope normally and removed when an
  // exception unwinds through it.
  void close();

 private:
  void write(const std::string& line);
  output::FilePtr file_;
  std::size_t song_ = 0;
  std::chrono::steady_clock::time_point opened_ = std::chrono::steady_clock::now();
};

// {"song":I,"track":T,"key":K,"start_s":S,"scheduled_tick":N,"actual_tick":M}
std::string started_line(std::size_t song, const StartedNote& n);
// {"song_end":{"index":I,"path":"…","played_s":S,"wall_s":W,"notes_sent":..,"notes_played":..,"late":..,
// "stolen":..,"rejected":..,"skipped":..,"cancelled":..}}; wall_s: seconds since the log was opened
std::string song_end_line(std::size_t index, const std::string& path, double played_s, double wall_s,
                          const Counters& c);
// {"between_songs":{"wall_s":W,"rss_kib":R|null}}
std::string between_songs_line(double wall_s, std::optional<std::uint64_t> rss_kib);
// {"summary":{"notes_sent":..,"notes_played":..,"late":..,"stolen":..,"rejected":..,"skipped":..,"cancelled":..,
// "songs_played":..,"files_skipped":..,"played_s":..,"audio_underruns":N|null,"audio_realtime":B|null,
// "audio_underrun_list":[{"at_s":..,"short_ms":..,"woke_late_ms":..,"callback_ms":..}...]}}
std::string summary_line(const Counters& c, const PlayLog::Totals& totals);

}  // namespace hmp::player
