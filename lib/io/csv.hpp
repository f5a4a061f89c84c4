// Comma-separated tables with one header row (SPEC 6): reading with errors that name file, line and
// column, number parsing, and writing.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace contactnn::io {

/// A CSV file as text: the header and each data row's fields, unparsed, so that columns the tools do
/// not use are copied to their outputs unchanged.
struct CsvTable {
  std::filesystem::path path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::size_t> line_numbers;  ///< 1-based line in the file of each row (header is line 1)

  /// Index of column `name`. FormatError naming the file and the column if it is missing.
  [[nodiscard]] std::size_t column(std::string_view name) const;
  /// Field (row, col) as a number. "nan", "inf", "-inf" (any case) parse; anything else that is not a
  /// complete number is FormatError "<file>:<line>: column '<name>': '<text>' is not a number".
  [[nodiscard]] double number(std::size_t row, std::size_t col) const;
};

/// Reads a CSV file: comma-separated, RFC 4180 double quotes allowed, LF or CRLF line ends, blank lines
/// skipped, a leading UTF-8 byte-order mark ignored. FormatError (naming file and line) for: an empty file, a header without data rows, a
/// duplicate or empty column name, a row whose field count differs from the header's, an unterminated
/// quote. IoError if the file cannot be opened.
[[nodiscard]] CsvTable read_csv(const std::filesystem::path& path);

/// Same, from text in memory (`name` stands for the file in messages). Used by read_csv and the fuzzer.
[[nodiscard]] CsvTable parse_csv(std::string_view text, const std::filesystem::path& name);

/// Parses a whole field as a number (leading/trailing blanks allowed, a leading '+' allowed);
/// false if the field is not exactly one number. nan/inf accepted; a number beyond double's range
/// rounds to +-inf or 0 as in IEEE arithmetic.
[[nodiscard]] bool parse_double(std::string_view field, double& value);

/// Appends one CSV row to `out`, quoting fields that contain a comma, quote or line break or begin with a
/// UTF-8 byte-order mark, so that parse_csv reads the row back unchanged.
void append_csv_row(std::string& out, const std::vector<std::string>& fields);

/// Shortest text that reads back to exactly the same double ("%.17g" where needed).
[[nodiscard]] std::string format_double(double value);

/// Writes `text` to `path` atomically (temporary file in the same directory, then rename).
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace contactnn::io
