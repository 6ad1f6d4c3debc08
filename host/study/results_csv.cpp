#include "host/study/results_csv.hpp"

#include <charconv>
#include <cmath>
#include <ctime>
#include <map>
#include <sstream>
#include <string_view>
#include <tuple>

#include <fmt/format.h>

#include "host/common/error.hpp"
#include "host/common/printable.hpp"

namespace hmp::study {

// The round's columns, which both headers begin with.
#define HMP_STUDY_ROUND_COLUMNS                                                                             \
  "participant,experiment,phase,position,instrument,mapping,envelope,key,rank,seconds_felt,times_selected," \
  "round_started_utc,ranked_utc,round_ended_utc,seed,version"
const char* const kResultsHeader = HMP_STUDY_ROUND_COLUMNS ",age,sex,handedness";
const char* const kResultsHeaderWithoutParticipant = HMP_STUDY_ROUND_COLUMNS;
#undef HMP_STUDY_ROUND_COLUMNS

namespace {

constexpr std::size_t kVersionField = 15;          // the free-text field: last of the round's columns
constexpr std::string_view kBom = "\xEF\xBB\xBF";  // a spreadsheet saving "CSV UTF-8" starts with it

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out(1);
  for (const char c : line) {
    if (c == ',')
      out.emplace_back();
    else
      out.back() += c;
  }
  return out;
}

[[noreturn]] void fail(const std::string& file, int line, const std::string& what) {
  throw BadInput(fmt::format("{}:{}: {}", printable(file), line, what));
}

// A field as messages quote it: in double quotes, its bytes made visible (a NUL would end the message).
std::string quoted(const std::string& field) { return "\"" + printable(field) + "\""; }

// The header's column names, for messages about a field (a file without the participant's columns
// has the first ones).
const std::vector<std::string>& column_names() {
  static const std::vector<std::string> names = split(kResultsHeader);
  return names;
}

std::size_t field_count(Columns columns) {
  return split(columns == Columns::with_participant ? kResultsHeader : kResultsHeaderWithoutParticipant).size();
}

// Every field is UTF-8 text; the free-text one (version) also without control characters, which the
// other fields' own rules already refuse.
void check_text(const std::vector<std::string>& f, const std::string& file, int line) {
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!valid_utf8(f[i])) fail(file, line, fmt::format("{} {} is not valid UTF-8", column_names()[i], quoted(f[i])));
  }
  for (const char c : f[kVersionField]) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
      fail(file, line, fmt::format("version {} holds a control character", quoted(f[kVersionField])));
    }
  }
}

template <class T>
T number(const std::string& s, const char* column, const std::string& file, int line) {
  T v{};
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) {
    fail(file, line, fmt::format("{} {} is not a number", column, quoted(s)));
  }
  return v;
}

double real(const std::string& s, const char* column, const std::string& file, int line) {
  // from_chars for double is in libstdc++ 11+; strtod would accept "inf", "nan" and hex, which a
  // results file never holds.
  const double v = number<double>(s, column, file, line);
  if (!std::isfinite(v) || v < 0) fail(file, line, fmt::format("{} {} must be a finite number ≥ 0", column, quoted(s)));
  return v;
}

double utc(const std::string& s, const char* column, const std::string& file, int line) {
  const double v = parse_utc(s);
  if (std::isnan(v))
    fail(file, line, fmt::format("{} {} is not a UTC time like 2026-01-31T12:00:00.000Z", column, quoted(s)));
  return v;
}

Envelope envelope_of(const std::string& s, const std::string& file, int line) {
  for (const Envelope e : kEnvelopes) {
    if (s == envelope_name(e)) return e;
  }
  fail(file, line, fmt::format("unknown envelope {} (square, triangle or analogue)", quoted(s)));
}

