#include "io/csv.hpp"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <unordered_set>

#include "core/error.hpp"
#include "io/atomic_output.hpp"

namespace contactnn::io {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool is_blank(std::string_view line) { return trim(line).empty(); }

}  // namespace

bool parse_double(std::string_view field, double& value) {
  field = trim(field);
  if (!field.empty() && field.front() == '+') {
    field.remove_prefix(1);
    if (!field.empty() && (field.front() == '-' || field.front() == '+')) return false;  // "+-1"
  }
  if (field.empty()) return false;
  const char* end = field.data() + field.size();
  const auto result = std::from_chars(field.data(), end, value);
  if (result.ptr != end) return false;
  if (result.ec == std::errc::result_out_of_range) {
    // A well-formed number beyond double's range (1e400, 1e-400): rounded as IEEE does, to +-inf (the row
    // is then invalid) or to 0, rather than reported as "not a number". strtod does that rounding.
    value = std::strtod(std::string(field).c_str(), nullptr);
    return true;
  }
  return result.ec == std::errc();
}

std::size_t CsvTable::column(std::string_view name) const {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return i;
  }
  throw FormatError("'" + path.string() + "':1: missing column '" + std::string(name) + "'");
}

double CsvTable::number(std::size_t row, std::size_t col) const {
  double value = 0.0;
  if (!parse_double(rows[row][col], value)) {
    throw FormatError("'" + path.string() + "':" + std::to_string(line_numbers[row]) + ": column '" + header[col] +
                      "': '" + rows[row][col] + "' is not a number");
  }
  return value;
}

CsvTable parse_csv(std::string_view text, const std::filesystem::path& name) {
  CsvTable table;
  table.path = name;
  const std::string file = "'" + name.string() + "'";

  // Splits the text into records of fields, honouring quotes (which may span lines). A UTF-8 byte-order
  // mark (spreadsheet exports) is not part of the first column's name.
  std::size_t pos = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  std::size_t line = 1;
  bool have_header = false;
  while (pos < text.size()) {
    const std::size_t record_line = line;
    std::vector<std::string> fields;
    std::string field;
    bool in_quotes = false;
    bool record_has_content = false;
    for (; pos < text.size(); ++pos) {
      const char c = text[pos];
      if (in_quotes) {
        if (c == '"') {
          if (pos + 1 < text.size() && text[pos + 1] == '"') {
            field += '"';
            ++pos;
          } else {
            in_quotes = false;
          }
        } else {
          if (c == '\n') ++line;
          field += c;
        }
        continue;
      }
      if (c == '"') {
        in_quotes = true;
        record_has_content = true;
      } else if (c == ',') {
        fields.push_back(std::move(field));
        field.clear();
        record_has_content = true;
      } else if (c == '\n') {
        ++pos;
        ++line;
        break;
      } else if (c == '\r') {
        // part of a CRLF line end, or stray: never part of a field
      } else {
        field += c;
        if (c != ' ' && c != '\t') record_has_content = true;
      }
    }
    CONTACTNN_REQUIRE_AS(FormatError, !in_quotes,
                         file << ":" << record_line << ": unterminated quoted field");
    if (!record_has_content && is_blank(field)) continue;  // blank line
    fields.push_back(std::move(field));
    if (!have_header) {
      std::unordered_set<std::string> seen;
      for (auto& column : fields) {
        column = std::string(trim(column));
        CONTACTNN_REQUIRE_AS(FormatError, !column.empty(), file << ":1: empty column name in the header");
        CONTACTNN_REQUIRE_AS(FormatError, seen.insert(column).second,
                             file << ":1: duplicate column '" << column << "' in the header");
      }
      table.header = std::move(fields);
      have_header = true;
      continue;
    }
    CONTACTNN_REQUIRE_AS(FormatError, fields.size() == table.header.size(),
                         file << ":" << record_line << ": ragged row: " << fields.size() << " fields, the header has "
                              << table.header.size());
    table.rows.push_back(std::move(fields));
    table.line_numbers.push_back(record_line);
  }
  CONTACTNN_REQUIRE_AS(FormatError, have_header, file << ": empty file: expected a header row and data rows");
  CONTACTNN_REQUIRE_AS(FormatError, !table.rows.empty(), file << ": header only: expected at least one data row");
  return table;
}

CsvTable read_csv(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  CONTACTNN_REQUIRE_AS(IoError, in.good(), "cannot open '" << path.string() << "' for reading");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_csv(buffer.str(), path);
}

void append_csv_row(std::string& out, const std::vector<std::string>& fields) {
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) out += ',';
    const std::string& f = fields[i];
    // Quoted: a comma, quote or line break, and a leading byte-order mark (which the reader skips at the
    // start of a file: unquoted, a first column named "\xEF\xBB\xBFid" would read back as "id").
    if (f.find_first_of(",\"\n\r") == std::string::npos && f.rfind("\xEF\xBB\xBF", 0) != 0) {
      out += f;
    } else {
      out += '"';
      for (char c : f) {
        if (c == '"') out += '"';
        out += c;
      }
      out += '"';
    }
  }
  out += '\n';
}

std::string format_double(double value) {
  char buffer[32];
  // to_chars without a precision gives the shortest representation that round-trips exactly.
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

void write_text_atomically(const std::filesystem::path& path, std::string_view text) {
  AtomicOutput output(path);
  {
    std::ofstream out(output.temp_path(), std::ios::binary | std::ios::trunc);
    CONTACTNN_REQUIRE_AS(IoError, out.good(), "cannot create '" << output.temp_path().string() << "'");
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    CONTACTNN_REQUIRE_AS(IoError, out.good(), "cannot write '" << output.temp_path().string() << "' (disk full?)");
  }
  output.commit();
}

}  // namespace contactnn::io
