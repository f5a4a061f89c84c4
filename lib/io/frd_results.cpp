#include "io/frd_results.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "core/error.hpp"

namespace contactnn::io {

namespace {

/// A fixed-width field of a record: 0-based first column and width (messages show 1-based columns).
struct Field {
  std::size_t start, width;
};

// Header fields, as CalculiX GraphiX's manual ("Result Format") gives them and ccx's frd.c / frdheader.c
// write them.
constexpr Field kNodeBlockFormat{73, 1};  // "    2C": (1X,'   2','C',18X,I12,37X,I1)
constexpr Field kStepIncrement{36, 12};   // "    1PSTEP": ccx writes output count, increment, step (I12 each)
constexpr Field kStepNumber{48, 12};
constexpr Field kTimeValue{12, 12};     // "  100C": (1X,' 100','C',6A1,E12.5,I12,20A1,I2,I5,10A1,I2)
constexpr Field kAnalysisType{56, 2};   //   ICTYPE
constexpr Field kOutputCounter{58, 5};  //   NUMSTP
constexpr Field kResultFormat{73, 2};   //   FORMAT
constexpr Field kBlockName{5, 8};       // " -4": (1X,I2,2X,8A1,2I5)  NAME, NCOMPS
constexpr Field kComponentCount{13, 5};
constexpr Field kComponentName{5, 8};  // " -5": (1X,I2,2X,8A1,5I5,8A1)  NAME, ..., IEXIST
constexpr Field kComponentExists{33, 5};

constexpr std::size_t kRecordIdStart = 3;  // after " -1"
constexpr std::size_t kValueWidth = 12;    // E12.5
constexpr std::size_t kValuesPerRecord = 6;

// ICTYPE of the steps SPEC 10 counts.
constexpr int kStatic = 0;
constexpr int kDynamic = 1;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

/// The columns of `f` in `line` ("" past its end).
std::string_view cut(std::string_view line, Field f) {
  if (f.start >= line.size()) return {};
  return line.substr(f.start, f.width);
}

std::string columns(Field f) {
  return f.width == 1 ? "column " + std::to_string(f.start + 1)
                      : "columns " + std::to_string(f.start + 1) + "-" + std::to_string(f.start + f.width);
}

/// A whole (trimmed, non-empty) field as an integer.
bool parse_integer(std::string_view text, long& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return false;
  const char* end = text.data() + text.size();
  const auto r = std::from_chars(text.data(), end, value);
  return r.ec == std::errc() && r.ptr == end;
}

/// A whole (trimmed, non-empty) field as a finite number (E12.5, or ccx's fixed-point time values).
bool parse_number(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty() || text.front() == '+' || text.front() == ' ') return false;
  const char* end = text.data() + text.size();
  const auto r = std::from_chars(text.data(), end, value);
  return r.ec == std::errc() && r.ptr == end && std::isfinite(value);
}

/// The components of a result block (its " -5" records) that carry a value in the records, in order.
struct Components {
  std::vector<std::string> names;
  int records = 0;  // " -5" records, including those with IEXIST = 1
  [[nodiscard]] int find(std::string_view name) const {
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (names[i] == name) return static_cast<int>(i);
    }
    return -1;
  }
  [[nodiscard]] std::string list() const {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "none" : out;
  }
};

/// A CONTACT block waiting for the DISP block of its increment.
struct PendingContact {
  int step = 0, output_counter = 0, line = 0;
  std::vector<FrdContact> rows;
};

class FrdReader {
 public:
  FrdReader(std::string text, std::string file) : text_(std::move(text)) { results_.file = std::move(file); }

  FrdResults read() {
    std::string_view line;
    while (next(line)) {
      if (trim(line).empty()) continue;
      const std::string_view key = trim(line.substr(0, std::min<std::size_t>(5, line.size())));
      const char code = line.size() > 5 ? line[5] : ' ';
      if (key == "9999" && trim(line.substr(std::min<std::size_t>(5, line.size()))).empty()) break;
      if (key == "1" && (code == 'C' || code == 'U')) continue;
      if (key == "1" && code == 'P') {
        parameter(line);
      } else if (key == "2" && code == 'C') {
        node_block(line);
      } else if (key == "3" && code == 'C') {
        skip_block("element block ('    3C')", line_);
      } else if (key == "100" && code == 'C') {
        result_block(line);
      } else {
        fail(line_, "record",
             "expected a record key ('    1C', '    1U', '    1P', '    2C', '    3C', '  100C' or "
             "' 9999' in columns 1-6), got '" +
                 shown(line) + "'");
      }
    }
    finish();
    return std::move(results_);
  }