ResultRow parse_row(const std::string& text, Columns columns, const std::string& file, int line) {
  const std::vector<std::string> f = split(text);
  const std::size_t fields = field_count(columns);
  if (f.size() != fields) fail(file, line, fmt::format("{} fields, expected {}", f.size(), fields));
  check_text(f, file, line);
  ResultRow r;
  r.file = file;
  r.line = line;
  r.participant = f[0];
  if (!valid_participant_id(r.participant)) fail(file, line, fmt::format("bad participant id {}", quoted(f[0])));
  r.experiment = number<int>(f[1], "experiment", file, line);
  if (r.experiment != 1 && r.experiment != 2) fail(file, line, fmt::format("experiment {} (1 or 2)", r.experiment));
  if (f[2] != "practice" && f[2] != "main") fail(file, line, fmt::format("phase {} (practice or main)", quoted(f[2])));
  r.practice = f[2] == "practice";
  r.position = number<int>(f[3], "position", file, line);
  if (r.position < 1 || r.position > (r.practice ? 2 : 4))
    fail(file, line, fmt::format("position {} out of range", r.position));
  r.instrument = f[4];
  bool known = false;
  for (const char* i : kInstruments) known = known || r.instrument == i;
  if (!known) fail(file, line, fmt::format("unknown instrument {}", quoted(f[4])));
  r.mapping = f[5];
  if (r.mapping != mapping_of_experiment(r.experiment)) {
    fail(file, line,
         fmt::format("mapping {} is not experiment {}'s ({})", quoted(f[5]), r.experiment,
                     mapping_of_experiment(r.experiment)));
  }
  r.envelope = envelope_of(f[6], file, line);
  r.key = number<int>(f[7], "key", file, line);
  if (r.key < 0 || r.key > 2) fail(file, line, fmt::format("key {} (0, 1 or 2)", r.key));
  r.rank = number<int>(f[8], "rank", file, line);
  if (r.rank < 1 || r.rank > 3) fail(file, line, fmt::format("rank {} (1, 2 or 3)", r.rank));
  r.seconds_felt = real(f[9], "seconds_felt", file, line);
  r.times_selected = number<int>(f[10], "times_selected", file, line);
  if (r.times_selected < 0) fail(file, line, "times_selected < 0");
  r.round_started = utc(f[11], "round_started_utc", file, line);
  r.ranked_at = utc(f[12], "ranked_utc", file, line);
  r.round_ended = utc(f[13], "round_ended_utc", file, line);
  r.seed = number<std::uint64_t>(f[14], "seed", file, line);
  r.version = f[kVersionField];
  if (columns == Columns::with_participant) {
    r.participant_data = parse_participant({f[kVersionField + 1], f[kVersionField + 2], f[kVersionField + 3]},
                                           participant_columns(), fmt::format("{}:{}: ", printable(file), line));
  }
  return r;
}

// All rows of a participant give the same age, sex and handedness (they describe one person).
void check_participants(const std::vector<ResultRow>& rows, const std::string& file) {
  std::map<std::string, const ResultRow*> first;
  for (const ResultRow& r : rows) {
    const auto [it, is_first] = first.emplace(r.participant, &r);
    if (is_first) continue;
    const std::string difference =
        participant_difference(r.participant_data, it->second->participant_data,
                               fmt::format("line {}", it->second->line), participant_columns());
    if (!difference.empty()) fail(file, r.line, fmt::format("participant {}: {}", r.participant, difference));
  }
}

// The text's first line: the header, without a byte order mark or a CR.
std::string header_of(const std::string& text) {
  const std::string_view rest =
      std::string_view(text).starts_with(kBom) ? std::string_view(text).substr(kBom.size()) : text;
  std::string_view line = rest.substr(0, rest.find('\n'));
  if (line.ends_with('\r')) line.remove_suffix(1);
  return std::string(line);
}

