// Comma-separated tables with one header row (SPEC 6): reading, streamed or whole, with errors that name
// file, line and column; number parsing; writing, streamed or whole.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/quote_text.hpp"
#include "io/atomic_output.hpp"

namespace contactnn::io {

/// User text quoted in a message, at most kQuotedBytes of it (core/quote_text.hpp: one helper for every
/// module).
using contactnn::kQuotedBytes;
using contactnn::quote_text;

/// The index of the one column of `header` called `name`; std::nullopt when there is none; FormatError naming
/// `path` when there are several (a header may hold repeated names: only looking one up is an error).
[[nodiscard]] std::optional<std::size_t> find_column(const std::vector<std::string>& header,
                                                     std::string_view name,
                                                     const std::filesystem::path& path);

/// One CSV record held compactly: the fields' text back to back and where each ends (a row of 17 numbers
/// takes its text plus 68 bytes, not 17 separately allocated strings).
class CsvRecord {
 public:
  [[nodiscard]] std::size_t size() const { return ends_.size(); }
  [[nodiscard]] std::string_view operator[](std::size_t i) const {
    const std::size_t begin = i == 0 ? 0 : ends_[i - 1];
    return std::string_view(text_).substr(begin, ends_[i] - begin);
  }
  [[nodiscard]] std::vector<std::string> strings() const;
  void clear() {
    text_.clear();
    ends_.clear();
  }
  void append(char c) { text_ += c; }
  void end_field() { ends_.push_back(static_cast<std::uint32_t>(text_.size())); }
  [[nodiscard]] std::string_view current_field() const {
    return std::string_view(text_).substr(ends_.empty() ? 0 : ends_.back());
  }
  [[nodiscard]] std::size_t text_size() const { return text_.size(); }

 private:
  std::string text_;
  std::vector<std::uint32_t> ends_;
};

/// Whether a CSV file must hold data rows after its header. kMayBeNone: a header alone is a table of no rows
/// (a RAW.csv of no configurations, such as the pairs file of a contact pair without slave nodes: SPEC 7
/// makes it valid input); kRequired: it is an error (a dataset or report needs rows).
enum class DataRows { kRequired, kMayBeNone };

/// Reads a CSV file record by record, holding one buffer of the file and one record at a time, so a file of
/// any size is read in bounded memory.
///
/// Format: comma-separated, RFC 4180 double quotes (a quoted field may hold commas, quotes as "" and line
/// breaks), LF or CRLF line ends, blank lines skipped, a leading UTF-8 byte-order mark ignored, blanks
/// around column names ignored. FormatError naming the file and line for: an empty file, a header without
/// data rows (unless DataRows::kMayBeNone), a row whose field count differs from the header's, an
/// unterminated quote (and the column it opens in), a carriage return not followed by a line feed (CR-only
/// line ends), UTF-16 or UTF-32 text (by its byte-order mark, or NUL bytes in the header). IoError if the
/// file cannot be opened or read.
class CsvReader {
 public:
  /// Streams the file at `path`. Reads the header and looks ahead to the first data row (so an empty file
  /// or, where rows are required, a header alone is reported here).
  explicit CsvReader(const std::filesystem::path& path, DataRows rows = DataRows::kRequired);
  /// Same, from text in memory; `name` stands for the file in messages. `text` must outlive the reader.
  CsvReader(std::string_view text, const std::filesystem::path& name, DataRows rows = DataRows::kRequired);

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] const std::vector<std::string>& header() const { return header_; }
  /// Index of column `name`. FormatError "'F':1: missing column 'name'" if there is none, "duplicate column"
  /// if the header names two (empty and repeated names are allowed in a header: such columns are data a
  /// reader may copy, but not look up).
  [[nodiscard]] std::size_t column(std::string_view name) const;

  /// The next data row: `record` gets header().size() fields (its storage is reused from call to call),
  /// `line` the 1-based line it starts on. False, leaving both alone, when no row is left.
  bool next(CsvRecord& record, std::size_t& line);