 private:
  std::string text_;
  std::size_t pos_ = 0;
  int line_ = 0;
  FrdResults results_;
  int step_ = 0, increment_in_step_ = 0;  // of the last "1PSTEP"
  int other_disp_blocks_ = 0;             // DISP of frequency, buckling and other steps
  std::vector<PendingContact> contacts_;

  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    line = std::string_view(text_).substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++line_;
    return true;
  }

  static std::string shown(std::string_view line) {
    constexpr std::size_t kShown = 40;
    return line.size() > kShown ? std::string(line.substr(0, kShown)) + "..." : std::string(line);
  }

  [[nodiscard]] std::string where(int line) const {
    return "'" + results_.file + "':" + std::to_string(line);
  }

  [[noreturn]] void fail(int line, std::string_view what, const std::string& message) const {
    throw FormatError(where(line) + ": " + std::string(what) + ": " + message);
  }

  /// A header field read as Fortran reads an I-format: blank is 0.
  int header_integer(std::string_view line, Field f, std::string_view what, std::string_view name) const {
    const std::string_view text = trim(cut(line, f));
    if (text.empty()) return 0;
    long value = 0;
    if (!parse_integer(text, value) || value < -2147483647L || value > 2147483647L) {
      fail(line_, what,
           std::string(name) + " (" + columns(f) + "): '" + std::string(text) + "' is not an integer");
    }
    return static_cast<int>(value);
  }

  /// " -1", " -2", ... in columns 1-3, or "" for anything else.
  static std::string_view data_key(std::string_view line) {
    if (line.size() < 3 || line[0] != ' ' || line[1] != '-' || line[2] < '1' || line[2] > '6') return {};
    return line.substr(1, 2);
  }

  /// Reads the value record at the current line: `key` (" -1": then the node id, `id_columns` columns; " -2":
  /// as many blank columns) and `count` values of 12 columns. Returns the node id (0 for " -2").
  long value_record(std::string_view line, std::string_view what, std::size_t id_columns, std::size_t count,
                    double* values) const {
    const std::size_t values_start = kRecordIdStart + id_columns;
    const std::size_t needed = values_start + count * kValueWidth;
    std::string_view content = line;
    while (!content.empty() && (content.back() == ' ' || content.back() == '\t')) content.remove_suffix(1);
    if (content.size() < needed) {
      fail(line_, what,
           "record ' " + std::string(line.substr(1, 2)) + "' too short: expected " +
               (line[2] == '1' ? "the node id (" + columns({kRecordIdStart, id_columns}) + ") and " : "") +
               std::to_string(count) + " values of 12 columns (up to column " + std::to_string(needed) +
               "), the line ends at column " + std::to_string(content.size()));
    }
    if (content.size() > needed) {
      fail(line_, what,
           "unexpected text after the " + std::to_string(count) + " values, from column " +
               std::to_string(needed + 1) + ": '" + shown(content.substr(needed)) + "'");
    }
    long id = 0;
    const Field id_field{kRecordIdStart, id_columns};
    if (line[2] == '1') {
      const std::string_view text = trim(cut(line, id_field));
      if (!parse_integer(text, id) || id <= 0) {
        fail(line_, what,
             "node id (" + columns(id_field) + "): '" + std::string(text) + "' is not a positive integer");
      }
    } else if (!trim(cut(line, id_field)).empty()) {
      fail(line_, what,
           "continuation record ' -2': " + columns(id_field) + " must be blank, got '" +
               std::string(cut(line, id_field)) + "'");
    }
    for (std::size_t k = 0; k < count; ++k) {
      const Field f{values_start + k * kValueWidth, kValueWidth};
      const std::string_view text = trim(cut(line, f));
      if (!parse_number(text, values[k])) {
        fail(line_, what,
             (id > 0 ? "node " + std::to_string(id) + ": " : std::string()) + "value " +
                 std::to_string(k + 1) + " (" + columns(f) + "): '" + std::string(cut(line, f)) +
                 "' is not a finite number");
      }
    }
    return id;
  }

  /// ID width of the value records for a block's FORMAT (0 short, 1 long); binary is refused.
  std::size_t id_width(int format, int line, std::string_view what, Field f) const {
    if (format == 0) return 5;
    if (format == 1) return 10;
    if (format == 2 || format == 3) {
      fail(line, what,
           "FORMAT " + std::to_string(format) + " (" + columns(f) +
               ") is a binary block: only ASCII results are read (ccx writes them for *NODE FILE and "
               "*CONTACT FILE; *NODE OUTPUT writes binary)");
    }
    fail(line, what,
         "FORMAT " + std::to_string(format) + " (" + columns(f) + ") is not 0 (short) or 1 (long)");
  }

  [[noreturn]] void truncated(std::string_view what, int header_line) const {
    fail(line_, what,
         "the file ends inside the block begun at line " + std::to_string(header_line) +
             " (no ' -3' end-of-block record): the file is truncated");
  }

  void parameter(std::string_view line) {
    const std::string_view name = trim(line.substr(6, std::min<std::size_t>(line.size(), 24) - 6));
    if (name != "STEP") return;
    increment_in_step_ = header_integer(line, kStepIncrement, "'    1PSTEP'", "INCREMENT");
    step_ = header_integer(line, kStepNumber, "'    1PSTEP'", "STEP");
  }

  void node_block(std::string_view header) {
    const std::string what = "node block ('    2C')";
    const int header_line = line_;
    if (results_.node_block_line != 0) {
      fail(line_, what,
           "a second node block (the first at line " + std::to_string(results_.node_block_line) +
               "): results of a mesh that changes during the run are not supported");
    }
    results_.node_block_line = header_line;
    const std::size_t width = id_width(header_integer(header, kNodeBlockFormat, what, "FORMAT"), header_line,
                                       what, kNodeBlockFormat);
    std::unordered_map<long, int> first_line;
    std::string_view line;
    while (next(line)) {
      const std::string_view key = data_key(line);
      if (key == "-3") return;
      if (key != "-1") {
        fail(line_, what,
             "expected a node record ' -1' or the end of the block ' -3' (block begun at line " +
                 std::to_string(header_line) + "), got '" + shown(line) + "'");
      }
      double x[3];
      const long id = value_record(line, what, width, 3, x);
      const auto [it, inserted] = first_line.emplace(id, line_);
      if (!inserted)
        fail(line_, what,
             "node " + std::to_string(id) + " is listed twice (first at line " + std::to_string(it->second) +
                 ")");
      results_.node_ids.push_back(id);
      results_.coordinates.emplace_back(x[0], x[1], x[2]);
    }
    truncated(what, header_line);
  }

  /// Skips the records of a block up to its " -3"; anything but a " -N" record before it is an error.
  void skip_block(const std::string& what, int header_line) {
    std::string_view line;
    while (next(line)) {
      const std::string_view key = data_key(line);
      if (key == "-3") return;
      if (key.empty()) {
        fail(line_, what,
             "expected a ' -N' record up to the end of the block ' -3' (block begun at line " +
                 std::to_string(header_line) + "), got '" + shown(line) + "'");
      }
    }
    truncated(what, header_line);
  }

  /// The " -5" records after the " -4" record `attribute` (line header_line + 1); leaves `line` at the first
  /// record after them.
  Components components(std::string_view attribute, const std::string& what, int header_line,
                        std::string_view& line) {
    const int announced = header_integer(attribute, kComponentCount, what, "NCOMPS");
    Components c;
    bool more = false;
    while ((more = next(line))) {
      const std::string_view key = data_key(line);
      if (key == "-6") continue;  // "not used" (manual): a request for computed components
      if (key != "-5") break;
      ++c.records;
      const std::string_view name = trim(cut(line, kComponentName));
      if (header_integer(line, kComponentExists, what, "IEXIST") != 1) c.names.emplace_back(name);
    }
    if (!more) truncated(what, header_line);
    if (c.records != announced) {
      fail(header_line + 1, what,
           "the ' -4' record announces " + std::to_string(announced) + " components (" +
               columns(kComponentCount) + "), " + std::to_string(c.records) + " ' -5' records follow it");
    }
    return c;
  }

  /// A DISP or CONTACT block being read: its name for messages, its header's line and fields, its node id
  /// width, its components, the current line and the current node's values.
  struct OpenBlock {
    std::string what;
    int header_line = 0;
    int analysis_type = 0;
    int output_counter = 0;
    double time = 0;
    std::size_t width = 0;
    Components c;
    std::string_view line;
    std::vector<double> values;
  };

  void advance(OpenBlock& b) {
    if (!next(b.line)) truncated(b.what, b.header_line);
  }

  void expect_value_record(const OpenBlock& b) {
    if (data_key(b.line) != "-1") {
      fail(line_, b.what,
           "expected a value record ' -1' or the end of the block ' -3', got '" + shown(b.line) + "'");
    }
  }

  /// Reads one node's records (the current " -1" line and its " -2" continuations) into b.values.
  long node_values(OpenBlock& b) {
    std::vector<double>& values = b.values;
    const std::size_t first = std::min<std::size_t>(kValuesPerRecord, values.size());
    const long id = value_record(b.line, b.what, b.width, first, values.data());
    for (std::size_t done = first; done < values.size(); done += kValuesPerRecord) {
      advance(b);
      if (data_key(b.line) != "-2") {
        fail(line_, b.what,
             "node " + std::to_string(id) + " has " + std::to_string(values.size()) +
                 " values: expected the continuation record ' -2' for values " + std::to_string(done + 1) +
                 "..., got '" + shown(b.line) + "'");
      }
      value_record(b.line, b.what, b.width, std::min(kValuesPerRecord, values.size() - done),
                   values.data() + done);
    }
    return id;
  }

  void result_block(std::string_view header) {
    OpenBlock b;
    b.header_line = line_;
    const std::string header_what = "result block header ('  100C')";
    const std::string_view time_text = trim(cut(header, kTimeValue));
    if (!time_text.empty() && !parse_number(time_text, b.time)) {
      fail(line_, header_what,
           "VALUE (" + columns(kTimeValue) + "): '" + std::string(time_text) + "' is not a finite number");
    }
    b.analysis_type = header_integer(header, kAnalysisType, header_what, "ICTYPE");
    b.output_counter = header_integer(header, kOutputCounter, header_what, "NUMSTP");
    const int format = header_integer(header, kResultFormat, header_what, "FORMAT");

    std::string_view attribute;
    if (!next(attribute)) truncated(header_what, b.header_line);
    if (data_key(attribute) != "-4") {
      fail(line_, header_what,
           "expected the attribute record ' -4  NAME' after the header at line " +
               std::to_string(b.header_line) + ", got '" + shown(attribute) + "'");
    }
    const std::string name(trim(cut(attribute, kBlockName)));
    b.what = name + " block (header at line " + std::to_string(b.header_line) + ")";
    const bool counted = b.analysis_type == kStatic || b.analysis_type == kDynamic;
    if (name == "DISP" && !counted) ++other_disp_blocks_;
    if (!counted || (name != "DISP" && name != "CONTACT")) {
      skip_block(b.what, b.header_line);
      return;
    }
    b.width = id_width(format, b.header_line, header_what, kResultFormat);
    b.c = components(attribute, b.what, b.header_line, b.line);
    b.values.resize(b.c.names.size());
    if (name == "DISP") {
      disp_block(b);
    } else {
      contact_block(b);
    }
  }

  /// A DISP block: one increment's displacements (D1, D2, D3) by node.
  void disp_block(OpenBlock& b) {
    int d[3];
    const char* const labels[3] = {"D1", "D2", "D3"};
    for (int k = 0; k < 3; ++k) {
      d[k] = b.c.find(labels[k]);
      if (d[k] < 0) {
        fail(b.header_line + 1, b.what,
             std::string("no component ") + labels[k] + " (the block's values: " + b.c.list() + ")");
      }
    }
    FrdIncrement inc;
    inc.number = static_cast<int>(results_.increments.size()) + 1;
    inc.step = step_;
    inc.increment_in_step = increment_in_step_;
    inc.analysis_type = b.analysis_type;
    inc.output_counter = b.output_counter;
    inc.time = b.time;
    inc.line = b.header_line;
    std::unordered_map<long, int> first_line;
    for (; data_key(b.line) != "-3"; advance(b)) {
      expect_value_record(b);
      const int record_line = line_;
      const long id = node_values(b);
      const auto [it, inserted] = first_line.emplace(id, record_line);
      if (!inserted) {
        fail(record_line, b.what,
             "node " + std::to_string(id) + " is listed twice (first at line " + std::to_string(it->second) +
                 ")");
      }
      inc.disp_nodes.push_back(id);
      inc.displacement.emplace_back(b.values[static_cast<std::size_t>(d[0])],
                                    b.values[static_cast<std::size_t>(d[1])],
                                    b.values[static_cast<std::size_t>(d[2])]);
    }
    results_.increments.push_back(std::move(inc));
  }

  /// A CONTACT block: COPEN, CSLIP1, CSLIP2 by node, and CPRESS, CSHEAR1, CSHEAR2 when present (all three or
  /// none); kept until its increment's DISP block is known.
  void contact_block(OpenBlock& b) {
    const char* const labels[6] = {"COPEN", "CSLIP1", "CSLIP2", "CPRESS", "CSHEAR1", "CSHEAR2"};
    int k_of[6];
    for (int k = 0; k < 6; ++k) k_of[k] = b.c.find(labels[k]);
    for (int k = 0; k < 3; ++k) {
      if (k_of[k] < 0) {
        fail(b.header_line + 1, b.what,
             std::string("no component ") + labels[k] + " (the block's values: " + b.c.list() + ")");
      }
    }
    const int stresses =
        static_cast<int>(k_of[3] >= 0) + static_cast<int>(k_of[4] >= 0) + static_cast<int>(k_of[5] >= 0);
    if (stresses != 0 && stresses != 3) {
      fail(
          b.header_line + 1, b.what,
          "CPRESS, CSHEAR1 and CSHEAR2 come together or not at all (the block's values: " + b.c.list() + ")");
    }
    PendingContact pending{step_, b.output_counter, b.header_line, {}};
    for (; data_key(b.line) != "-3"; advance(b)) {
      expect_value_record(b);
      const long id = node_values(b);
      const auto v = [&](int k) { return b.values[static_cast<std::size_t>(k_of[k])]; };
      FrdContact row;
      row.node = id;
      row.copen = v(0);
      row.cslip1 = v(1);
      row.cslip2 = v(2);
      row.has_stress = stresses == 3;
      if (row.has_stress) {
        row.cpress = v(3);
        row.cshear1 = v(4);
        row.cshear2 = v(5);
      }
      pending.rows.push_back(row);
    }
    contacts_.push_back(std::move(pending));
  }

  void finish() {
    if (results_.node_block_line == 0) {
      fail(line_, "end of file", "no node block ('    2C'): not a CalculiX result file, or an empty one");
    }
    if (results_.increments.empty()) {
      fail(line_, "end of file",
           "no DISP block of a static or dynamic step (" + std::to_string(other_disp_blocks_) +
               " of frequency, buckling or other steps): request U under *NODE FILE in a *STATIC or *DYNAMIC "
               "step");
    }
    // A CONTACT block goes with the DISP block of the same step and output count: the last such before it
    // (ccx writes DISP first), else the first after it; none (no U written for that output): dropped.
    std::map<std::pair<int, int>, std::vector<std::size_t>> by_key;
    for (std::size_t i = 0; i < results_.increments.size(); ++i) {
      const FrdIncrement& inc = results_.increments[i];
      by_key[{inc.step, inc.output_counter}].push_back(i);
    }
    for (PendingContact& p : contacts_) {
      const auto it = by_key.find({p.step, p.output_counter});
      if (it == by_key.end()) continue;
      std::size_t chosen = it->second.front();
      for (std::size_t i : it->second) {
        if (results_.increments[i].line < p.line) chosen = i;
      }
      auto& rows = results_.increments[chosen].contact;
      rows.insert(rows.end(), p.rows.begin(), p.rows.end());
    }
    for (FrdIncrement& inc : results_.increments) {
      std::stable_sort(inc.contact.begin(), inc.contact.end(),
                       [](const FrdContact& a, const FrdContact& b) { return a.node < b.node; });
    }
  }
};

}  // namespace