// Rows of one round must be three, with each envelope, key and rank once.
void check_rounds(const std::vector<ResultRow>& rows, const std::string& file) {
  using RoundId = std::tuple<std::string, int, bool, std::string>;
  std::map<RoundId, std::vector<const ResultRow*>> rounds;
  for (const ResultRow& r : rows) {
    auto& group = rounds[{r.participant, r.experiment, r.practice, r.instrument}];
    for (const ResultRow* o : group) {
      const std::string where = fmt::format("participant {} experiment {} {}{}", r.participant, r.experiment,
                                            r.practice ? "practice " : "", r.instrument);
      if (o->rank == r.rank)
        fail(file, r.line, fmt::format("{}: rank {} used twice (also line {})", where, r.rank, o->line));
      if (o->envelope == r.envelope) {
        fail(file, r.line,
             fmt::format("{}: envelope {} twice (also line {})", where, envelope_name(r.envelope), o->line));
      }
      if (o->key == r.key) fail(file, r.line, fmt::format("{}: key {} twice (also line {})", where, r.key, o->line));
    }
    group.push_back(&r);
  }
  for (const auto& [id, group] : rounds) {
    if (group.size() != 3) {
      fail(file, group.front()->line,
           fmt::format("participant {} experiment {} {}: {} rows, a round has 3", std::get<0>(id), std::get<1>(id),
                       std::get<3>(id), group.size()));
    }
  }
}

}  // namespace

bool valid_participant_id(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  for (const char c : id) {
    const bool ok =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

std::string format_utc(double unix_s) {
  const auto whole = static_cast<std::time_t>(std::floor(unix_s));
  int millis = static_cast<int>(std::lround((unix_s - static_cast<double>(whole)) * 1000));
  std::time_t secs = whole;
  if (millis == 1000) {
    millis = 0;
    ++secs;
  }
  std::tm tm{};
  gmtime_r(&secs, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec, millis);
}

double parse_utc(const std::string& text) {
  std::tm tm{};
  int millis = 0;
  char z = 0;
  if (text.size() != 24 ||
      std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d.%3d%c", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
                  &tm.tm_min, &tm.tm_sec, &millis, &z) != 8 ||
      z != 'Z') {
    return std::nan("");
  }
  if (tm.tm_mon < 1 || tm.tm_mon > 12 || tm.tm_mday < 1 || tm.tm_mday > 31 || tm.tm_hour > 23 || tm.tm_min > 59 ||
      tm.tm_sec > 60 || tm.tm_year < 1970) {
    return std::nan("");
  }
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  return static_cast<double>(timegm(&tm)) + millis / 1000.0;
}

const ParticipantTexts& participant_columns() {
  static const ParticipantTexts names{column_names()[kVersionField + 1], column_names()[kVersionField + 2],
                                      column_names()[kVersionField + 3]};
  return names;
}

Columns results_columns(const std::string& text) {
  return header_of(text) == kResultsHeaderWithoutParticipant ? Columns::without_participant : Columns::with_participant;
}

std::string format_row(const ResultRow& r, Columns columns) {
  std::string row =
      fmt::format("{},{},{},{},{},{},{},{},{},{:.3f},{},{},{},{},{},{}", r.participant, r.experiment,
                  r.practice ? "practice" : "main", r.position, r.instrument, r.mapping, envelope_name(r.envelope),
                  r.key, r.rank, r.seconds_felt, r.times_selected, format_utc(r.round_started), format_utc(r.ranked_at),
                  format_utc(r.round_ended), r.seed, r.version);
  if (columns == Columns::with_participant) {
    for (const std::string& field : participant_texts(r.participant_data)) row += "," + field;
  }
  return row;
}

std::vector<ResultRow> parse_results(const std::string& text, const std::string& file_name) {
  std::vector<ResultRow> rows;
  const std::string header = header_of(text);
  if (!text.empty() && header != kResultsHeader && header != kResultsHeaderWithoutParticipant) {
    fail(file_name, 1, "not a study results file (the header differs)");
  }
  const Columns columns = results_columns(text);
  std::istringstream in(text);
  std::string line;
  int number_of_line = 0;
  while (std::getline(in, line)) {
    ++number_of_line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number_of_line == 1 || line.empty()) continue;  // the header, checked above
    rows.push_back(parse_row(line, columns, file_name, number_of_line));
  }
  check_rounds(rows, file_name);
  check_participants(rows, file_name);
  return rows;
}

}  // namespace hmp::study
