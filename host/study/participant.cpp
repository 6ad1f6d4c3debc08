#include "host/study/participant.hpp"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

#include "host/common/error.hpp"
#include "host/common/printable.hpp"

namespace hmp::study {

namespace {

// "female, male, other or unstated": what a field of named values accepts, for messages.
template <std::size_t N>
std::string alternatives(const std::array<const char*, N>& names) {
  std::string s;
  for (std::size_t i = 0; i < N; ++i) s += (i == 0 ? "" : i + 1 == N ? " or " : ", ") + std::string(names[i]);
  return s;
}

template <class E, std::size_t N>
std::optional<E> named(const std::string& text, const std::array<const char*, N>& names) {
  for (std::size_t i = 0; i < N; ++i) {
    if (text == names[i]) return static_cast<E>(i);
  }
  return std::nullopt;
}

// Whole years, digits only (no sign, no spaces), kMinAge to kMaxAge.
std::optional<int> age_of(const std::string& text) {
  int v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  const bool digits = !text.empty() && text.front() != '-' && ec == std::errc() && end == text.data() + text.size();
  if (!digits || v < kMinAge || v > kMaxAge) return std::nullopt;
  return v;
}

[[noreturn]] void bad(const std::string& where, const std::string& label, const std::string& text,
                      const std::string& allowed) {
  throw BadInput(fmt::format("{}{} {}: {}", where, label, printable(text), allowed));
}

// A value that may be absent: read by `parse` unless the text is empty.
template <class T, class Parse>
std::optional<T> optional_field(const std::string& text, Parse parse, const std::string& where,
                                const std::string& label, const std::string& allowed) {
  if (text.empty()) return std::nullopt;
  const std::optional<T> v = parse(text);
  if (!v) bad(where, label, text, allowed);
  return v;
}

std::string shown(const std::string& text) { return text.empty() ? "(not given)" : text; }

template <std::size_t N>
std::string counts(const std::array<int, 4>& n, const std::array<const char*, N>& names) {
  std::string s;
  for (std::size_t i = 0; i < N; ++i) s += fmt::format("{}{} {}", i == 0 ? "" : ", ", names[i], n[i]);
  return s;
}

std::string age_line(const ParticipantSummary& s) {
  if (s.with_age == 0) return fmt::format("age: not given (by none of the {})", s.participants);
  const int without = s.participants - s.with_age;
  const std::string who = without == 0 ? fmt::format("all {} gave it", s.with_age)
                                       : fmt::format("{} gave it; {} did not", s.with_age, without);
  return fmt::format("age: {}–{} years, mean {:.1f} ({})", s.age_min, s.age_max, s.age_mean, who);
}

}  // namespace

ParticipantTexts participant_texts(const ParticipantData& d) {
  return {d.age ? std::to_string(*d.age) : "", d.sex ? kSexNames[static_cast<std::size_t>(*d.sex)] : "",
          d.handedness ? kHandednessNames[static_cast<std::size_t>(*d.handedness)] : ""};
}

std::string participant_allowed(std::size_t field) {
  if (field == 0) return fmt::format("whole years from {} to {}", kMinAge, kMaxAge);
  return field == 1 ? alternatives(kSexNames) : alternatives(kHandednessNames);
}

ParticipantData parse_participant(const ParticipantTexts& texts, const ParticipantTexts& labels,
                                  const std::string& where) {
  ParticipantData d;
  d.age = optional_field<int>(texts[0], age_of, where, labels[0], participant_allowed(0));
  d.sex = optional_field<Sex>(
      texts[1], [](const std::string& t) { return named<Sex>(t, kSexNames); }, where, labels[1],
      participant_allowed(1));
  d.handedness = optional_field<Handedness>(
      texts[2], [](const std::string& t) { return named<Handedness>(t, kHandednessNames); }, where, labels[2],
      participant_allowed(2));
  return d;
}

std::string participant_difference(const ParticipantData& here, const ParticipantData& there,
                                   const std::string& there_name, const ParticipantTexts& labels) {
  const ParticipantTexts a = participant_texts(here), b = participant_texts(there);
  for (std::size_t i = 0; i < kParticipantFields; ++i) {
    if (a[i] != b[i]) return fmt::format("{} {}, but {} on {}", labels[i], shown(a[i]), shown(b[i]), there_name);
  }
  return "";
}

ParticipantSummary summarize(const std::vector<ParticipantData>& participants) {
  ParticipantSummary s;
  s.participants = static_cast<int>(participants.size());
  long age_sum = 0;
  for (const ParticipantData& p : participants) {
    ++s.by_sex[static_cast<std::size_t>(p.sex.value_or(Sex::unstated))];
    ++s.by_handedness[static_cast<std::size_t>(p.handedness.value_or(Handedness::unstated))];
    if (!p.age) continue;
    s.age_min = s.with_age == 0 ? *p.age : std::min(s.age_min, *p.age);
    s.age_max = s.with_age == 0 ? *p.age : std::max(s.age_max, *p.age);
    age_sum += *p.age;
    ++s.with_age;
  }
  if (s.with_age > 0) s.age_mean = static_cast<double>(age_sum) / s.with_age;
  return s;
}

std::string format_summary(const ParticipantSummary& s) {
  return fmt::format("participants: {} — sex: {}\n{}\nhandedness: {}\n", s.participants, counts(s.by_sex, kSexNames),
                     age_line(s), counts(s.by_handedness, kHandednessNames));
}

}  // namespace hmp::study
