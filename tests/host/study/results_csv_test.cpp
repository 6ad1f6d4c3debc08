// The results file's text as people's tools leave it (host/study/results_csv.hpp): a spreadsheet's byte
// order mark is accepted; a field that is not UTF-8 is refused; what a message quotes from the file is
// escaped, so a NUL does not cut it short and raw bytes do not reach the terminal.
#include <gtest/gtest.h>

#include <string>

#include "host/common/error.hpp"
#include "host/study/results_csv.hpp"
#include "tests/host/study/results_error.hpp"
#include "tests/host/study/round_row.hpp"

namespace {

using namespace hmp::study;
using hmp::study::test::error_of;
using namespace std::string_literals;

// One practice round of participant p1: three rows, each envelope, key and rank once.
std::string round_text(const std::string& version = "1.0") {
  std::string text = std::string(kResultsHeader) + "\n";
  for (int i = 0; i < 3; ++i) {
    const ResultRow r = hmp::study::test::round_row("p1", "violin", i, true, 5, version);
    text += format_row(r) + "\n";
  }
  return text;
}

TEST(ResultsCsvText, AByteOrderMarkIsAccepted) {
  const std::string text = round_text();
  ASSERT_EQ(error_of(text), "");
  const auto rows = parse_results("\xEF\xBB\xBF" + text, "res.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].participant, "p1");
  EXPECT_EQ(rows[0].line, 2);
  // With Windows line ends too, as a spreadsheet writes them.
  std::string crlf;
  for (const char c : "\xEF\xBB\xBF" + text) crlf += c == '\n' ? "\r\n"s : std::string(1, c);
  EXPECT_EQ(parse_results(crlf, "res.csv").size(), 3u);
  // Only at the very start: elsewhere it is a byte of a field like any other.
  EXPECT_EQ(error_of("\n\xEF\xBB\xBF" + text), "res.csv:1: not a study results file (the header differs)");
}

TEST(ResultsCsvText, ANulIsShownNotCutAt) {
  std::string text = round_text();
  text.replace(text.find("\np1,") + 1, 2,
               "p\0"
               "1"s);
  const std::string e = error_of(text);
  EXPECT_EQ(e, "res.csv:2: bad participant id \"p\\01\"");
  std::string instrument = round_text();
  instrument.replace(instrument.find(",violin,"), 8, ",vio\0lin,"s);
  EXPECT_EQ(error_of(instrument), "res.csv:2: unknown instrument \"vio\\0lin\"");
}

TEST(ResultsCsvText, NonUtf8FieldsAreRefusedAndEscaped) {
  EXPECT_EQ(error_of(round_text("v\xFF"
                                "1")),
            "res.csv:2: version \"v\\xFF1\" is not valid UTF-8");
  EXPECT_EQ(error_of(round_text("caf\xE9")), "res.csv:2: version \"caf\\xE9\" is not valid UTF-8");
  EXPECT_EQ(error_of(round_text("v\x1B[2J")), "res.csv:2: version \"v\\x1B[2J\" holds a control character");
  EXPECT_EQ(error_of(round_text("v\0"s)), "res.csv:2: version \"v\\0\" holds a control character");
  EXPECT_EQ(error_of(round_text("v1 — café")), "");  // UTF-8 text is fine
  std::string phase = round_text();
  phase.replace(phase.find(",practice,"), 10,
                ",pr\xC3"
                "actice,");
  EXPECT_EQ(error_of(phase), "res.csv:2: phase \"pr\\xC3actice\" is not valid UTF-8");
}

TEST(ResultsCsvText, TheFileNameIsEscapedToo) {
  try {
    parse_results("nope\n", "dir/r\xFFs.csv");
    FAIL() << "no error";
  } catch (const hmp::BadInput& e) {
    EXPECT_EQ(std::string(e.what()), "dir/r\\xFFs.csv:1: not a study results file (the header differs)");
  }
}

}  // namespace
