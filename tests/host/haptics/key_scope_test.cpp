// The key range a track's notes are mapped against: the song's pitched keys (2015 paper §5.4, the
// default), or the track's own (2013 paper, legacy2013's default). Expectations come from the paper's
// Eq. 5–7 as printed, computed here from the song's notes.
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "host/common/error.hpp"
#include "host/haptics/haptic_track.hpp"
#include "host/midi/smf_reader.hpp"
#include "tests/support/midi_builder.hpp"

namespace {

using hmp::haptics::HapticOptions;
using hmp::haptics::KeyScope;
namespace midi = hmp::midi;

const char* const kDemo = HMP_REPO_DIR "/examples/bach-bwv1050-brandenburg5-mvt3-allegro.mid";

struct Range {
  int k_min = 128, k_max = -1, k_eps = 0;
};

// k_min, k_max and k_ε of the notes the predicate keeps, counted here (not with mapping::KeySet).
template <class Keep>
Range range_of(const midi::Song& song, Keep keep) {
  bool seen[128] = {};
  Range r;
  for (const midi::Note& n : song.notes) {
    if (!keep(n) || seen[n.key]) continue;
    seen[n.key] = true;
    ++r.k_eps;
    r.k_min = std::min<int>(r.k_min, n.key);
    r.k_max = std::max<int>(r.k_max, n.key);
  }
  return r;
}

bool pitched(const midi::Note& n) { return n.channel != midi::kDrumChannel; }

// Eq. 5–7 as printed, with the defaults 50–250 Hz and 7.5–30 dB (30 dB = full scale).
void eq5to7(const Range& r, int key, double& f, double& amp) {
  const double dk = r.k_max - r.k_min;
  const double n = dk > 0 ? r.k_eps * (key - r.k_min) / dk : r.k_eps / 2.0;  // Eq. 5
  f = 50 + (250.0 - 50) / r.k_eps * n;                                       // Eq. 6
  const double a_db = 7.5 + (30 - 7.5) / r.k_eps * n;                        // Eq. 7
  amp = std::pow(10.0, (a_db - 30) / 20);
}

midi::Song demo() { return midi::load_song(kDemo).song; }

std::vector<std::uint32_t> pitched_tracks(const midi::Song& song) {
  std::vector<std::uint32_t> out;
  for (const midi::Track& t : song.tracks) {
    if (t.note_count > 0 && !t.is_drums()) out.push_back(t.index);
  }
  return out;
}

TEST(KeyScope, TheDefaultMapsEveryNoteOfTheDemoByEq5to7OverTheSongsKeys) {
  const midi::Song song = demo();
  const Range r = range_of(song, pitched);
  ASSERT_GT(r.k_eps, 10);
  const std::vector<std::uint32_t> tracks = pitched_tracks(song);
  ASSERT_GE(tracks.size(), 4u);
  for (std::uint32_t t : tracks) {
    const auto track = hmp::haptics::build_haptic_track(song, t, HapticOptions{});
    EXPECT_EQ(track.key_scope, KeyScope::song);
    for (const auto& n : track.notes) {
      double f = 0, amp = 0;
      eq5to7(r, n.key, f, amp);
      ASSERT_NEAR(n.freq_hz, f, 1e-9) << "track " << t << " key " << int(n.key);
      ASSERT_NEAR(n.amplitude, amp, 1e-12) << "track " << t << " key " << int(n.key);
    }
  }
}

TEST(KeyScope, OnTheDemoBassTracksAreFeltLowAndTheFluteHigh) {
  const midi::Song song = demo();
  std::map<std::string, std::pair<double, double>> means;  // instrument → (mean key, mean frequency)
  std::vector<std::pair<double, double>> all;
  for (std::uint32_t t : pitched_tracks(song)) {
    const auto track = hmp::haptics::build_haptic_track(song, t, HapticOptions{});
    double key = 0, f = 0;
    for (const auto& n : track.notes) {
      key += n.key;
      f += n.freq_hz;
    }
    const auto count = static_cast<double>(track.notes.size());
    means[song.tracks[t].name] = {key / count, f / count};
    all.emplace_back(key / count, f / count);
  }
  // Mean frequencies order as mean keys do.
  std::sort(all.begin(), all.end());
  for (std::size_t i = 1; i < all.size(); ++i) EXPECT_LT(all[i - 1].second, all[i].second) << i;
  // The contrabass and the cello lowest, the flute highest.
  const auto find = [&](const std::string& part) {
    for (const auto& [name, m] : means) {
      std::string lower = name;
      for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (lower.find(part) != std::string::npos) return m.second;
    }
    ADD_FAILURE() << "no track named like " << part;
    return 0.0;
  };
  const double bass = find("bass"), cello = find("cello"), flute = find("flute");
  std::vector<double> f;
  for (const auto& m : all) f.push_back(m.second);
  std::sort(f.begin(), f.end());
  EXPECT_LE(std::max(bass, cello), f[1]);
  EXPECT_EQ(flute, f.back());
  EXPECT_LT(bass, 150.0) << "a bass line is felt in the lower half of 50–250 Hz";
  EXPECT_GT(flute, 150.0) << "a flute in the upper half";
}

TEST(KeyScope, OnlyTheSongsLowestKeyMapsTo50Hz) {
  const midi::Song song = demo();
  const Range r = range_of(song, pitched);
  int at_floor = 0;
  for (std::uint32_t t : pitched_tracks(song)) {
    for (const auto& n : hmp::haptics::build_haptic_track(song, t, HapticOptions{}).notes) {
      if (n.key == r.k_min) {
        EXPECT_EQ(n.freq_hz, 50.0);
        ++at_floor;
      } else {
        EXPECT_GT(n.freq_hz, 50.0) << "key " << int(n.key);
      }
    }
  }
  EXPECT_GT(at_floor, 0);
}

TEST(KeyScope, TrackScopeIsThe2013ReadingAndEveryTrackSpansTheWholeRange) {
  const midi::Song song = demo();
  HapticOptions track_scope;
  track_scope.key_scope = KeyScope::track;
  for (std::uint32_t t : pitched_tracks(song)) {
    const auto track = hmp::haptics::build_haptic_track(song, t, track_scope);
    const Range r = range_of(song, [&](const midi::Note& n) { return n.track == t && pitched(n); });
    for (const auto& n : track.notes) {
      double f = 0, amp = 0;
      eq5to7(r, n.key, f, amp);
      ASSERT_NEAR(n.freq_hz, f, 1e-9);
    }
  }
  HapticOptions legacy;
  legacy.mapping = hmp::mapping::Mode::legacy2013;
  EXPECT_EQ(hmp::haptics::key_scope_of(legacy), KeyScope::track);
  legacy.key_scope = KeyScope::song;
  EXPECT_EQ(hmp::haptics::key_scope_of(legacy), KeyScope::song);
  HapticOptions rank;
  rank.mapping = hmp::mapping::Mode::rank;
  EXPECT_EQ(hmp::haptics::key_scope_of(rank), KeyScope::song);
}

midi::Song song_of(const std::vector<midi_test::Events>& tracks) {
  const midi_test::Bytes bytes = midi_test::smf(1, 480, tracks);
  return midi::read_smf(bytes).song;
}

midi_test::Events melody(int channel, std::initializer_list<int> keys) {
  midi_test::Events e;
  for (int k : keys) e.on(0, channel, k).off(240, channel, k);
  e.end();
  return e;
}

std::vector<double> frequencies(const midi::Song& song, std::uint32_t track, const HapticOptions& o) {
  std::vector<double> f;
  for (const auto& n : hmp::haptics::build_haptic_track(song, track, o).notes) f.push_back(n.freq_hz);
  return f;
}

TEST(KeyScope, AOneTrackSongIsMappedAlikeUnderBothScopes) {
  const midi::Song song = song_of({melody(0, {60, 64, 67, 72, 62})});
  HapticOptions s, t;
  s.key_scope = KeyScope::song;
  t.key_scope = KeyScope::track;
  for (auto mode : {hmp::mapping::Mode::paper, hmp::mapping::Mode::rank, hmp::mapping::Mode::legacy2013}) {
    s.mapping = t.mapping = mode;
    EXPECT_EQ(frequencies(song, 0, s), frequencies(song, 0, t)) << hmp::mapping::name(mode);
  }
  EXPECT_EQ(frequencies(song, 0, HapticOptions{}).front(), 50.0);
}

TEST(KeyScope, ADrumTrackChangesNothing) {
  const auto tune = melody(0, {60, 64, 67, 72});
  const auto bass = melody(1, {48, 43});
  const auto drums = melody(midi::kDrumChannel, {35, 81, 42});  // keys outside the pitched range
  const midi::Song without = song_of({tune, bass});
  const midi::Song with = song_of({tune, drums, bass});
  for (auto mode : {hmp::mapping::Mode::paper, hmp::mapping::Mode::rank}) {
    HapticOptions o;
    o.mapping = mode;
    EXPECT_EQ(frequencies(without, 0, o), frequencies(with, 0, o));
    EXPECT_EQ(frequencies(without, 1, o), frequencies(with, 2, o));
  }
  // The song's range is 43–72: the tune's C4 sits (60 − 43)/29 of the way up.
  EXPECT_NEAR(frequencies(with, 0, HapticOptions{}).front(), 50 + 200.0 * 17 / 29, 1e-9);
  EXPECT_EQ(hmp::haptics::pitched_keys(with).min(), 43);
  EXPECT_EQ(hmp::haptics::pitched_keys(with).max(), 72);
}

TEST(KeyScope, NamesAreReadCaseInsensitivelyAndUnknownOnesRefused) {
  KeyScope s = KeyScope::track;
  EXPECT_TRUE(hmp::haptics::find_key_scope("SONG", s));
  EXPECT_EQ(s, KeyScope::song);
  EXPECT_TRUE(hmp::haptics::find_key_scope("track", s));
  EXPECT_EQ(s, KeyScope::track);
  EXPECT_FALSE(hmp::haptics::find_key_scope("chord", s));
  EXPECT_FALSE(hmp::haptics::find_key_scope("", s));
  hmp::config::Config cfg;
  cfg.key_scope = "bar";
  HapticOptions o;
  EXPECT_THROW(hmp::haptics::apply_config(cfg, o), hmp::BadInput);
  cfg.key_scope = "Track";
  hmp::haptics::apply_config(cfg, o);
  EXPECT_EQ(hmp::haptics::key_scope_of(o), KeyScope::track);
}

// `hmp info --json`: the song's pitched keys and each track's felt span under the chosen scope.
nlohmann::json info(const std::string& options) {
  const std::string cmd = std::string(HMP_BIN_DIR) + "/hmp info --json " + options + " " + kDemo;
  std::FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  for (std::size_t n; p && (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  EXPECT_EQ(p ? pclose(p) : -1, 0) << cmd;
  return nlohmann::json::parse(out);
}

TEST(KeyScope, InfoShowsTheSongsKeysAndEachTracksFeltSpan) {
  const midi::Song song = demo();
  const Range r = range_of(song, pitched);
  const auto by_song = info("");
  EXPECT_EQ(by_song["song_keys"]["key_min"], r.k_min);
  EXPECT_EQ(by_song["song_keys"]["key_max"], r.k_max);
  EXPECT_EQ(by_song["song_keys"]["distinct_keys"], r.k_eps);
  EXPECT_EQ(by_song["mapping"]["key_scope"], "song");
  const auto by_track = info("--key-scope track");
  EXPECT_EQ(by_track["mapping"]["key_scope"], "track");
  for (std::size_t i = 0; i < song.tracks.size(); ++i) {
    const auto& t = song.tracks[i];
    if (t.note_count == 0) {
      EXPECT_TRUE(by_song["tracks"][i]["freq_min_hz"].is_null());
      continue;
    }
    double lo = 0, hi = 0, amp = 0;
    eq5to7(r, t.key_min(), lo, amp);
    eq5to7(r, t.key_max(), hi, amp);
    EXPECT_NEAR(by_song["tracks"][i]["freq_min_hz"].get<double>(), lo, 1e-9) << t.name;
    EXPECT_NEAR(by_song["tracks"][i]["freq_max_hz"].get<double>(), hi, 1e-9) << t.name;
    EXPECT_EQ(by_track["tracks"][i]["freq_min_hz"].get<double>(), 50.0) << t.name;
    EXPECT_EQ(by_track["tracks"][i]["freq_max_hz"].get<double>(), 250.0) << t.name;
  }
}

}  // namespace
