#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "core/error.hpp"
#include "error_message.hpp"
#include "io/csv.hpp"
#include "io/raw_configurations.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

std::string message_of(const std::string& text) {
  return testing::error_message<FormatError>([&] { (void)parse_csv(text, "in.csv"); });
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

TEST(Csv, EmptyAndRepeatedColumnNamesAreColumnsButCannotBeLookedUp) {
  // pandas writes its index as a column named "" (SPEC 6 copies the columns a tool does not read); a name the
  // header holds twice is ambiguous only when a reader asks for it.
  const CsvTable t = parse_csv(",a,b,a, \n0,1,2,3,4\n", "in.csv");
  ASSERT_EQ(t.header, (std::vector<std::string>{"", "a", "b", "a", ""}));
  EXPECT_EQ(t.column("b"), 2u);
  EXPECT_EQ(t.rows[0][4], "4");
  const auto message = [&t](std::string_view name) {
    try {
      (void)t.column(name);
    } catch (const FormatError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message("a"), "'in.csv':1: duplicate column 'a' in the header");
  EXPECT_EQ(message(""), "'in.csv':1: duplicate column '' in the header");
  EXPECT_EQ(message("c"), "'in.csv':1: missing column 'c'");
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
  EXPECT_NE(ragged.find("1 fields, the header has 2 (column 2, 'b', missing)"), std::string::npos) << ragged;
  const std::string long_row = message_of("a,b\n1,2,3\n");
  EXPECT_NE(
      long_row.find("'in.csv':2: ragged row: 3 fields, the header has 2 (column 3 is beyond the header)"),
      std::string::npos)
      << long_row;
  EXPECT_EQ(
      message_of("a,b\n1,\"2\n"),
      "'in.csv':2: column 2 ('b'): unterminated quoted field (no closing '\"' before the end of the file)");
  // The line the quote opens on, after a record whose quoted field spans lines; in the header: no name.
  EXPECT_EQ(
      message_of("a,b\n\"x\ny\",\"2\n\n"),
      "'in.csv':3: column 2 ('b'): unterminated quoted field (no closing '\"' before the end of the file)");
  EXPECT_EQ(message_of("a,\"b\n1,2\n"),
            "'in.csv':1: column 2: unterminated quoted field (no closing '\"' before the end of the file)");
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

TEST(Csv, AHugeFieldIsQuotedShortInMessages) {
  // Issue 12: a 10 MB field was copied whole into the error message.
  const std::string huge(10'000'000, 'x');
  const CsvTable t = parse_csv("ax,ay\n1," + huge + "\n", "in.csv");
  try {
    (void)t.number(0, 1);
    FAIL();
  } catch (const FormatError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m, "'in.csv':2: column 'ay': '" + std::string(kQuotedBytes, 'x') +
                     "...' (10000000 bytes) is not a number");
  }
  EXPECT_EQ(quote_text("short"), "'short'");
  EXPECT_EQ(quote_text(std::string(kQuotedBytes, 'y')), "'" + std::string(kQuotedBytes, 'y') + "'");
  std::string duplicate = "(no error)";
  try {
    (void)parse_csv(huge + "," + huge + "\n1,2\n", "in.csv").column(huge);
  } catch (const FormatError& e) {
    duplicate = e.what();
  }
  EXPECT_LT(duplicate.size(), 200u) << duplicate.substr(0, 200);
  EXPECT_NE(duplicate.find("duplicate column"), std::string::npos) << duplicate.substr(0, 200);
  EXPECT_NE(duplicate.find("(10000000 bytes)"), std::string::npos) << duplicate.substr(0, 200);
}

TEST(Csv, OtherEncodingsAndLineEndsAreNamed) {
  EXPECT_NE(message_of(std::string("\xFF\xFE"
                                   "a\0,\0b\0\n\0",
                                   10))
                .find("UTF-16 (little-endian)"),
            std::string::npos);
  EXPECT_NE(message_of(std::string("\xFE\xFF\0a\0,\0b\0\n", 10)).find("UTF-16 (big-endian)"),
            std::string::npos);
  EXPECT_NE(message_of(std::string("\xFF\xFE\0\0a\0\0\0", 8)).find("UTF-32 (little-endian)"),
            std::string::npos);
  const std::string no_mark =
      message_of(std::string("a\0,\0b\0\n\0"
                             "1\0,\0"
                             "2\0\n\0",
                             16));
  EXPECT_NE(no_mark.find("'in.csv':1: the header holds NUL bytes: UTF-16 text without a byte-order mark"),
            std::string::npos)
      << no_mark;
  const std::string cr_only = message_of("a,b\r1,2\r3,4\r");
  EXPECT_NE(cr_only.find("'in.csv':1: carriage return without a line feed (a file with CR-only line ends?)"),
            std::string::npos)
      << cr_only;
  // CRLF, and a CR as the very last byte, are line ends; a CR inside quotes is text.
  const CsvTable t = parse_csv("a,b\r\n1,\"x\ry\"\r\n2,3\r", "in.csv");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0][1], "x\ry");
  EXPECT_EQ(t.rows[1][1], "3");
}

