#pragma once
// What the paper reports about its participants (how many, their sex, an age range): the optional data
// `hmp study --age --sex --handedness` records in every row of the results file (results_csv.hpp), and
// the summary `hmp study analyze` prints of it. Each field may be left out: empty in the file.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hmp::study {

enum class Sex : std::uint8_t { female, male, other, unstated };
inline constexpr std::array<const char*, 4> kSexNames{"female", "male", "other", "unstated"};
enum class Handedness : std::uint8_t { left, right, ambidextrous, unstated };
inline constexpr std::array<const char*, 4> kHandednessNames{"left", "right", "ambidextrous", "unstated"};
inline constexpr int kMinAge = 5, kMaxAge = 120;  // years: outside, a typing mistake rather than a person

// nullopt: not given (an empty field). `unstated` is given: the participant chose not to say.
struct ParticipantData {
  std::optional<int> age;
  std::optional<Sex> sex;
  std::optional<Handedness> handedness;
  bool operator==(const ParticipantData&) const = default;
};

// The three fields in this order everywhere: the file's last columns, the options, the messages.
inline constexpr std::size_t kParticipantFields = 3;
using ParticipantTexts = std::array<std::string, kParticipantFields>;  // age, sex, handedness; "" = not given

ParticipantTexts participant_texts(const ParticipantData& d);
// What a field accepts, for messages and help: "whole years from 5 to 120", "female, male, other or unstated".
std::string participant_allowed(std::size_t field);
// The data from its texts. A text that is none of its field's values throws BadInput
// "<where><label> <text>: <what is allowed>", labels being the columns' or the options' names.
ParticipantData parse_participant(const ParticipantTexts& texts, const ParticipantTexts& labels,
                                  const std::string& where);

// The first field in which `here` differs from `there`, as "age 30, but 25 on <there_name>"; "" when
// they agree. A field not given reads "(not given)".
std::string participant_difference(const ParticipantData& here, const ParticipantData& there,
                                   const std::string& there_name, const ParticipantTexts& labels);

// Over participants (each once): how many, by sex and handedness (not given counted as unstated, in
// kSexNames / kHandednessNames order), and the ages of those who gave one.
struct ParticipantSummary {
  int participants = 0;
  std::array<int, 4> by_sex{};
  std::array<int, 4> by_handedness{};
  int with_age = 0;  // the age figures below are over these; 0: none gave an age
  int age_min = 0, age_max = 0;
  double age_mean = 0;
};

ParticipantSummary summarize(const std::vector<ParticipantData>& participants);
// Three lines, like the paper's description of its participants:
//   participants: 11 — sex: female 4, male 7, other 0, unstated 0
//   age: 20–35 years, mean 26.1 (10 gave it; 1 did not)
//   handedness: left 1, right 10, ambidextrous 0, unstated 0
std::string format_summary(const ParticipantSummary& s);

}  // namespace hmp::study
