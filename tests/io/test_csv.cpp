#include "io/csv.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"

namespace contactnn::io {
namespace {

std::string message_of(const std::string& text) {
  try {
    (void)parse_csv(text, "in.csv");
  } catch (const FormatError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Csv, ParsesColumnsQuotesCrlfAndBlankLines) {
  const CsvTable t = parse_csv("a,b,\"c,d\"\r\n1,\"x \"\"y\"\"\",3\r\n\r\n4,5,6\n", "in.csv");
  ASSERT_EQ(t.header.size(), 3u);
  EXPECT_EQ(t.header[2], "c,d");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0][1], "x \"y\"");
  EXPECT_EQ(t.line_numbers[0], 2u);
  EXPECT_EQ(t.line_numbers[1], 4u);  // the blank line 3 is skipped but counted
  EXPECT_EQ(t.column("b"), 1u);
  EXPECT_DOUBLE_EQ(t.number(1, 2), 6.0);
}

TEST(Csv, NumbersAcceptNanInfAndSignsButNotText) {
  double v = 0;
  EXPECT_TRUE(parse_double(" 1.5e3 ", v));
  EXPECT_DOUBLE_EQ(v, 1500.0);
  EXPECT_TRUE(parse_double("+2", v));
  EXPECT_DOUBLE_EQ(v, 2.0);
  EXPECT_TRUE(parse_double("nan", v));
  EXPECT_TRUE(std::isnan(v));
  EXPECT_TRUE(parse_double("-INF", v));
  EXPECT_TRUE(std::isinf(v) && v < 0);
  EXPECT_FALSE(parse_double("1.5x", v));
  EXPECT_FALSE(parse_double("", v));
  EXPECT_FALSE(parse_double("one", v));
  EXPECT_FALSE(parse_double("1,5", v));
}

TEST(Csv, EveryMalformedCaseNamesFileLineAndWhat) {
  EXPECT_NE(message_of("").find("empty file"), std::string::npos);
  EXPECT_NE(message_of("a,b\n").find("header only"), std::string::npos);
  const std::string ragged = message_of("a,b\n1,2\n3\n");
  EXPECT_NE(ragged.find("'in.csv':3"), std::string::npos) << ragged;
  EXPECT_NE(ragged.find("1 fields, the header has 2"), std::string::npos) << ragged;
  EXPECT_NE(message_of("a,b,a\n1,2,3\n").find("duplicate column 'a'"), std::string::npos);
  EXPECT_NE(message_of("a,b\n1,\"2\n").find("unterminated"), std::string::npos);
  const CsvTable t = parse_csv("ax,ay\n1,2\n3,oops\n", "in.csv");
  try {
    (void)t.number(1, 1);
    FAIL();
  } catch (const FormatError& e) {
    EXPECT_EQ(std::string(e.what()), "'in.csv':3: column 'ay': 'oops' is not a number");
  }
  try {
    (void)t.column("az");
    FAIL();
  } catch (const FormatError& e) {
    EXPECT_EQ(std::string(e.what()), "'in.csv':1: missing column 'az'");
  }
}

TEST(Csv, WritingQuotesWhatNeedsItAndDoublesRoundTrip) {
  std::string out;
  append_csv_row(out, {"plain", "a,b", "say \"hi\""});
  EXPECT_EQ(out, "plain,\"a,b\",\"say \"\"hi\"\"\"\n");
  for (double x : {0.1, 1.0 / 3.0, -2.5e-300, 123456789.123456789}) {
    double back = 0;
    ASSERT_TRUE(parse_double(format_double(x), back));
    EXPECT_EQ(back, x);
  }
}

}  // namespace
}  // namespace contactnn::io