TEST(Csv, StreamingAFileEqualsParsingItWhole) {
  // A file several read buffers long, with quoted fields holding commas, quotes and line breaks that fall
  // across buffer boundaries: CsvReader over the file and parse_csv over the text give the same records.
  std::mt19937_64 rng(8);
  std::string text = "id,value,note\n";
  std::uniform_int_distribution<int> length(0, 300);
  for (int i = 0; i < 20000; ++i) {
    std::string note(static_cast<std::size_t>(length(rng)), 'n');
    for (char& c : note) c = "ab,\"\n x"[rng() % 8];
    std::string quoted = "\"";
    for (char c : note) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    text += std::to_string(i) + "," + std::to_string(i * 0.5) + "," + quoted + "\"" +
            (i % 3 == 0 ? "\r\n" : "\n");
  }
  ASSERT_GT(text.size(), 3u << 20);
  const auto path = testing::test_output_dir("test-io") / "stream.csv";
  std::ofstream(path, std::ios::binary) << text;
  const CsvTable whole = parse_csv(text, path);
  const CsvTable streamed = read_csv(path);
  EXPECT_EQ(streamed.header, whole.header);
  EXPECT_EQ(streamed.line_numbers, whole.line_numbers);
  ASSERT_EQ(streamed.rows.size(), 20000u);
  EXPECT_TRUE(streamed.rows == whole.rows);
}

TEST(Csv, ALateErrorInAStreamedFileLeavesNoOutput) {
  // map_raw_configurations writes chunk by chunk to a temporary: a bad field in the last chunk, after
  // earlier chunks were written, leaves neither the output nor a temporary, and names file, line, column.
  const auto dir = testing::test_output_dir("test-io") / "late-error";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::string text = "ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz\n";
  for (int i = 0; i < 100; ++i) text += "0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,0.1\n";
  text += "0,0,0,1,0,0,1,1,0,0,1,0,0.3,oops,0.1\n";
  std::ofstream(dir / "in.csv") << text;
  std::size_t chunks = 0;
  try {
    (void)map_raw_configurations(
        dir / "in.csv", dir / "out.csv", SurfaceKind::kBilinear, {"x"},
        [&](const RawChunk& chunk, std::vector<std::vector<std::string>>& rows) {
          ++chunks;
          for (std::size_t i = 0; i < chunk.size(); ++i) rows[i] = {"1"};
        },
        nullptr, 7);
    FAIL() << "the bad field was not reported";
  } catch (const FormatError& e) {
    EXPECT_EQ(std::string(e.what()),
              "'" + (dir / "in.csv").string() + "':102: column 'sy': 'oops' is not a number");
  }
  EXPECT_EQ(chunks, 14u);  // 98 good rows in chunks of 7 were computed and written before the error
  std::vector<std::string> left;
  for (const auto& e : std::filesystem::directory_iterator(dir)) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"in.csv"});
}

