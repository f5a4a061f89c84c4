// Tests for lib/io/frd_results.* (SPEC 10): hand-written .frd files in ccx's long layout and in the short
// one, values that touch, the steps that count, CONTACT blocks; every error naming its file and line; and a
// real run of ccx (skipped where ccx is not installed).
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "mesh/contact_model.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

namespace fs = std::filesystem;
using geometry::Vec3;

// The values typed here have at most 5 significant digits, as the .frd's E12.5 holds them: they come back
// to the rounding of a decimal to double, and a coordinate plus a displacement to that of one more sum.
constexpr double kExact = 1e-13;

fs::path dir() { return testing::test_output_dir("frd_results"); }

std::string write(const std::string& name, const std::string& text) {
  const fs::path path = dir() / name;
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  return text;
}

/// `text` with line `number` (1-based) replaced by `line`.
std::string with_line(const std::string& text, int number, const std::string& line) {
  auto lines = lines_of(text);
  lines.at(static_cast<std::size_t>(number - 1)) = line;
  return joined(lines);
}

/// The first `count` lines of `text`.
std::string first_lines(const std::string& text, int count) {
  auto lines = lines_of(text);
  lines.resize(static_cast<std::size_t>(count));
  return joined(lines);
}

/// Lines `first`..`last` (1-based, inclusive) of `text`.
std::string line_range(const std::string& text, int first, int last) {
  const auto lines = lines_of(text);
  return joined({lines.begin() + (first - 1), lines.begin() + last});
}

/// `text` without line `number`.
std::string without_line(const std::string& text, int number) {
  auto lines = lines_of(text);
  lines.erase(lines.begin() + (number - 1));
  return joined(lines);
}

