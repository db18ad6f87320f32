// log_text: client and file text escaped and bounded for one log line.
#include <gtest/gtest.h>

#include <string>

#include "sim/log_text.h"

namespace tumble::sim {
namespace {

TEST(LogText, PrintableTextIsKeptAsItIs) {
  EXPECT_EQ(log_text("crate-7 (blue)"), "crate-7 (blue)");
  EXPECT_EQ(log_text(""), "");
  // Valid UTF-8 beyond ASCII: two-, three- and four-byte characters.
  EXPECT_EQ(log_text("Kiste \xc3\xa4 \xe2\x82\xac \xf0\x9f\x93\xa6"), "Kiste \xc3\xa4 \xe2\x82\xac \xf0\x9f\x93\xa6");
}

TEST(LogText, ANewlineCannotStartAForgedLine) {
  EXPECT_EQ(log_text("bob\n2099-01-01 info [net] FAKE LINE"), "bob\\n2099-01-01 info [net] FAKE LINE");
  EXPECT_EQ(log_text("a\rb\tc"), "a\\rb\\tc");
}

TEST(LogText, TerminalEscapesAndControlBytesAreWrittenAsHex) {
  EXPECT_EQ(log_text("\x1b[2J\x1b]0;owned\x07"), "\\x1b[2J\\x1b]0;owned\\x07");
  EXPECT_EQ(log_text(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(log_text("\x7f"), "\\x7f");
  // A backslash is doubled, so an escape in the log is never the client's own text.
  EXPECT_EQ(log_text("\\x1b"), "\\\\x1b");
}

TEST(LogText, UnicodeControlsAndLineSeparatorsAreEscaped) {
  const std::string csi = "\xc2\x9b";                 // C1 CONTROL SEQUENCE INTRODUCER
  const std::string line_separator = "\xe2\x80\xa8";  // U+2028
  const std::string right_to_left = "\xe2\x80\xae";   // U+202E RIGHT-TO-LEFT OVERRIDE
  EXPECT_EQ(log_text(csi + "31m"), "\\u{009b}31m");
  EXPECT_EQ(log_text("a" + line_separator + "b"), "a\\u{2028}b");
  EXPECT_EQ(log_text(right_to_left + "gnp.exe"), "\\u{202e}gnp.exe");
}

TEST(LogText, InvalidUtf8IsWrittenByteByByte) {
  EXPECT_EQ(log_text("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(log_text("a\xc3"), "a\\xc3");                           // cut short
  EXPECT_EQ(log_text("\xc0\xaf"), "\\xc0\\xaf");                    // overlong '/'
  EXPECT_EQ(log_text("\xed\xa0\x80"), "\\xed\\xa0\\x80");           // a surrogate
  EXPECT_EQ(log_text("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
  EXPECT_EQ(log_text("\xe2\x28\xa1"), "\\xe2(\\xa1");               // a bad continuation byte
}

TEST(LogText, LongTextIsCutAndSaysHowMuchIsLeftOut) {
  const std::string name(1000000, 'x');
  EXPECT_EQ(log_text(name), std::string(96, 'x') + "...(999904 more bytes)");
  EXPECT_EQ(log_text(std::string(96, 'y')), std::string(96, 'y'));
  EXPECT_EQ(log_text("abcdef", 4), "abcd...(2 more bytes)");
  // The bound counts the escaped text, and never splits an escape or a character.
  EXPECT_EQ(log_text("ab\ncd", 3), "ab...(3 more bytes)");
  EXPECT_EQ(log_text("a\xe2\x82\xac", 3), "a...(3 more bytes)");
}

}  // namespace
}  // namespace tumble::sim