TEST(Csv, StreamedOutputEqualsTheRowsComputed) {
  // Chunks of every size give the same bytes: the header and rows in input order, extra columns appended
  // and an input column of the same name replaced.
  const auto dir = testing::test_output_dir("test-io") / "chunked";
  std::filesystem::create_directories(dir);
  std::string text = "id,ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz,x,note\n";
  for (int i = 0; i < 50; ++i) {
    text += std::to_string(i) + ",0,0,0,1,0,0,1,1,0,0,1,0,0.3," + std::to_string(i) +
            ",0.1,old,\"a, \"\"b\"\"\"\n";
  }
  std::ofstream(dir / "in.csv") << text;
  std::string expected = "id,ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz,note,x\n";
  for (int i = 0; i < 50; ++i) {
    expected += std::to_string(i) + ",0,0,0,1,0,0,1,1,0,0,1,0,0.3," + std::to_string(i) +
                ",0.1,\"a, \"\"b\"\"\"," + std::to_string(i) + "\n";
  }
  for (const std::size_t chunk_rows : {std::size_t{1}, std::size_t{7}, std::size_t{50}, kRawChunkRows}) {
    std::vector<std::string> replaced;
    const std::size_t n = map_raw_configurations(
        dir / "in.csv", dir / "out.csv", SurfaceKind::kBilinear, {"x"},
        [](const RawChunk& chunk, std::vector<std::vector<std::string>>& rows) {
          for (std::size_t i = 0; i < chunk.size(); ++i) rows[i] = {format_double(chunk.configs[i].slave[1])};
        },
        &replaced, chunk_rows);
    EXPECT_EQ(n, 50u);
    EXPECT_EQ(replaced, std::vector<std::string>{"x"});
    std::ifstream in(dir / "out.csv", std::ios::binary);
    const std::string got{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_EQ(got, expected) << "chunk " << chunk_rows;
  }
}

TEST(RawConfigurations, RowsWithoutCoordinatesAreNoSegmentRowsOthersMustBeNumbers) {
  // SPEC 7: a pairs file is a RAW.csv; a slave node without a segment has every field after `slave` empty.
  const std::string text =
      "slave,ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz,status\n"
      "1,0,0,0,1,0,0,1,1,0,0,1,0,0.3,0.4,0.1,ok\n"
      "2,,,,,,,,,,,,,,,,no_segment\n"
      "3,0,0,0,1,0,0,1,1,0,0,1,0,0.3,,0.1,ok\n";
  RawConfigurationReader reader(text, "pairs.csv", SurfaceKind::kBilinear);
  RawChunk chunk;
  try {
    (void)reader.next_chunk(chunk, 10);
    FAIL() << "the partly empty row was accepted";
  } catch (const FormatError& e) {
    EXPECT_EQ(std::string(e.what()), "'pairs.csv':4: column 'sy': '' is not a number");
  }
  const std::string first_two = text.substr(0, text.find("\n3,") + 1);
  RawConfigurationReader two(first_two, "pairs.csv", SurfaceKind::kBilinear);
  ASSERT_TRUE(two.next_chunk(chunk, 10));
  ASSERT_EQ(chunk.size(), 2u);
  EXPECT_EQ(chunk.no_segment, (std::vector<std::uint8_t>{0, 1}));
  EXPECT_TRUE(std::isnan(chunk.configs[1].slave.x()));
  EXPECT_EQ(chunk.configs[0].slave.y(), 0.4);
}

TEST(RawConfigurations, AHeaderAloneIsNoRowsWhereRowsMayBeNoneAndAnErrorElsewhere) {
  // SPEC 7: the pairs file of a pair without slave nodes is a header alone, and valid input for the tools'
  // input modes; a dataset (report mode) still needs rows. An empty file is an error either way.
  const std::string header = "slave,ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz\n";
  RawConfigurationReader none(header, "pairs.csv", SurfaceKind::kBilinear, DataRows::kMayBeNone);
  EXPECT_EQ(none.header().size(), 16u);
  RawChunk chunk;
  EXPECT_FALSE(none.next_chunk(chunk, 10));
  EXPECT_EQ(chunk.size(), 0u);
  EXPECT_EQ(parse_raw_configurations(header, "pairs.csv", SurfaceKind::kBilinear).configs.size(), 0u);
  try {
    RawConfigurationReader required(header, "pairs.csv", SurfaceKind::kBilinear);
    FAIL() << "a header alone was accepted where rows are required";
  } catch (const FormatError& e) {
    EXPECT_EQ(std::string(e.what()), "'pairs.csv': header only: expected at least one data row");
  }
  EXPECT_THROW(RawConfigurationReader("", "pairs.csv", SurfaceKind::kBilinear, DataRows::kMayBeNone),
               FormatError);
  // The columns are still checked.
  EXPECT_THROW(RawConfigurationReader("ax,ay\n", "pairs.csv", SurfaceKind::kBilinear, DataRows::kMayBeNone),
               FormatError);
}

}  // namespace
}  // namespace contactnn::io
