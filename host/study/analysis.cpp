#include "host/study/analysis.hpp"

#include <cmath>
#include <map>
#include <tuple>

#include <fmt/format.h>

#include "host/common/error.hpp"
#include "host/common/printable.hpp"

namespace hmp::study {

namespace {

std::size_t index_of(Envelope e) { return static_cast<std::size_t>(e); }

std::string winners_text(const CopelandResult& c) {
  std::string s;
  for (const int w : c.winners)
    s += (s.empty() ? "" : " = ") + std::string(envelope_name(kEnvelopes[static_cast<std::size_t>(w)]));
  if (c.winners.size() > 1) s += fmt::format(" (tie of {})", c.winners.size());
  return s;
}

std::string number_or_dash(double v, const char* format) {
  return std::isnan(v) ? std::string("–") : fmt::format(fmt::runtime(format), v);
}

}  // namespace

std::vector<GroupAnalysis> analyze(const std::vector<ResultRow>& rows) {
  // (experiment, instrument position in kInstruments) → participant → ranks by envelope
  std::map<std::pair<int, std::size_t>, std::map<std::string, std::vector<double>>> tables;
  std::map<std::tuple<int, std::string, std::string>, int> first_line;
  for (const ResultRow& r : rows) {
    if (r.practice) continue;
    std::size_t instrument = 0;
    while (kInstruments[instrument] != r.instrument) ++instrument;  // parse_results checked it is one
    auto& ranks = tables[{r.experiment, instrument}][r.participant];
    if (ranks.empty()) ranks.assign(3, 0.0);
    if (ranks[index_of(r.envelope)] != 0) {
      throw BadInput(fmt::format("{}:{}: participant {} has experiment {} {} twice (the same results in two files?)",
                                 r.file, r.line, r.participant, r.experiment, r.instrument));
    }
    ranks[index_of(r.envelope)] = r.rank;
  }
  std::vector<GroupAnalysis> out;
  for (const auto& [id, by_participant] : tables) {
    RankTable table;
    for (const auto& [participant, ranks] : by_participant) table.push_back(ranks);
    GroupAnalysis g;
    g.experiment = id.first;
    g.instrument = kInstruments[id.second];
    g.participants = static_cast<int>(table.size());
    const auto votes = first_place_votes(table);
    const auto prefer = pairwise_preferences(table);
    for (std::size_t i = 0; i < 3; ++i) {
      g.first_votes[i] = votes[i];
      for (std::size_t j = 0; j < 3; ++j) g.prefer[i][j] = prefer[i][j];
    }
    g.copeland = copeland(table);
    g.friedman = friedman(table);
    out.push_back(g);
  }
  return out;
}

std::vector<ParticipantData> analysed_participants(const std::vector<ResultRow>& rows) {
  std::map<std::string, const ResultRow*> first;
  for (const ResultRow& r : rows) {
    if (r.practice) continue;
    const auto [it, is_first] = first.emplace(r.participant, &r);
    if (is_first) continue;
    const ResultRow& o = *it->second;
    const std::string difference = participant_difference(
        r.participant_data, o.participant_data, fmt::format("{}:{}", printable(o.file), o.line), participant_columns());
    if (!difference.empty())
      throw BadInput(fmt::format("{}:{}: participant {}: {}", printable(r.file), r.line, r.participant, difference));
  }
  std::vector<ParticipantData> out;
  for (const auto& [id, row] : first) out.push_back(row->participant_data);
  return out;
}

std::string format_report(const std::vector<GroupAnalysis>& groups) {
  std::string s;
  for (const GroupAnalysis& g : groups) {
    s += fmt::format("experiment {} ({} mapping), {}: {} participant(s)\n", g.experiment,
                     mapping_of_experiment(g.experiment), g.instrument, g.participants);
    s += "  envelope   1st votes  beats: square triangle analogue  Copeland (W-L)\n";
    for (std::size_t i = 0; i < 3; ++i) {
      s += fmt::format("  {:<9}  {:>9}         ", envelope_name(kEnvelopes[i]), g.first_votes[i]);
      for (std::size_t j = 0; j < 3; ++j) {
        s += i == j ? fmt::format("{:>9}", "–")
                    : fmt::format("{:>9}", fmt::format("{}:{}", g.prefer[i][j], g.prefer[j][i]));
      }
      s += fmt::format("  {:>+3} ({}-{})\n", g.copeland.score[i], g.copeland.wins[i], g.copeland.losses[i]);
    }
    s += fmt::format("  Copeland winner: {}\n", winners_text(g.copeland));
    s += fmt::format("  Friedman chi2 = {} (df {}), p = {}; Kendall's W = {}\n",
                     number_or_dash(g.friedman.chi2, "{:.3f}"), g.friedman.df, number_or_dash(g.friedman.p, "{:.4f}"),
                     number_or_dash(g.friedman.kendall_w, "{:.3f}"));
  }
  return s;
}

nlohmann::json to_json(const std::vector<GroupAnalysis>& groups) {
  nlohmann::json out = nlohmann::json::array();
  auto number = [](double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); };
  for (const GroupAnalysis& g : groups) {
    nlohmann::json j;
    j["experiment"] = g.experiment;
    j["mapping"] = mapping_of_experiment(g.experiment);
    j["instrument"] = g.instrument;
    j["participants"] = g.participants;
    nlohmann::json envelopes = nlohmann::json::object();
    for (std::size_t i = 0; i < 3; ++i) {
      nlohmann::json e;
      e["first_place_votes"] = g.first_votes[i];
      e["copeland_score"] = g.copeland.score[i];
      nlohmann::json beats = nlohmann::json::object();
      for (std::size_t k = 0; k < 3; ++k) {
        if (k != i) beats[envelope_name(kEnvelopes[k])] = g.prefer[i][k];
      }
      e["preferred_over"] = beats;
      envelopes[envelope_name(kEnvelopes[i])] = e;
    }
    j["envelopes"] = envelopes;
    nlohmann::json winners = nlohmann::json::array();
    for (const int w : g.copeland.winners) winners.push_back(envelope_name(kEnvelopes[static_cast<std::size_t>(w)]));
    j["copeland_winners"] = winners;
    j["copeland_tie"] = g.copeland.winners.size() > 1;
    j["friedman"] = {{"chi2", number(g.friedman.chi2)}, {"df", g.friedman.df}, {"p", number(g.friedman.p)}};
    j["kendall_w"] = number(g.friedman.kendall_w);
    out.push_back(j);
  }
  return out;
}

}  // namespace hmp::study