FrdResults read_frd(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw FormatError("'" + path + "': a directory, not a results file (.frd)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open results file '" + path + "': " + std::strerror(errno));
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw IoError("cannot read results file '" + path + "'");
  return FrdReader(std::move(content).str(), path).read();
}

std::size_t increment_index(const FrdResults& results, int number) {
  const auto count = static_cast<int>(results.increments.size());
  CONTACTNN_REQUIRE_AS(InvalidArgument, count > 0, "'" << results.file << "' holds no increment");
  if (number == kLastIncrement) return static_cast<std::size_t>(count - 1);
  CONTACTNN_REQUIRE_AS(InvalidArgument, number >= 1 && number <= count,
                       "increment " << number << " does not exist: '" << results.file << "' holds " << count
                                    << " (DISP of static or dynamic steps, counted from 1: 1.." << count
                                    << ", or last)");
  return static_cast<std::size_t>(number - 1);
}

NodeRows node_rows(const mesh::SolidMesh& mesh, const FrdResults& results, std::size_t increment) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, increment < results.increments.size(),
                       "increment index " << increment << " is out of range: '" << results.file << "' holds "
                                          << results.increments.size());
  const FrdIncrement& inc = results.increments[increment];

  // An element using each node (-1: none), to tell the nodes that must have results from those that need not.
  std::vector<int> element_of(static_cast<std::size_t>(mesh.node_count()), -1);
  for (int e = 0; e < mesh.element_count(); ++e) {
    for (int n : mesh.element_nodes(e)) {
      if (element_of[static_cast<std::size_t>(n)] < 0) element_of[static_cast<std::size_t>(n)] = e;
    }
  }
  std::unordered_map<long, std::size_t> in_block, in_disp;
  in_block.reserve(results.node_ids.size());
  for (std::size_t i = 0; i < results.node_ids.size(); ++i) in_block.emplace(results.node_ids[i], i);
  in_disp.reserve(inc.disp_nodes.size());
  for (std::size_t i = 0; i < inc.disp_nodes.size(); ++i) in_disp.emplace(inc.disp_nodes[i], i);

  // Check everything first, so that a failure leaves `mesh` as it was (move_to_increment).
  int first_missing_block = -1, missing_block = 0, first_missing_disp = -1, missing_disp = 0;
  for (int n = 0; n < mesh.node_count(); ++n) {
    if (element_of[static_cast<std::size_t>(n)] < 0) continue;
    if (!in_block.contains(mesh.node_id(n))) {
      if (missing_block++ == 0) first_missing_block = n;
    } else if (!in_disp.contains(mesh.node_id(n))) {
      if (missing_disp++ == 0) first_missing_disp = n;
    }
  }
  const auto describe = [&](int n, int count) {
    return "node " + std::to_string(mesh.node_id(n)) + " (of element " +
           std::to_string(mesh.element_id(element_of[static_cast<std::size_t>(n)])) + ")" +
           (count > 1 ? " and " + std::to_string(count - 1) + " other node(s) of the deck's elements"
                      : std::string());
  };
  if (missing_block > 0) {
    const mesh::ElementType& type =
        mesh.element_type(element_of[static_cast<std::size_t>(first_missing_block)]);
    if (!type.name.starts_with("C3D")) {
      // CalculiX expands shell, beam, membrane and plane elements into solids with new nodes: the node block
      // holds those, not the deck's.
      long foreign = 0;
      for (const long id : results.node_ids) foreign += mesh.find_node(id) < 0 ? 1 : 0;
      throw FormatError(
          "'" + results.file + "':" + std::to_string(results.node_block_line) +
          ": node block ('    2C'): " + describe(first_missing_block, missing_block) + " not in it, and " +
          std::to_string(foreign) + " node(s) the deck does not have: element " +
          std::to_string(mesh.element_id(element_of[static_cast<std::size_t>(first_missing_block)])) +
          " is of type " + type.name +
          ", a shell, beam, membrane or plane element, which CalculiX expands into solid elements "
          "with new nodes (those it writes) and the project does not model. Use a deck whose "
          "elements are solid (C3D*), or have CalculiX write the deck's own nodes (*NODE FILE, "
          "OUTPUT=2D, where its manual allows it)");
    }
  }
  CONTACTNN_REQUIRE_AS(FormatError, missing_block == 0,
                       "'" << results.file << "':" << results.node_block_line
                           << ": node block ('    2C'): " << describe(first_missing_block, missing_block)
                           << " not in it: the results file does not belong to the deck");
  CONTACTNN_REQUIRE_AS(
      FormatError, missing_disp == 0,
      "'" << results.file << "':" << inc.line << ": DISP of increment " << inc.number << " (step " << inc.step
          << ", time " << inc.time << "): no displacement of " << describe(first_missing_disp, missing_disp)
          << " (U written for a node set only? write it for all nodes: *NODE FILE without NSET=)");

  NodeRows rows;
  rows.block.assign(static_cast<std::size_t>(mesh.node_count()), -1);
  rows.disp.assign(static_cast<std::size_t>(mesh.node_count()), -1);
  for (int n = 0; n < mesh.node_count(); ++n) {
    const auto b = in_block.find(mesh.node_id(n));
    if (b != in_block.end()) rows.block[static_cast<std::size_t>(n)] = static_cast<long>(b->second);
    const auto d = in_disp.find(mesh.node_id(n));
    if (d != in_disp.end()) rows.disp[static_cast<std::size_t>(n)] = static_cast<long>(d->second);
  }
  return rows;
}

