// Quoting bytes in messages (host/common/printable.hpp): nothing a user's file holds reaches a message
// raw — a NUL does not end it, invalid UTF-8 and control characters are shown as escapes.
#include <gtest/gtest.h>

#include <string>

#include "host/common/printable.hpp"

namespace {

using hmp::kTerminalLineMaxBytes;
using hmp::printable;
using hmp::terminal_line;
using hmp::valid_utf8;
using namespace std::string_literals;

TEST(Printable, TextStaysAsItIs) {
  EXPECT_EQ(printable("plain, text 1.0"), "plain, text 1.0");
  EXPECT_EQ(printable("Kendall’s W ≥ 0 — 🎻"), "Kendall’s W ≥ 0 — 🎻");
  EXPECT_EQ(printable(""), "");
}

TEST(Printable, NulAndControlCharactersAreEscaped) {
  EXPECT_EQ(printable("a\0b"s), "a\\0b");
  EXPECT_EQ(printable("\0"s), "\\0");
  EXPECT_EQ(printable("l1\nl2\r\tx"), "l1\\nl2\\r\\tx");
  EXPECT_EQ(printable("\x1B[31mred"), "\\x1B[31mred");  // a terminal escape sequence, made harmless
  EXPECT_EQ(printable("\x7F"), "\\x7F");
  EXPECT_EQ(printable("back\\slash"), "back\\\\slash");
  EXPECT_EQ(printable("\xC2\x9B"
                      "2J"),
            "\\u009B2J");  // C1 CSI
}

TEST(Printable, InvalidUtf8BytesAreEscapedOneByOne) {
  EXPECT_EQ(printable("v\xFF"
                      "1"),
            "v\\xFF1");
  EXPECT_EQ(printable("caf\xE9"), "caf\\xE9");                       // Latin-1 é
  EXPECT_EQ(printable("\xE2\x82"), "\\xE2\\x82");                    // cut short
  EXPECT_EQ(printable("\xC0\xAF"), "\\xC0\\xAF");                    // overlong '/'
  EXPECT_EQ(printable("\xED\xA0\x80"), "\\xED\\xA0\\x80");           // a surrogate
  EXPECT_EQ(printable("\xF4\x90\x80\x80"), "\\xF4\\x90\\x80\\x80");  // past U+10FFFF
  EXPECT_EQ(printable("\x80"
                      "é"),
            "\\x80é");  // stray continuation, then valid text
}

TEST(TerminalLine, EscapesControlsAndBrokenBytesKeepsBackslashesAndText) {
  EXPECT_EQ(terminal_line("--mapping a\x01"
                          "b: unknown"),
            "--mapping a\\x01b: unknown");
  EXPECT_EQ(terminal_line("two\nlines\r\x1b[2J"), "two\\nlines\\r\\x1B[2J");  // one line, no terminal command
  EXPECT_EQ(terminal_line("caf\xE9 \xC2\x9B"), "caf\\xE9 \\u009B");           // not UTF-8; a C1 control
  // A message already escaped by printable() reads the same: its backslashes are not doubled.
  EXPECT_EQ(terminal_line(printable("p\0001"s)), "p\\01");
  EXPECT_EQ(terminal_line("0 < min ≤ max, 🎻"), "0 < min ≤ max, 🎻");
}

TEST(TerminalLine, CutsALongMessageAtACharacterAndCountsTheRest) {
  EXPECT_EQ(terminal_line(std::string(10, 'x'), 10), std::string(10, 'x'));
  EXPECT_EQ(terminal_line(std::string(11, 'x'), 10), std::string(10, 'x') + "… (1 bytes more)");
  // 'é' is 2 bytes: the cut falls after a whole one, never inside it.
  EXPECT_EQ(terminal_line("aéé", 2), "aé… (2 bytes more)");
  const std::string huge(100000, 'y');
  const std::string line = terminal_line("unknown preset '" + huge + "'");
  EXPECT_LE(line.size(), kTerminalLineMaxBytes + 40);
  EXPECT_TRUE(line.ends_with("… (99017 bytes more)")) << line.substr(line.size() - 40);
}

TEST(ValidUtf8, AcceptsTextRefusesBrokenSequences) {
  EXPECT_TRUE(valid_utf8(""));
  EXPECT_TRUE(valid_utf8("ascii"));
  EXPECT_TRUE(valid_utf8("é ≥ 🎻 \xF4\x8F\xBF\xBF"));  // U+10FFFF is the last
  EXPECT_TRUE(valid_utf8("a\0b"s));                   // valid UTF-8; whether a NUL is welcome is the reader's call
  EXPECT_FALSE(valid_utf8("\xFF"));
  EXPECT_FALSE(valid_utf8("caf\xE9"));
  EXPECT_FALSE(valid_utf8("\xE2\x82"));
  EXPECT_FALSE(valid_utf8("\xC0\xAF"));
  EXPECT_FALSE(valid_utf8("\xE0\x80\xAF"));
  EXPECT_FALSE(valid_utf8("\xED\xA0\x80"));
  EXPECT_FALSE(valid_utf8("\xF4\x90\x80\x80"));
  EXPECT_FALSE(valid_utf8("\xF5\x80\x80\x80"));
}

}  // namespace