 private:
  int get();
  int peek();
  bool refill();
  bool read_record(CsvRecord& record, std::size_t& line);
  void check_encoding();
  void start(DataRows rows);

  std::filesystem::path path_;
  std::ifstream file_;
  std::string buffer_;
  std::string_view view_;
  std::size_t pos_ = 0;
  bool streaming_ = false;
  std::size_t line_ = 1;
  std::vector<std::string> header_;
  CsvRecord lookahead_;
  std::size_t lookahead_line_ = 0;
  bool have_lookahead_ = false;
};

/// A CSV file as text: the header and each data row's fields, unparsed, so that columns the tools do
/// not use are copied to their outputs unchanged. For small files (tests, reports); large inputs are read
/// with CsvReader.
struct CsvTable {
  std::filesystem::path path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::size_t> line_numbers;  ///< 1-based line in the file of each row (header is line 1)

  /// Index of column `name`. FormatError naming the file and the column if it is missing or named twice.
  [[nodiscard]] std::size_t column(std::string_view name) const;
  /// Field (row, col) as a number. "nan", "inf", "-inf" (any case) parse; anything else that is not a
  /// complete number is FormatError "<file>:<line>: column '<name>': '<text>' is not a number".
  [[nodiscard]] double number(std::size_t row, std::size_t col) const;
};

/// Reads a whole CSV file into memory (CsvReader's format and errors).
[[nodiscard]] CsvTable read_csv(const std::filesystem::path& path);

/// Same, from text in memory (`name` stands for the file in messages). Used by read_csv and the fuzzer.
[[nodiscard]] CsvTable parse_csv(std::string_view text, const std::filesystem::path& name);

/// Parses a whole field as a number (leading/trailing blanks allowed, a leading '+' allowed);
/// false if the field is not exactly one number. nan/inf accepted; a number beyond double's range
/// rounds to +-inf or 0 as in IEEE arithmetic.
[[nodiscard]] bool parse_double(std::string_view field, double& value);

/// The FormatError of a field that is not a number: "'FILE':LINE: column 'NAME': 'TEXT' is not a number",
/// TEXT quoted with quote_text.
[[nodiscard]] std::string not_a_number_message(const std::filesystem::path& file, std::size_t line,
                                               std::string_view column, std::string_view text);

/// Appends one CSV row to `out`, quoting fields that contain a comma, quote or line break or begin with a
/// byte-order mark (UTF-8, UTF-16 or UTF-32), so that parse_csv reads the row back unchanged.
void append_csv_row(std::string& out, const std::vector<std::string>& fields);
/// Appends one field (the separator before it is the caller's), quoted as append_csv_row does.
void append_csv_field(std::string& out, std::string_view field);

/// Shortest text that reads back to exactly the same double ("%.17g" where needed).
[[nodiscard]] std::string format_double(double value);

/// Writes a CSV file row by row through an AtomicOutput (sequential: a FIFO or /dev/stdout takes the rows
/// as they come), buffering about a megabyte at a time. Nothing appears under the final name before
/// commit(); IoError naming the file when a write fails (a full disk).
class CsvWriter {
 public:
  explicit CsvWriter(const std::filesystem::path& path);
  void write_row(const std::vector<std::string>& fields);
  /// A row built field by field: field() for each, then end_row().
  void field(std::string_view text);
  void end_row();
  /// Writes what is buffered, checks the stream and commits the output.
  void commit();
  [[nodiscard]] AtomicOutput& output() { return output_; }

 private:
  void flush_buffer();

  AtomicOutput output_;
  std::ofstream stream_;
  std::string buffer_;
  bool row_started_ = false;
};

/// Writes `text` to `path` atomically (temporary file in the same directory, then rename; written in place
/// into a device or FIFO).
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

/// The same in two steps, for outputs committed together (commit_together): the text is written and
/// flushed to the returned output's temporary, which the caller commits.
[[nodiscard]] std::unique_ptr<AtomicOutput> write_text_uncommitted(const std::filesystem::path& path,
                                                                   std::string_view text);

}  // namespace contactnn::io
