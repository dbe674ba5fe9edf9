#include "groundline/core/text_parse.h"

#include <gtest/gtest.h>

#include <cmath>

namespace groundline::core {
namespace {

TEST(TextParse, ParseDoubleIsStrict) {
  EXPECT_EQ(ParseDouble("1e-3"), 1e-3);
  EXPECT_EQ(ParseDouble("+2.5"), 2.5);
  EXPECT_EQ(ParseDouble("-0.5"), -0.5);
  EXPECT_FALSE(ParseDouble("").has_value());
  EXPECT_FALSE(ParseDouble("+").has_value());
  EXPECT_FALSE(ParseDouble("+-1").has_value());
  EXPECT_FALSE(ParseDouble("1.5x").has_value());
  EXPECT_FALSE(ParseDouble(" 1").has_value());
  // Non-finite values parse; callers report them as such.
  EXPECT_TRUE(std::isnan(*ParseDouble("nan")));
}

TEST(TextParse, ParseIntIsStrict) {
  EXPECT_EQ(ParseInt("+42"), 42);
  EXPECT_EQ(ParseInt("-7"), -7);
  EXPECT_FALSE(ParseInt("++1").has_value());
  EXPECT_FALSE(ParseInt("1.0").has_value());
  EXPECT_FALSE(ParseInt("99999999999999999999").has_value());
}

TEST(TextParse, SplitDelimitedKeepsEmptyFieldsAndTrims) {
  const std::vector<std::string_view> fields = SplitDelimited(" a , b,,c \r", ',');
  ASSERT_EQ(fields.size(), 4u);
  EXPECT_EQ(fields[0], "a");
  EXPECT_EQ(fields[1], "b");
  EXPECT_EQ(fields[2], "");
  EXPECT_EQ(fields[3], "c");
}

TEST(TextParse, FieldErrorNamesFileLineAndField) {
  EXPECT_EQ(FieldError("x.csv", 3, "stamp_s", "a finite number", "nan"),
            "x.csv:3: field 'stamp_s': expected a finite number, got 'nan'");
}

}  // namespace
}  // namespace groundline::core

namespace groundline::core {
namespace {

TEST(FormatDouble, ShortestRoundTripsAndYamlFormHasAMantissaPoint) {
  for (const double v : {0.1, 1e-5, -2.5e-12, 1234567.0, 0.58, 3e100, -0.0}) {
    EXPECT_EQ(*ParseDouble(FormatShortestDouble(v)), v);
    const std::string yaml = FormatYamlDouble(v);
    EXPECT_EQ(*ParseDouble(yaml), v) << yaml;
    const std::size_t e = yaml.find('e');
    if (e != std::string::npos) {
      EXPECT_NE(yaml.substr(0, e).find('.'), std::string::npos) << yaml;
    }
  }
  EXPECT_EQ(FormatYamlDouble(1e-5), "1.0e-05");
  EXPECT_EQ(FormatYamlDouble(0.58), "0.58");
}

TEST(TextParse, IsValidUtf8AcceptsUtf8AndRejectsEverythingElse) {
  for (const char* good : {"", "map", "\xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x98\x80",
                           "\xef\xbf\xbf", "\xf4\x8f\xbf\xbf"}) {
    EXPECT_TRUE(IsValidUtf8(good)) << good;
  }
  for (const char* bad : {"ma\xffp", "\x80", "\xc3", "\xc0\xaf",  // lone, cut, overlong
                          "\xe0\x80\xaf", "\xed\xa0\x80",         // overlong, surrogate
                          "\xf4\x90\x80\x80", "\xf5\x80\x80\x80", "\xc3\x28"}) {
    EXPECT_FALSE(IsValidUtf8(bad)) << bad;
  }
}

}  // namespace
}  // namespace groundline::core