/// The message of the FormatError that reading `text` (written to `name`) throws; "" if it throws nothing.
std::string format_error(const std::string& name, const std::string& text) {
  const std::string path = write(name, text);
  try {
    (void)read_frd(path);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "";
}

std::string location(const std::string& name, int line) {
  return "'" + (dir() / name).string() + "':" + std::to_string(line) + ":";
}

/// The lines that open a block of displacements (D1, D2, D3, ALL) and one of contact results (COPEN ...
/// CSHEAR2), as ccx writes them: the blocks of the files below.
const std::string kDispHeader =
    " -4  DISP        4    1\n"
    " -5  D1          1    2    1    0\n"
    " -5  D2          1    2    2    0\n"
    " -5  D3          1    2    3    0\n"
    " -5  ALL         1    2    0    0    1ALL\n";
const std::string kContactHeader =
    " -4  CONTACT     6    1\n"
    " -5  COPEN       1    4    1    1\n"
    " -5  CSLIP1      1    4    2    2\n"
    " -5  CSLIP2      1    4    3    3\n"
    " -5  CPRESS      1    4    1    2\n"
    " -5  CSHEAR1     1    4    2    3\n"
    " -5  CSHEAR2     1    4    3    1\n";

// ccx 2.20's layout (long format): node block, element block, DISP and CONTACT of increment 1 (time 0.25),
// DISP of increment 2 (time 1.0, no CONTACT). Values touch their neighbours where they are negative.
// Line numbers, used by the error tests: 2C header 3, first DISP header 14 (records 20-23, " -3" 24),
// CONTACT header 26, second DISP header 38.
const std::string kLong =
    "    1C\n"
    "    1UPGM               CalculiX                                        \n"
    "    2C                             4                                     1\n"
    " -1         1 0.00000E+00 0.00000E+00 0.00000E+00\n"
    " -1         2 1.00000E+00 0.00000E+00 0.00000E+00\n"
    " -1        10 1.00000E+00 2.00000E+00 3.00000E+00\n"
    " -1       123 5.00000E-01 5.00000E-01 1.00100E+00\n"
    " -3\n"
    "    3C                             1                                     1\n"
    " -1         1    3    0    1\n"
    " -2         1         2        10       123\n"
    " -3\n"
    "    1PSTEP                         1           1           1          \n"
    "  100CL  101 2.50000E-01           4                     0    1           1\n" +
    kDispHeader +
    " -1         1 0.00000E+00 0.00000E+00 0.00000E+00\n"
    " -1         2 1.00000E-03-2.00000E-03 3.00000E-03\n"
    " -1        10-1.50000E-04-2.50000E-04-3.50000E-04\n"
    " -1       123 0.00000E+00 0.00000E+00-1.25000E-03\n"
    " -3\n"
    "    1PSTEP                         2           1           1          \n"
    "  100CL  101 2.50000E-01           2                     0    1           1\n" +
    kContactHeader +
    " -1       123-2.34698E-04 1.00000E-06-2.00000E-06 2.31699E+02 3.00000E-01-4.00000E-01\n"
    " -1        10 1.00000E-02 0.00000E+00 0.00000E+00 0.00000E+00 0.00000E+00 0.00000E+00\n"
    " -3\n"
    "    1PSTEP                         3           2           1          \n"
    "  100CL  102 1.000000000           4                     0    2           1\n" +
    kDispHeader +
    " -1         1 0.00000E+00 0.00000E+00 0.00000E+00\n"
    " -1         2 2.00000E-03-4.00000E-03 6.00000E-03\n"
    " -1        10-3.00000E-04-5.00000E-04-7.00000E-04\n"
    " -1       123 0.00000E+00 0.00000E+00-2.50000E-03\n"
    " -3\n"
    " 9999\n";

void expect_vec(const Vec3& actual, double x, double y, double z, double tol = kExact) {
  EXPECT_NEAR(actual.x(), x, tol);
  EXPECT_NEAR(actual.y(), y, tol);
  EXPECT_NEAR(actual.z(), z, tol);
}

TEST(FrdResults, ReadsCcxLongFormatNodesDispAndContact) {
  const FrdResults r = read_frd(write("long.frd", kLong));
  EXPECT_EQ(r.node_block_line, 3);
  ASSERT_EQ(r.node_ids, (std::vector<long>{1, 2, 10, 123}));
  expect_vec(r.coordinates[2], 1.0, 2.0, 3.0);
  expect_vec(r.coordinates[3], 0.5, 0.5, 1.001);

  ASSERT_EQ(r.increments.size(), 2u);
  const FrdIncrement& a = r.increments[0];
  EXPECT_EQ(a.number, 1);
  EXPECT_EQ(a.step, 1);
  EXPECT_EQ(a.increment_in_step, 1);
  EXPECT_EQ(a.analysis_type, 0);
  EXPECT_EQ(a.output_counter, 1);
  EXPECT_DOUBLE_EQ(a.time, 0.25);
  EXPECT_EQ(a.line, 14);
  ASSERT_EQ(a.disp_nodes, (std::vector<long>{1, 2, 10, 123}));
  expect_vec(a.displacement[1], 1e-3, -2e-3, 3e-3);
  expect_vec(a.displacement[2], -1.5e-4, -2.5e-4, -3.5e-4);  // three values touching
  expect_vec(a.displacement[3], 0.0, 0.0, -1.25e-3);

  // The CONTACT records come in ccx's order (123, 10) and are kept in increasing node id.
  ASSERT_EQ(a.contact.size(), 2u);
  EXPECT_EQ(a.contact[0].node, 10);
  EXPECT_DOUBLE_EQ(a.contact[0].copen, 1e-2);
  EXPECT_EQ(a.contact[1].node, 123);
  EXPECT_DOUBLE_EQ(a.contact[1].copen, -2.34698e-4);
  EXPECT_DOUBLE_EQ(a.contact[1].cslip1, 1e-6);
  EXPECT_DOUBLE_EQ(a.contact[1].cslip2, -2e-6);
  EXPECT_TRUE(a.contact[1].has_stress);
  EXPECT_DOUBLE_EQ(a.contact[1].cpress, 231.699);
  EXPECT_DOUBLE_EQ(a.contact[1].cshear1, 0.3);
  EXPECT_DOUBLE_EQ(a.contact[1].cshear2, -0.4);

  const FrdIncrement& b = r.increments[1];
  EXPECT_EQ(b.number, 2);
  EXPECT_EQ(b.step, 1);
  EXPECT_EQ(b.increment_in_step, 2);
  EXPECT_DOUBLE_EQ(b.time, 1.0);  // ccx writes times >= 1 in fixed point: "1.000000000"
  EXPECT_EQ(b.line, 38);
  expect_vec(b.displacement[2], -3e-4, -5e-4, -7e-4);
  EXPECT_TRUE(b.contact.empty());
}

TEST(FrdResults, ReadsShortFormatWhereFiveDigitIdsTouchTheKey) {
  // CGX's short format: ids I5 right after " -1", so " -112345" is node 12345; no 1PSTEP, no " 9999".
  const std::string text =
      "    1Cshort\n"
      "    2C                             3                                     0\n"
      " -1    7 0.00000E+00 0.00000E+00-1.00000E+00\n"
      " -112345-2.50000E-01 1.50000E+00-2.00000E+00\n"
      " -199999 3.00000E+00-4.00000E+00 5.00000E+00\n"
      " -3\n"
      "  100CL  101 5.00000E-01           3                     0    1           0\n"
      " -4  DISP        3    1\n"
      " -5  D1          1    2    1    0\n"
      " -5  D2          1    2    2    0\n"
      " -5  D3          1    2    3    0\n"
      " -1    7 0.00000E+00 0.00000E+00 0.00000E+00\n"
      " -112345-1.61361E-04-1.61361E-04-7.53348E-04\n"
      " -199999 1.00000E+00-2.00000E+00 3.00000E+00\n"
      " -3\n";
  const FrdResults r = read_frd(write("short.frd", text));
  ASSERT_EQ(r.node_ids, (std::vector<long>{7, 12345, 99999}));
  expect_vec(r.coordinates[1], -0.25, 1.5, -2.0);
  ASSERT_EQ(r.increments.size(), 1u);
  EXPECT_EQ(r.increments[0].step, 0);  // no 1PSTEP record
  EXPECT_DOUBLE_EQ(r.increments[0].time, 0.5);
  ASSERT_EQ(r.increments[0].disp_nodes, (std::vector<long>{7, 12345, 99999}));
  expect_vec(r.increments[0].displacement[1], -1.61361e-4, -1.61361e-4, -7.53348e-4);
  expect_vec(r.increments[0].displacement[2], 1.0, -2.0, 3.0);
}

// A static step (1 output), a frequency step (2 mode shapes: ICTYPE 2, MODAL), a dynamic step (ICTYPE 1,
// with CONTACT), as ccx 2.20 writes them; a STRESS block with a continuation record is skipped.
const std::string kSteps =
    "    2C                             2                                     1\n"
    " -1         1 0.00000E+00 0.00000E+00 0.00000E+00\n"
    " -1         2 1.00000E+00 0.00000E+00 0.00000E+00\n"
    " -3\n"
    "    1PSTEP                         1           1           1          \n"
    "  100CL  101 1.000000000           2                     0    1           1\n" +
    kDispHeader +
    " -1         1 1.00000E+00 0.00000E+00 0.00000E+00\n"
    " -1         2 2.00000E+00 0.00000E+00 0.00000E+00\n"
    " -3\n"
    "    1PSTEP                         2           1           1          \n"
    "  100CL  101 1.000000000           2                     0    1           1\n"
    " -4  STRESS      7    1\n"
    " -5  SXX         1    4    1    1\n"
    " -5  SYY         1    4    2    2\n"
    " -5  SZZ         1    4    3    3\n"
    " -5  SXY         1    4    1    2\n"
    " -5  SYZ         1    4    2    3\n"
    " -5  SZX         1    4    3    1\n"
    " -5  EXTRA       1    1    0    0\n"
    " -1         1 1.00000E+00 2.00000E+00 3.00000E+00 4.00000E+00 5.00000E+00 6.00000E+00\n"
    " -2           7.00000E+00\n"
    " -1         2 1.00000E+00 2.00000E+00 3.00000E+00 4.00000E+00 5.00000E+00 6.00000E+00\n"
    " -2           7.00000E+00\n"
    " -3\n"
    "    1PSTEP                         3           1           2          \n"
    "    1PGM                1.000000E+00                                  \n"
    "    1PMODE                         1                                  \n"
    "  100CL  102 654708.0902           2                     2    2MODAL      1\n" +
    kDispHeader +
    " -1         1 5.00000E-01 0.00000E+00 0.00000E+00\n"
    " -1         2 5.00000E-01 0.00000E+00 0.00000E+00\n"
    " -3\n"
    "    1PSTEP                         4           1           2          \n"
    "    1PMODE                         2                                  \n"
    "  100CL  103 887067.0158           2                     2    3MODAL      1\n" +
    kDispHeader +
    " -1         1 0.00000E+00 5.00000E-01 0.00000E+00\n"
    " -1         2 0.00000E+00 5.00000E-01 0.00000E+00\n"
    " -3\n"
    "    1PSTEP                         5           1           3          \n"
    "  100CL  104 1.500000000           2                     1    4           1\n" +
    kDispHeader +
    " -1         1 0.00000E+00 0.00000E+00 3.00000E+00\n"
    " -1         2 0.00000E+00 0.00000E+00 4.00000E+00\n"
    " -3\n"
    "    1PSTEP                         6           1           3          \n"
    "  100CL  104 1.500000000           1                     1    4           1\n" +
    kContactHeader +
    " -1         2-5.00000E-05 0.00000E+00 0.00000E+00 5.00000E+01 0.00000E+00 0.00000E+00\n"
    " -3\n"
    " 9999\n";

TEST(FrdResults, CountsDispOfStaticAndDynamicStepsOnly) {
  const FrdResults r = read_frd(write("steps.frd", kSteps));
  ASSERT_EQ(r.increments.size(), 2u);
  EXPECT_EQ(r.increments[0].step, 1);
  EXPECT_EQ(r.increments[0].analysis_type, 0);
  expect_vec(r.increments[0].displacement[1], 2.0, 0.0, 0.0);
  EXPECT_TRUE(r.increments[0].contact.empty());
  EXPECT_EQ(r.increments[1].number, 2);
  EXPECT_EQ(r.increments[1].step, 3);
  EXPECT_EQ(r.increments[1].analysis_type, 1);
  EXPECT_EQ(r.increments[1].output_counter, 4);
  EXPECT_DOUBLE_EQ(r.increments[1].time, 1.5);
  expect_vec(r.increments[1].displacement[1], 0.0, 0.0, 4.0);
  ASSERT_EQ(r.increments[1].contact.size(), 1u);
  EXPECT_EQ(r.increments[1].contact[0].node, 2);
  EXPECT_DOUBLE_EQ(r.increments[1].contact[0].copen, -5e-5);
  EXPECT_DOUBLE_EQ(r.increments[1].contact[0].cpress, 50.0);

  EXPECT_EQ(increment_index(r, 1), 0u);
  EXPECT_EQ(increment_index(r, 2), 1u);
  EXPECT_EQ(increment_index(r, kLastIncrement), 1u);
  for (int bad : {0, 3, -2}) {
    try {
      (void)increment_index(r, bad);
      ADD_FAILURE() << "increment " << bad << " accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("holds 2"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("steps.frd"), std::string::npos) << e.what();
    }
  }
}

TEST(FrdResults, FindsComponentsByNameAndReadsContinuationRecords) {
  // A DISP block listing its components in another order, with more than 6 values per node (a " -2"
  // record carries the 7th); a CONTACT block with the three CDIS components only.
  const std::string text =
      "    2C                             1                                     1\n"
      " -1         5 1.00000E+00 1.00000E+00 1.00000E+00\n"
      " -3\n"
      "  100CL  101 1.00000E-01           1                     0    1           1\n"
      " -4  DISP        8    1\n"
      " -5  ALL         1    2    0    0    1ALL\n"
      " -5  X1          1    1    0    0\n"
      " -5  D3          1    2    3    0\n"
      " -5  X2          1    1    0    0\n"
      " -5  X3          1    1    0    0\n"
      " -5  X4          1    1    0    0\n"
      " -5  D2          1    2    2    0\n"
      " -5  D1          1    2    1    0\n"
      " -1         5 9.00000E+00 3.00000E-03 9.00000E+00 9.00000E+00 9.00000E+00 2.00000E-03\n"
      " -2           1.00000E-03\n"
      " -3\n"
      "  100CL  101 1.00000E-01           1                     0    1           1\n"
      " -4  CONTACT     3    1\n"
      " -5  CSLIP2      1    1    0    0\n"
      " -5  COPEN       1    1    0    0\n"
      " -5  CSLIP1      1    1    0    0\n"
      " -1         5 3.00000E-01 1.00000E-01 2.00000E-01\n"
      " -3\n";
  const FrdResults r = read_frd(write("components.frd", text));
  ASSERT_EQ(r.increments.size(), 1u);
  expect_vec(r.increments[0].displacement[0], 1e-3, 2e-3, 3e-3);
  ASSERT_EQ(r.increments[0].contact.size(), 1u);
  const FrdContact& c = r.increments[0].contact[0];
  EXPECT_DOUBLE_EQ(c.copen, 0.1);
  EXPECT_DOUBLE_EQ(c.cslip1, 0.2);
  EXPECT_DOUBLE_EQ(c.cslip2, 0.3);
  EXPECT_FALSE(c.has_stress);
}

TEST(FrdResults, AcceptsCrlfLineEnds) {
  std::string text;
  for (const auto& line : lines_of(kLong)) text += line + "\r\n";
  const FrdResults r = read_frd(write("crlf.frd", text));
  ASSERT_EQ(r.increments.size(), 2u);
  expect_vec(r.increments[1].displacement[3], 0.0, 0.0, -2.5e-3);
}

struct BadFile {
  std::string name;
  std::string text;
  int line;              // the line the message must name
  std::string expected;  // a part of the message
};

TEST(FrdResults, MalformedFilesNameFileAndLine) {
  const std::vector<BadFile> cases = {
      {"truncated_disp.frd", first_lines(kLong, 22), 22, "truncated"},
      {"truncated_nodes.frd", without_line(kLong, 8), 8, "expected a node record ' -1'"},
      {"bad_number.frd", with_line(kLong, 21, " -1         2 1.00000E-03-2.0000xE-03 3.00000E-03"), 21,
       "columns 26-37"},
      {"not_finite.frd", with_line(kLong, 22, " -1        10-1.50000E-04         nan-3.50000E-04"), 22,
       "not a finite number"},
      {"short_record.frd", with_line(kLong, 23, " -1       123 0.00000E+00 0.00000E+00"), 23, "too short"},
      {"extra_value.frd", with_line(kLong, 23, " -1       123 0.00000E+00 0.00000E+00-1.25000E-03 1.0E+00"),
       23, "unexpected text after the 3 values"},
      {"bad_node_id.frd", with_line(kLong, 6, " -1       1x0 1.00000E+00 2.00000E+00 3.00000E+00"), 6,
       "node id (columns 4-13)"},
      {"duplicate_node.frd", with_line(kLong, 6, " -1         2 1.00000E+00 2.00000E+00 3.00000E+00"), 6,
       "node 2 is listed twice (first at line 5)"},
      {"duplicate_disp.frd", with_line(kLong, 22, " -1         2 1.00000E+00 2.00000E+00 3.00000E+00"), 22,
       "node 2 is listed twice"},
      {"bad_time.frd",
       with_line(kLong, 14, "  100CL  101 2.5000xE-01           4                     0    1           1"),
       14, "VALUE (columns 13-24)"},
      {"binary.frd",
       with_line(kLong, 3, "    2C                             4                                     3"), 3,
       "binary"},
      {"unknown_record.frd", with_line(kLong, 13, "    4C"), 13, "expected a record key"},
      {"no_attribute.frd", without_line(kLong, 15), 15, "expected the attribute record ' -4  NAME'"},
      {"no_d3.frd", with_line(kLong, 18, " -5  DX          1    2    3    0"), 15, "no component D3"},
      {"no_copen.frd", with_line(kLong, 28, " -5  CGAP        1    4    1    1"), 27, "no component COPEN"},
      {"component_count.frd", with_line(kLong, 15, " -4  DISP        5    1"), 15, "announces 5 components"},
      {"second_node_block.frd",
       with_line(kLong, 9, "    2C                             1                                     1"), 9,
       "second node block (the first at line 3)"},
      {"no_node_block.frd", line_range(kLong, 13, 49), 37, "no node block"},
      {"no_disp.frd", first_lines(kLong, 12), 12, "no DISP block"},
      {"frequency_only.frd", first_lines(kSteps, 4) + line_range(kSteps, 30, 41), 16,
       "no DISP block of a static or dynamic step (1 of frequency"},
      {"skipped_block_cut.frd", first_lines(kSteps, 27) + " 9999\n", 28, "expected a ' -N' record"},
  };
  for (const BadFile& c : cases) {
    const std::string message = format_error(c.name, c.text);
    EXPECT_EQ(message.rfind(location(c.name, c.line), 0), 0u) << c.name << ": " << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.name << ": " << message;
  }
}

TEST(FrdResults, MissingFileIsAnIoError) {
  EXPECT_THROW((void)read_frd((dir() / "does_not_exist.frd").string()), IoError);
}

/// Nodes 1, 2, 10, 123 as in kLong's deck, but at other positions (a deck before ccx's ADJUST), one C3D4
/// element on them and node 99, used by no element.
mesh::SolidMesh deck_mesh(bool with_node_19) {
  mesh::SolidMesh m;
  const int n1 = m.add_node(1, Vec3(0, 0, 0));
  const int n2 = m.add_node(2, Vec3(1, 0, 0));
  const int n10 = m.add_node(10, Vec3(1, 2, 3));
  const int n123 = m.add_node(123, Vec3(0.5, 0.5, 1.1));
  m.add_node(99, Vec3(7, 8, 9));
  const std::array<int, 4> tet{n1, n2, n10, n123};
  m.add_element(5, mesh::element_type("C3D4"), tet);
  if (with_node_19) {
    const int n19 = m.add_node(19, Vec3(2, 2, 2));
    const std::array<int, 4> tet2{n2, n10, n123, n19};
    m.add_element(6, mesh::element_type("C3D4"), tet2);
  }
  return m;
}

TEST(FrdResults, MovesTheDeckToNodeBlockPlusDisp) {
  const FrdResults r = read_frd(write("move.frd", kLong));
  mesh::SolidMesh m = deck_mesh(false);
  move_to_increment(m, r, increment_index(r, 2));
  expect_vec(m.position(m.find_node(2)), 1.002, -0.004, 0.006);
  expect_vec(m.position(m.find_node(10)), 0.9997, 1.9995, 2.9993);
  // The node block's 1.001, not the deck's 1.1 (the solver's coordinates), plus DISP.
  expect_vec(m.position(m.find_node(123)), 0.5, 0.5, 0.9985);
  expect_vec(m.position(m.find_node(99)), 7, 8, 9);  // in no element, not in the results: stays

  move_to_increment(m, r, increment_index(r, 1));  // from the node block again, not from the moved mesh
  expect_vec(m.position(m.find_node(2)), 1.001, -0.002, 0.003);
  EXPECT_THROW(move_to_increment(m, r, 2), InvalidArgument);
}

/// move_to_increment(m, r, increment) must throw a FormatError whose message starts with "'path':line:" and
/// names `node`.
void expect_mismatch(mesh::SolidMesh& m, const FrdResults& r, int increment, const std::string& path,
                     int line, const std::string& node) {
  try {
    move_to_increment(m, r, increment);
    ADD_FAILURE() << node << " does not match the results of increment " << increment + 1;
  } catch (const FormatError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("'" + path + "':" + std::to_string(line) + ":", 0), 0u) << message;
    EXPECT_NE(message.find(node), std::string::npos) << message;
  }
}

