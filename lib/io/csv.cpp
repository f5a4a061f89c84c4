#include "io/csv.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/error.hpp"
#include "io/byte_order_mark.hpp"

namespace contactnn::io {

namespace {

/// Bytes read from a file at a time: the reader's whole footprint besides one record.
constexpr std::size_t kReadBytes = std::size_t{1} << 20;
/// Written rows are handed to the stream in pieces of about this size.
constexpr std::size_t kWriteBytes = std::size_t{1} << 20;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool is_blank(std::string_view line) { return trim(line).empty(); }

std::string file_label(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

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

std::string not_a_number_message(const std::filesystem::path& file, std::size_t line, std::string_view column,
                                 std::string_view text) {
  return file_label(file) + ":" + std::to_string(line) + ": column " + quote_text(column) + ": " +
         quote_text(text) + " is not a number";
}

// ---------------------------------------------------------------------------------------------------------
// CsvReader

CsvReader::CsvReader(const std::filesystem::path& path, DataRows rows) : path_(path), streaming_(true) {
  file_.open(path, std::ios::binary);
  CONTACTNN_REQUIRE_AS(IoError, file_.good(), "cannot open " << file_label(path) << " for reading");
  buffer_.resize(kReadBytes);
  start(rows);
}

CsvReader::CsvReader(std::string_view text, const std::filesystem::path& name, DataRows rows)
    : path_(name), view_(text) {
  start(rows);
}

bool CsvReader::refill() {
  if (!streaming_) return false;
  file_.read(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  const std::streamsize got = file_.gcount();
  CONTACTNN_REQUIRE_AS(IoError, got > 0 || file_.eof(),
                       "cannot read " << file_label(path_) << ": " << std::strerror(errno));
  if (got == 0) return false;  // the view keeps the last bytes (check_encoding may step back into them)
  view_ = std::string_view(buffer_.data(), static_cast<std::size_t>(got));
  pos_ = 0;
  return true;
}

inline int CsvReader::get() {
  if (pos_ >= view_.size() && !refill()) return -1;
  return static_cast<unsigned char>(view_[pos_++]);
}

inline int CsvReader::peek() {
  if (pos_ >= view_.size() && !refill()) return -1;
  return static_cast<unsigned char>(view_[pos_]);
}

void CsvReader::check_encoding() {
  // A byte-order mark says what the text is; UTF-8's is skipped, the others are named.
  std::string head;
  while (head.size() < 4 && peek() >= 0) head += static_cast<char>(get());
  const std::string_view encoding = foreign_byte_order_mark(head);
  CONTACTNN_REQUIRE_AS(FormatError, encoding.empty(),
                       file_label(path_) << ": the file is " << encoding
                                         << " text (by its byte-order mark); save it as UTF-8 or ASCII");
  // Step back over the bytes read (a UTF-8 mark excepted): they all came from the first read, which fills
  // the buffer unless the file ends first, and refill() keeps the view at the end of the file.
  const std::size_t skip = head.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  pos_ -= head.size() - skip;
}

void CsvReader::start(DataRows rows) {
  check_encoding();
  std::size_t line = 0;
  CsvRecord record;
  const bool got_header = read_record(record, line);
  CONTACTNN_REQUIRE_AS(FormatError, got_header,
                       file_label(path_) << ": empty file: expected a header row and data rows");
  std::vector<std::string> fields = record.strings();
  for (auto& column : fields) {
    CONTACTNN_REQUIRE_AS(FormatError, column.find('\0') == std::string::npos,
                         file_label(path_)
                             << ":1: the header holds NUL bytes: UTF-16 text without a byte-order mark, "
                                "or not a text file; save it as UTF-8 or ASCII");
    column = std::string(trim(column));
  }
  // An empty or repeated name is a column like any other (pandas writes its index as a column named ""; SPEC
  // 6 copies columns it does not read): only looking one up by a name the header holds twice is an error
  // (column_index).
  header_ = std::move(fields);
  have_lookahead_ = next(lookahead_, lookahead_line_);
  CONTACTNN_REQUIRE_AS(FormatError, have_lookahead_ || rows == DataRows::kMayBeNone,
                       file_label(path_) << ": header only: expected at least one data row");
}

bool CsvReader::read_record(CsvRecord& record, std::size_t& record_line) {
  for (;;) {
    if (peek() < 0) return false;
    record_line = line_;
    record.clear();
    bool in_quotes = false;
    bool record_has_content = false;
    std::size_t quote_line = 0;  // where the last quoted field opened, for the message of an unterminated one
    for (int c = get(); c >= 0; c = get()) {
      if (in_quotes) {
        if (c == '"') {
          if (peek() == '"') {
            record.append('"');
            get();
          } else {
            in_quotes = false;
          }
        } else {
          if (c == '\n') ++line_;
          record.append(static_cast<char>(c));
        }
        continue;
      }
      if (c == '"') {
        in_quotes = true;
        quote_line = line_;
        record_has_content = true;
      } else if (c == ',') {
        record.end_field();
        record_has_content = true;
      } else if (c == '\n') {
        ++line_;
        break;
      } else if (c == '\r') {
        // Part of a CRLF line end (or the file's last byte); any other carriage return is a line end the
        // reader would otherwise merge into one record: CR-only (classic Mac OS) files.
        const int next = peek();
        CONTACTNN_REQUIRE_AS(FormatError, next == '\n' || next < 0,
                             file_label(path_)
                                 << ":" << line_
                                 << ": carriage return without a line feed (a file with CR-only line "
                                    "ends?): save it with LF or CRLF line ends");
      } else {
        record.append(static_cast<char>(c));
        if (c != ' ' && c != '\t') record_has_content = true;
      }
    }
    // An unterminated quote names the column it opens in (the header's name once the header is read).
    if (in_quotes) {
      const std::size_t column = record.size();
      throw FormatError(file_label(path_) + ":" + std::to_string(quote_line) + ": column " +
                        std::to_string(column + 1) +
                        (column < header_.size() ? " (" + quote_text(header_[column]) + ")" : std::string()) +
                        ": unterminated quoted field (no closing '\"' before the end of the file)");
    }
    if (!record_has_content && is_blank(record.current_field())) continue;  // blank line
    // Field ends are 32-bit: a record of 4 GB or more is not a CSV row anyone means.
    CONTACTNN_REQUIRE_AS(FormatError, record.text_size() < (std::size_t{1} << 32),
                         file_label(path_) << ":" << record_line << ": a record of 4 GB or more");
    record.end_field();
    return true;
  }
}

bool CsvReader::next(CsvRecord& record, std::size_t& line) {
  if (have_lookahead_) {
    std::swap(record, lookahead_);
    line = lookahead_line_;
    have_lookahead_ = false;
    return true;
  }
  std::size_t record_line = 0;
  if (!read_record(record, record_line)) return false;
  // A ragged row names the first column it lacks, or the first field beyond the header (SPEC 6: file, line
  // and column).
  CONTACTNN_REQUIRE_AS(FormatError, header_.empty() || record.size() == header_.size(),
                       file_label(path_)
                           << ":" << record_line << ": ragged row: " << record.size()
                           << " fields, the header has " << header_.size() << " ("
                           << (record.size() < header_.size()
                                   ? "column " + std::to_string(record.size() + 1) + ", " +
                                         quote_text(header_[record.size()]) + ", missing"
                                   : "column " + std::to_string(header_.size() + 1) + " is beyond the header")
                           << ")");
  line = record_line;
  return true;
}

std::vector<std::string> CsvRecord::strings() const {
  std::vector<std::string> out;
  out.reserve(size());
  for (std::size_t i = 0; i < size(); ++i) out.emplace_back((*this)[i]);
  return out;
}

std::optional<std::size_t> find_column(const std::vector<std::string>& header, std::string_view name,
                                       const std::filesystem::path& path) {
  const auto found = std::find(header.begin(), header.end(), name);
  if (found == header.end()) return std::nullopt;
  CONTACTNN_REQUIRE_AS(FormatError, std::find(found + 1, header.end(), name) == header.end(),
                       file_label(path)
                           << ":1: duplicate column " << quote_text(std::string(name)) << " in the header");
  return static_cast<std::size_t>(found - header.begin());
}

namespace {

/// The index of the one column called `name`: FormatError when the header has none, or more than one.
std::size_t column_index(const std::vector<std::string>& header, std::string_view name,
                         const std::filesystem::path& path) {
  const std::optional<std::size_t> found = find_column(header, name, path);
  CONTACTNN_REQUIRE_AS(FormatError, found.has_value(),
                       file_label(path) << ":1: missing column " << quote_text(std::string(name)));
  return *found;
}

}  // namespace

std::size_t CsvReader::column(std::string_view name) const { return column_index(header_, name, path_); }

// ---------------------------------------------------------------------------------------------------------
// CsvTable

std::size_t CsvTable::column(std::string_view name) const { return column_index(header, name, path); }

double CsvTable::number(std::size_t row, std::size_t col) const {
  double value = 0.0;
  if (!parse_double(rows[row][col], value)) {
    throw FormatError(not_a_number_message(path, line_numbers[row], header[col], rows[row][col]));
  }
  return value;
}

namespace {
CsvTable read_all(CsvReader& reader) {
  CsvTable table;
  table.path = reader.path();
  table.header = reader.header();
  CsvRecord record;
  std::size_t line = 0;
  while (reader.next(record, line)) {
    table.rows.push_back(record.strings());
    table.line_numbers.push_back(line);
  }
  return table;
}
}  // namespace

CsvTable parse_csv(std::string_view text, const std::filesystem::path& name) {
  CsvReader reader(text, name);
  return read_all(reader);
}

CsvTable read_csv(const std::filesystem::path& path) {
  CsvReader reader(path);
  return read_all(reader);
}

// ---------------------------------------------------------------------------------------------------------
// Writing

void append_csv_field(std::string& out, std::string_view f) {
  // Quoted: a comma, quote or line break, and a leading byte-order mark of any encoding, which the reader
  // interprets at the start of a file (unquoted, a first column named "\xEF\xBB\xBFid" would read back as
  // "id", and one starting with "\xFE\xFF" would make the file read as UTF-16).
  const auto starts = [&](std::string_view mark) { return f.substr(0, mark.size()) == mark; };
  const bool mark = starts("\xEF\xBB\xBF") || starts("\xFE\xFF") || starts("\xFF\xFE") ||
                    starts(std::string_view("\0\0\xFE\xFF", 4));
  if (f.find_first_of(",\"\n\r") == std::string_view::npos && !mark) {
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

void append_csv_row(std::string& out, const std::vector<std::string>& fields) {
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) out += ',';
    append_csv_field(out, fields[i]);
  }
  out += '\n';
}

std::string format_double(double value) {
  char buffer[32];
  // to_chars without a precision gives the shortest representation that round-trips exactly.
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

CsvWriter::CsvWriter(const std::filesystem::path& path) : output_(path, AtomicOutput::Access::kSequential) {
  stream_.open(output_.write_path(), std::ios::binary | std::ios::trunc);
  CONTACTNN_REQUIRE_AS(IoError, stream_.good(),
                       "cannot create " << file_label(output_.write_path()) << ": " << std::strerror(errno));
  buffer_.reserve(kWriteBytes + 4096);
}

void CsvWriter::write_row(const std::vector<std::string>& fields) {
  append_csv_row(buffer_, fields);
  if (buffer_.size() >= kWriteBytes) flush_buffer();
}

void CsvWriter::field(std::string_view text) {
  if (row_started_) buffer_ += ',';
  append_csv_field(buffer_, text);
  row_started_ = true;
}

void CsvWriter::end_row() {
  buffer_ += '\n';
  row_started_ = false;
  if (buffer_.size() >= kWriteBytes) flush_buffer();
}

void CsvWriter::flush_buffer() {
  stream_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  buffer_.clear();
  CONTACTNN_REQUIRE_AS(IoError, stream_.good(),
                       "cannot write " << file_label(output_.final_path()) << ": " << std::strerror(errno));
}

void CsvWriter::commit() {
  flush_buffer();
  stream_.flush();
  CONTACTNN_REQUIRE_AS(IoError, stream_.good(),
                       "cannot write " << file_label(output_.final_path()) << ": " << std::strerror(errno));
  stream_.close();
  CONTACTNN_REQUIRE_AS(IoError, !stream_.fail(),
                       "cannot write " << file_label(output_.final_path()) << ": " << std::strerror(errno));
  output_.commit();
}

std::unique_ptr<AtomicOutput> write_text_uncommitted(const std::filesystem::path& path,
                                                     std::string_view text) {
  auto output = std::make_unique<AtomicOutput>(path, AtomicOutput::Access::kSequential);
  std::ofstream out(output->write_path(), std::ios::binary | std::ios::trunc);
  CONTACTNN_REQUIRE_AS(IoError, out.good(),
                       "cannot create " << file_label(output->write_path()) << ": " << std::strerror(errno));
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.flush();
  CONTACTNN_REQUIRE_AS(IoError, out.good(),
                       "cannot write " << file_label(path) << ": " << std::strerror(errno));
  out.close();
  CONTACTNN_REQUIRE_AS(IoError, !out.fail(),
                       "cannot write " << file_label(path) << ": " << std::strerror(errno));
  return output;
}

void write_text_atomically(const std::filesystem::path& path, std::string_view text) {
  write_text_uncommitted(path, text)->commit();
}

}  // namespace contactnn::io