void move_to_increment(mesh::SolidMesh& mesh, const FrdResults& results, std::size_t increment) {
  const NodeRows rows = node_rows(mesh, results, increment);
  const FrdIncrement& inc = results.increments[increment];
  for (int n = 0; n < mesh.node_count(); ++n) {
    // A node used by no element, absent from the results, stays where it is.
    if (rows.block[static_cast<std::size_t>(n)] >= 0)
      mesh.set_position(n, position_at(results, inc, rows, n));
  }
}

void check_node_block(const mesh::ContactModel& model, const FrdResults& results) {
  const mesh::SolidMesh& mesh = model.mesh;
  // The nodes to check: those of the deck's elements, less the slave surfaces' (ADJUST= may have moved them).
  std::vector<char> checked(static_cast<std::size_t>(mesh.node_count()), 0);
  for (int e = 0; e < mesh.element_count(); ++e) {
    for (int n : mesh.element_nodes(e)) checked[static_cast<std::size_t>(n)] = 1;
  }
  for (const mesh::ContactPairDefinition& pair : model.pairs) {
    if (pair.slave < 0 || pair.slave >= static_cast<int>(model.surfaces.size())) continue;
    const mesh::SurfaceDefinition& slave = model.surfaces[static_cast<std::size_t>(pair.slave)];
    for (const int n : slave.nodes) checked[static_cast<std::size_t>(n)] = 0;
    for (const mesh::ElementFace& f : slave.faces) {
      for (const int n : mesh.element_nodes(f.element)) checked[static_cast<std::size_t>(n)] = 0;
    }
  }
  std::unordered_map<long, std::size_t> in_block;
  in_block.reserve(results.node_ids.size());
  for (std::size_t i = 0; i < results.node_ids.size(); ++i) in_block.emplace(results.node_ids[i], i);
  geometry::Vec3 lo = geometry::Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int e = 0; e < mesh.element_count(); ++e) {
    for (int n : mesh.element_nodes(e)) {
      lo = lo.cwiseMin(mesh.deck_position(n));
      hi = hi.cwiseMax(mesh.deck_position(n));
    }
  }
  if (!(lo.array() <= hi.array()).all()) return;  // no element
  const double size = (hi - lo).norm();
  for (int n = 0; n < mesh.node_count(); ++n) {
    const auto b = in_block.find(mesh.node_id(n));
    if (checked[static_cast<std::size_t>(n)] == 0 || b == in_block.end()) continue;
    const geometry::Vec3& deck = mesh.deck_position(n);
    const geometry::Vec3& file = results.coordinates[b->second];
    const double distance = (file - deck).norm();
    const double rounding =
        1e-5 * std::sqrt(3.0) * std::max(deck.cwiseAbs().maxCoeff(), file.cwiseAbs().maxCoeff());
    const double tolerance = kNodeBlockTolerance * size + rounding;
    if (distance <= tolerance) continue;
    std::ostringstream message;
    message.precision(6);
    message << "'" << results.file << "':" << results.node_block_line << ": node block ('    2C'): node "
            << mesh.node_id(n) << " is at (" << file.x() << ", " << file.y() << ", " << file.z()
            << "), the deck's at (" << deck.x() << ", " << deck.y() << ", " << deck.z() << "): " << distance
            << " apart, more than " << tolerance << " (" << kNodeBlockTolerance << " of the model's size "
            << size
            << "): the results are of another mesh with the same node ids (scaled, rotated or moved?); give "
               "--trust-results-nodes to take the file's coordinates";
    throw FormatError(message.str());
  }
}

}  // namespace contactnn::io