TEST(FrdResults, ResultsOfAnotherDeckAreAFormatErrorAndLeaveTheMeshAlone) {
  const std::string path = write("mismatch.frd", kLong);
  const FrdResults r = read_frd(path);
  mesh::SolidMesh m = deck_mesh(true);
  expect_mismatch(m, r, 0, path, 3, "node 19 (of element 6)");  // node 19 is not in the results
  expect_vec(m.position(m.find_node(2)), 1, 0, 0);

  // DISP written for a node set only: node 10 is in the node block but has no displacement in increment 2.
  const std::string partial_path = write("partial_disp.frd", without_line(kLong, 46));
  const FrdResults partial = read_frd(partial_path);
  mesh::SolidMesh m2 = deck_mesh(false);
  expect_mismatch(m2, partial, 1, partial_path, 38, "node 10 (of element 5)");
  move_to_increment(m2, partial, 0);  // increment 1 has all of them
  expect_vec(m2.position(m2.find_node(10)), 0.99985, 1.99975, 2.99965);
}

// ---- A real run of CalculiX -------------------------------------------------------------------------------

// Two C3D8 blocks: the unit cube (nodes 1-8) and a half-width block on its top face (nodes 11-18, bottom
// at z = 1), pushed down by 0.01 at its top in four equal increments of a static step; the block's bottom
// nodes are the slave nodes of a node-to-surface pair on the cube's top face (S2).
const std::string kDeck = R"(*NODE, NSET=NALL
1, 0., 0., 0.
2, 1., 0., 0.
3, 1., 1., 0.
4, 0., 1., 0.
5, 0., 0., 1.
6, 1., 0., 1.
7, 1., 1., 1.
8, 0., 1., 1.
11, 0.25, 0.25, 1.
12, 0.75, 0.25, 1.
13, 0.75, 0.75, 1.
14, 0.25, 0.75, 1.
15, 0.25, 0.25, 1.5
16, 0.75, 0.25, 1.5
17, 0.75, 0.75, 1.5
18, 0.25, 0.75, 1.5
*ELEMENT, TYPE=C3D8, ELSET=LOWER
1, 1, 2, 3, 4, 5, 6, 7, 8
*ELEMENT, TYPE=C3D8, ELSET=UPPER
2, 11, 12, 13, 14, 15, 16, 17, 18
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=LOWER, MATERIAL=STEEL
*SOLID SECTION, ELSET=UPPER, MATERIAL=STEEL
*NSET, NSET=BOTTOM
1, 2, 3, 4
*NSET, NSET=TOP
15, 16, 17, 18
*NSET, NSET=SLAVEN
11, 12, 13, 14
*SURFACE, NAME=SLAVE, TYPE=NODE
SLAVEN
*SURFACE, NAME=MASTER
1, S2
*CONTACT PAIR, INTERACTION=SI1, TYPE=NODE TO SURFACE
SLAVE, MASTER
*SURFACE INTERACTION, NAME=SI1
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR
1.e6
*BOUNDARY
BOTTOM, 1, 3
TOP, 1, 2
*STEP, NLGEOM
*STATIC, DIRECT
0.25, 1.
*BOUNDARY
TOP, 3, 3, -0.01
*NODE FILE
U
*CONTACT FILE
CDIS, CSTR
*END STEP
)";

