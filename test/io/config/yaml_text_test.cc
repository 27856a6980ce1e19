// SPDX-License-Identifier: Apache-2.0
// The one YAML scalar escaper (io/config/yaml_text.h): what it writes reads back through a YAML
// reader as the same text, for quotes, control characters and bytes that are not UTF-8.

#include "io/config/yaml_text.h"

#include "common/angles.h"

#include <cmath>
#include <cstdlib>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

namespace wallcal::io {
namespace {

// The scalar as a YAML reader reads it back from `key: <scalar>`.
std::string ReadBack(const std::string& scalar) {
  return YAML::Load("key: " + scalar)["key"].as<std::string>();
}

TEST(YamlTextTest, PlainTextStaysPlain) {
  EXPECT_EQ(YamlText("north_wall"), "north_wall");
  EXPECT_EQ(YamlQuoted("north_wall"), "\"north_wall\"");
}

TEST(YamlTextTest, WordsAYamlReaderWouldTurnIntoSomethingElseAreQuoted) {
  for (const char* word : {"true", "no", "null", "~", "", "1.5", "a: b", "# c", "- d"}) {
    const std::string scalar = YamlText(word);
    EXPECT_EQ(scalar.front(), '"') << word;
    EXPECT_EQ(ReadBack(scalar), word);
  }
}

TEST(YamlTextTest, QuotesAndBackslashesAreEscaped) {
  const std::string text = "quote \" and back\\slash, 'single'";
  EXPECT_EQ(YamlQuoted(text), "\"quote \\\" and back\\\\slash, 'single'\"");
  EXPECT_EQ(ReadBack(YamlText(text)), text);
}

TEST(YamlTextTest, ControlCharactersAreEscapedNotDropped) {
  const std::string text = std::string("line\nnext\ttab\rcr ") + '\x01' + " bell" + '\x7f';
  const std::string scalar = YamlText(text);
  EXPECT_EQ(scalar, "\"line\\nnext\\ttab\\rcr \\x01 bell\\x7F\"");
  EXPECT_EQ(scalar.find('\n'), std::string::npos);  // one line in the file
  EXPECT_EQ(ReadBack(scalar), text);
}

TEST(YamlTextTest, ValidUtf8GoesThroughAndOtherBytesAreEscaped) {
  const std::string utf8 = "東京 σ ±0.1 °";
  EXPECT_EQ(ReadBack(YamlText(utf8)), utf8);
  EXPECT_NE(YamlQuoted(utf8).find(utf8), std::string::npos);
  // A Latin-1 folder name: 0xE9 is not UTF-8 on its own. It is written as \xE9, which a YAML
  // reader turns into the code point U+00E9 (é, two bytes in UTF-8): the file stays UTF-8.
  const std::string latin1 = "caf\xe9/session";
  const std::string scalar = YamlText(latin1);
  EXPECT_EQ(scalar, "\"caf\\xE9/session\"");
  EXPECT_EQ(ReadBack(scalar), "caf\xc3\xa9/session");
  // A truncated sequence (the lead byte of a 3-byte character at the end) is escaped too.
  EXPECT_EQ(YamlText("x\xe6\x9d"), "\"x\\xE6\\x9D\"");
}

}  // namespace
}  // namespace wallcal::io

namespace wallcal::io {
namespace {

// Degrees read as radians (value / kRadToDeg, as the option readers do) come back as the
// degrees written; any radians written as degrees read back to the same double where some
// decimal does, and otherwise to within a unit in the last place.
TEST(ShortestScaledTest, DegreesReadAsRadiansAreWrittenAsGiven) {
  for (const char* degrees : {"30", "-30", "23", "0.1", "179.5", "-0.25", "2.8"}) {
    const double radians = std::strtod(degrees, nullptr) / kRadToDeg;
    EXPECT_EQ(ShortestScaled(radians, kRadToDeg), degrees);
  }
  EXPECT_NE(ShortestNumber(30.0 / kRadToDeg * kRadToDeg), "30");  // what it replaces
  std::mt19937_64 random(7);
  std::uniform_int_distribution<int> millidegrees(-180000, 180000);
  std::uniform_real_distribution<double> angle(-3.5, 3.5);
  for (int i = 0; i < 2000; ++i) {
    const double given = millidegrees(random) / 1000.0;
    const double radians = given / kRadToDeg;
    const std::string text = ShortestScaled(radians, kRadToDeg);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr) / kRadToDeg, radians) << text;
    EXPECT_LE(text.size(), ShortestNumber(given).size()) << text;
    const double any = angle(random);
    const double back = std::strtod(ShortestScaled(any, kRadToDeg).c_str(), nullptr) / kRadToDeg;
    EXPECT_LE(std::abs(back - any), 2.0 * std::abs(std::nextafter(any, 10.0) - any)) << any;
  }
  EXPECT_EQ(ShortestScaled(0.0, kRadToDeg), "0");
}

}  // namespace
}  // namespace wallcal::io
