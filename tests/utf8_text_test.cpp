// What an error line or a CSV field shows of text that may come from a file
// name: well-formed UTF-8, control characters (C0, DEL, C1) as escapes.
#include "nearcap/io/utf8_text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace nearcap {
namespace {

TEST(Utf8Text, FindsTheFirstByteOutsideWellFormedUtf8) {
  EXPECT_EQ(io::first_non_utf8("plain é ✓ 😀"), std::string::npos);
  EXPECT_EQ(io::first_non_utf8("ab\xff"), 2u);
  EXPECT_EQ(io::first_non_utf8("a\xc0\xaf"), 1u);          // overlong '/'
  EXPECT_EQ(io::first_non_utf8("a\xed\xa0\x80"), 1u);      // a surrogate
  EXPECT_EQ(io::first_non_utf8("a\xf4\x90\x80\x80"), 1u);  // past U+10FFFF
  EXPECT_EQ(io::first_non_utf8("ab\xe2\x9c"), 2u);         // cut short
}

TEST(Utf8Text, ControlCharactersAreC0DelAndC1) {
  EXPECT_EQ(io::first_control_character("plain é ✓"), std::string::npos);
  EXPECT_EQ(io::first_control_character("ab\x01"), 2u);
  EXPECT_EQ(io::first_control_character("ab\x7f"), 2u);
  EXPECT_EQ(io::first_control_character("é\xc2\x9b["), 2u);               // U+009B, CSI
  EXPECT_EQ(io::first_control_character("\xc2\xa0"), std::string::npos);  // U+00A0 is text
  EXPECT_EQ(io::first_control_character("\x9b"), std::string::npos);      // not UTF-8, not a character
}

TEST(Utf8Text, EscapesKeepTextOnOneLineOfUtf8) {
  EXPECT_EQ(io::escaped_control_characters("a\nb\rc\td"), "a\\nb\\rc\\td");
  EXPECT_EQ(io::escaped_control_characters("a\x01\x7f"), "a\\x01\\x7f");
  EXPECT_EQ(io::escaped_control_characters("a\xc2\x85z\xc2\x9b"), "a\\u0085z\\u009b");
  EXPECT_EQ(io::escaped_control_characters("x\xffy\xc3"), "x\\xffy\\xc3");
  const std::string text = "plain é ✓ 😀 \xc2\xa0";
  EXPECT_EQ(io::escaped_control_characters(text), text);
  const std::string escaped = io::escaped_control_characters("\xc2\x9b\xe2\x80\n\x80");
  EXPECT_EQ(io::first_non_utf8(escaped), std::string::npos) << escaped;
  EXPECT_EQ(io::first_control_character(escaped), std::string::npos) << escaped;
}

}  // namespace
}  // namespace nearcap
