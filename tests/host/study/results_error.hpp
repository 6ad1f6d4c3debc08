#pragma once
// The one-line error parse_results gives a results file's text ("" when it parses), for the study tests.
#include <string>

#include "host/common/error.hpp"
#include "host/study/results_csv.hpp"

namespace hmp::study::test {

inline std::string error_of(const std::string& text) {
  try {
    parse_results(text, "res.csv");
  } catch (const hmp::BadInput& e) {
    return e.what();
  }
  return "";
}

}  // namespace hmp::study::test