TEST(FrdResults, ReadsWhatCcxWrites) {
  if (std::system("command -v ccx > /dev/null 2>&1") != 0) GTEST_SKIP() << "ccx (CalculiX) is not on PATH";
  const fs::path run = dir() / "ccx_run";
  fs::remove_all(run);
  fs::create_directories(run);
  std::ofstream(run / "contact.inp") << kDeck;
  const std::string command = "cd '" + run.string() + "' && OMP_NUM_THREADS=1 ccx -i contact > ccx.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command << " failed: see " << (run / "ccx.log");

  const FrdResults r = read_frd((run / "contact.frd").string());
  EXPECT_EQ(r.node_ids.size(), 16u);
  ASSERT_EQ(r.increments.size(), 4u);  // DIRECT: 0.25, 0.5, 0.75, 1
  for (std::size_t i = 0; i < 4; ++i) {
    const FrdIncrement& inc = r.increments[i];
    EXPECT_EQ(inc.step, 1);
    EXPECT_NEAR(inc.time, 0.25 * static_cast<double>(i + 1), 1e-9);
    EXPECT_EQ(inc.disp_nodes.size(), 16u);
    ASSERT_EQ(inc.contact.size(), 4u) << "increment " << inc.number;
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(inc.contact[k].node, static_cast<long>(11 + k));
      // Pressed together: penetration (negative) or, at most, a clearance at the level of the 5 digits.
      EXPECT_LT(inc.contact[k].copen, 1e-9) << "node " << inc.contact[k].node;
      EXPECT_TRUE(inc.contact[k].has_stress);
      EXPECT_GE(inc.contact[k].cpress, 0.0);
    }
  }
  // Deeper with each increment.
  EXPECT_LT(r.increments[3].contact[0].copen, r.increments[0].contact[0].copen);

  // The deck moved to the last increment: the loaded face where the boundary condition put it, the fixed
  // face where it was, and COPEN = the slave node's height over the (flat, by symmetry) top of the cube.
  // Moved positions carry the 5 digits of the displacements (~1e-3): 1e-7 covers their rounding.
  constexpr double kFiveDigits = 1e-7;
  mesh::ContactModel model = read_inp_deck(run / "contact.inp");
  move_to_increment(model.mesh, r, increment_index(r, kLastIncrement));
  const auto z = [&](long id) { return model.mesh.position(model.mesh.find_node(id)).z(); };
  for (long id : {15, 16, 17, 18}) EXPECT_NEAR(z(id), 1.49, kFiveDigits) << "node " << id;
  for (long id : {1, 2, 3, 4}) EXPECT_NEAR(z(id), 0.0, kFiveDigits) << "node " << id;
  const double top = z(5);
  for (long id : {6, 7, 8}) ASSERT_NEAR(z(id), top, kFiveDigits) << "node " << id;
  for (const FrdContact& c : r.increments[3].contact) {
    EXPECT_NEAR(c.copen, z(c.node) - top, kFiveDigits) << "node " << c.node;
  }
}

}  // namespace
}  // namespace contactnn::io
