#pragma once
// The study's results file (design §15, docs/study.md "Results file"): one CSV row per participant ×
// experiment × instrument × envelope, practice rounds included (phase `practice`). Rows are only ever
// appended. Text in, text out: the caller reads and writes the file.
#include <cstdint>
#include <string>
#include <vector>

#include "host/study/participant.hpp"
#include "host/study/plan.hpp"

namespace hmp::study {

struct ResultRow {
  std::string participant;
  int experiment = 1;
  bool practice = false;
  int position = 0;  // the instrument's place in its experiment (1–4; practice 1–2)
  std::string instrument;
  std::string mapping;
  Envelope envelope{};
  int key = 0;   // 0–2: the envelope's presentation position
  int rank = 0;  // 1 = A (best) … 3 = C
  double seconds_felt = 0;
  int times_selected = 0;
  double round_started = 0, ranked_at = 0, round_ended = 0;  // Unix time, seconds (UTC in the file)
  std::uint64_t seed = 0;
  std::string version;
  ParticipantData participant_data;  // the same in all of a participant's rows
  std::string file;                  // where it was read from (empty, line 0: not read)
  int line = 0;
};

// The header of files written now: the round's columns, then the participant's (age, sex, handedness).
extern const char* const kResultsHeader;
// The header of files written before the participant's columns existed: still read, and appended to in
// their own layout (a file's rows all have its header's columns).
extern const char* const kResultsHeaderWithoutParticipant;

enum class Columns { without_participant, with_participant };
// The layout a file's text has: the one of its header (an empty text is a new file: the current one).
Columns results_columns(const std::string& text);

std::string format_row(const ResultRow& r, Columns columns = Columns::with_participant);
// Parses one file's text. Throws BadInput "FILE:LINE: what" on a bad header, a bad field, or rows that
// do not fit together (a rank, key or envelope used twice in a round, a round with fewer than three
// rows, two experiments' mappings mixed up, a participant's rows with different age, sex or
// handedness, a field that is not UTF-8); the bytes a message quotes are escaped. A leading UTF-8 byte
// order mark is skipped. An empty text is an empty file (no rows).
std::vector<ResultRow> parse_results(const std::string& text, const std::string& file_name);
// The participant columns' names (age, sex, handedness), for messages.
const ParticipantTexts& participant_columns();

bool valid_participant_id(const std::string& id);  // 1–64 of A–Z a–z 0–9 _ - . (no quoting needed)
std::string format_utc(double unix_s);             // 2026-11-24T19:37:07.250Z
double parse_utc(const std::string& text);         // inverse; NaN when malformed

}  // namespace hmp::study
