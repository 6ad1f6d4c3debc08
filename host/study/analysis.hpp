#pragma once
// `hmp study analyze`: the main rounds' rows grouped per experiment and instrument, with the
// statistics of stats.hpp, as a text table and as JSON. Practice rows are not analysed.
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/study/results_csv.hpp"
#include "host/study/stats.hpp"

namespace hmp::study {

struct GroupAnalysis {
  int experiment = 1;
  std::string instrument;
  int participants = 0;
  std::array<int, 3> first_votes{};            // by envelope (kEnvelopes order)
  std::array<std::array<int, 3>, 3> prefer{};  // prefer[i][j]: participants ranking i above j
  CopelandResult copeland;
  FriedmanResult friedman;
};

// Groups in experiment order, then the paper's instrument order. Throws BadInput when one participant
// has two rounds of the same experiment and instrument (e.g. the same file given twice).
std::vector<GroupAnalysis> analyze(const std::vector<ResultRow>& rows);
// The analysed participants' data (those with main rows), each once in id order. Throws BadInput
// "FILE:LINE: participant P: age 30, but 25 on OTHER:LINE" when their rows in two files disagree.
std::vector<ParticipantData> analysed_participants(const std::vector<ResultRow>& rows);
std::string format_report(const std::vector<GroupAnalysis>& groups);
nlohmann::json to_json(const std::vector<GroupAnalysis>& groups);

}  // namespace hmp::study
