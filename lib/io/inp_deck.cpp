// The .inp deck reader (inp_deck.hpp): the files and their lines, the fields of a line, the keyword lines and
// the entry points; nodes, elements and sets in inp_deck_mesh.cpp, surfaces, pairs and cyclic symmetry in
// inp_deck_contact.cpp (inp_deck_detail.hpp).
#include "io/inp_deck.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "io/byte_order_mark.hpp"
#include "io/inp_deck_detail.hpp"

namespace contactnn::io::detail {

namespace {

// The longest line a deck may hold: Abaqus reads 256 characters a line, CalculiX 132. Anything longer is not
// a deck (a binary file, CR-only line ends read as one line) and is refused before it fills memory.
constexpr std::size_t kMaxLineBytes = std::size_t{64} << 10;
// Files are read this many bytes at a time.
constexpr std::size_t kChunkBytes = std::size_t{1} << 20;
// Linux's PATH_MAX: an INPUT= longer than this names no file.
constexpr std::size_t kMaxPathBytes = 4096;

/// A file opened by open_regular_file: `file` when it opened, else `error` (an errno); `other_kind` says what
/// the path is when it is not a regular file ("a directory"), and the file is then not to be read.
struct OpenedFile {
  InputFile file;
  int error = 0;
  std::string other_kind;
};

/// Opens `path` for reading and says what it is. A directory reads as an empty file and /dev/zero as an
/// endless one; a FIFO is opened without waiting for a writer (O_NONBLOCK, cleared again for a regular file).
OpenedFile open_regular_file(const fs::path& path) {
  OpenedFile out;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    out.error = errno;
    return out;
  }
  out.file = InputFile(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    out.error = errno;
    return out;
  }
  if (S_ISREG(st.st_mode)) {
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags >= 0) (void)::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    return out;
  }
  out.other_kind = S_ISDIR(st.st_mode)    ? "a directory"
                   : S_ISCHR(st.st_mode)  ? "a character device"
                   : S_ISBLK(st.st_mode)  ? "a block device"
                   : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                   : S_ISSOCK(st.st_mode) ? "a socket"
                                          : "of an unknown kind";
  out.file.close();
  return out;
}

}  // namespace

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::string keyword_form(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c != ' ' && c != '\t') out.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  }
  return out;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  bool quoted = false;
  for (std::size_t i = 0; i <= line.size(); ++i) {
    if (i < line.size() && line[i] == '"') quoted = !quoted;
    if (i == line.size() || (line[i] == ',' && !quoted)) {
      fields.push_back(trim(line.substr(start, i - start)));
      start = i + 1;
    }
  }
  return fields;
}

std::vector<std::string_view> non_empty(const std::vector<std::string_view>& fields) {
  std::vector<std::string_view> out;
  for (auto f : fields) {
    if (!f.empty()) out.push_back(f);
  }
  return out;
}

std::string unquote(std::string_view s) {
  s = trim(s);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(s);
}

bool parse_id(std::string_view field, long& id) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  const char* end = field.data() + field.size();
  const auto r = std::from_chars(field.data(), end, id);
  return r.ec == std::errc() && r.ptr == end && !field.empty();
}

bool parse_coordinate(std::string_view field, double& value) {
  std::string text(field);
  for (char& c : text) {
    if (c == 'd' || c == 'D') c = 'e';
  }
  std::string_view v = text;
  if (!v.empty() && v.front() == '+') v.remove_prefix(1);
  if (v.empty() || v.front() == '+') return false;
  const char* end = v.data() + v.size();
  const auto r = std::from_chars(v.data(), end, value);
  return r.ec == std::errc() && r.ptr == end && std::isfinite(value);
}

int parse_face_label(std::string_view field) {
  const std::string u = upper(field);
  if (u == "SPOS") return -1;
  if (u == "SNEG") return -2;
  if (u.size() < 2 || u.size() > 3 || u[0] != 'S') return 0;
  int face = 0;
  const auto r = std::from_chars(u.data() + 1, u.data() + u.size(), face);
  if (r.ec != std::errc() || r.ptr != u.data() + u.size() || face < 1) return 0;
  return face;
}

mesh::ContactModel DeckReader::read(InputFile input, std::string text, const fs::path& name) {
  push_source(std::move(input), std::move(text), name, canonical_or_empty(name));
  std::string_view line;
  Location loc;
  while (next_line(line, loc)) {
    const std::string_view t = trim(line);
    if (t.empty() || t.substr(0, 2) == "**") continue;
    if (t.front() == '*') {
      keyword(t, loc);
    } else {
      data(t, loc);
    }
  }
  finish_element(true);
  return resolve();
}

fs::path DeckReader::canonical_or_empty(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  return ec ? fs::path() : c;
}

void DeckReader::push_source(InputFile input, std::string text, const fs::path& name, fs::path canonical) {
  auto source = std::make_unique<Source>();
  source->input = std::move(input);
  source->chunk = std::move(text);
  source->file = static_cast<int>(file_names_.size());
  source->canonical = std::move(canonical);
  file_names_.push_back(name.string());
  stack_.push_back(std::move(source));
}

/// Opens the file `input` (INPUT= of the line at `loc`) and makes it the current source.
void DeckReader::push_file(const std::string& input, Location loc, std::string_view keyword_name) {
  if (input.size() > kMaxPathBytes) {
    fail(loc, keyword_name,
         "INPUT=" + quote_text(input) + " is longer than any path (" + std::to_string(kMaxPathBytes) +
             " bytes)");
  }
  fs::path target(input);
  if (target.is_relative())
    target = fs::path(file_names_[static_cast<std::size_t>(loc.file)]).parent_path() / target;
  target = target.lexically_normal();
  const fs::path canonical = canonical_or_empty(target);
  for (const auto& source : stack_) {
    if (!canonical.empty() && source->canonical == canonical) {
      std::string chain;
      for (const auto& s : stack_) chain += file_names_[static_cast<std::size_t>(s->file)] + " -> ";
      fail(loc, keyword_name,
           "'" + input + "' is already being read (an include loop: " + chain + target.string() + ")");
    }
  }
  OpenedFile opened = open_regular_file(target);
  if (opened.error != 0) {
    throw IoError(where(loc) + ": " + std::string(keyword_name) + ": cannot open INPUT='" + input + "' (" +
                  target.string() + "): " + std::generic_category().message(opened.error));
  }
  if (!opened.other_kind.empty()) {
    fail(loc, keyword_name,
         "INPUT='" + input + "' (" + target.string() + ") is " + opened.other_kind + ", not a regular file");
  }
  push_source(std::move(opened.file), std::string(), target, canonical);
}

/// Reads the next chunk of `s`'s file; false at its end (and for a deck given as text, whose one chunk is
/// its whole text).
bool DeckReader::refill(Source& s) const {
  if (!s.input.is_open()) return false;
  s.chunk.resize(kChunkBytes);
  const long got = s.input.read(s.chunk.data(), kChunkBytes);
  if (got < 0) {
    throw IoError("cannot read '" + file_names_[static_cast<std::size_t>(s.file)] +
                  "': " + std::generic_category().message(static_cast<int>(-got)));
  }
  s.chunk.resize(static_cast<std::size_t>(got));
  s.pos = 0;
  if (got == 0) s.input.close();
  return got > 0;
}

/// The next line of `s` into s.text, without its line end; false when the file holds no more. A line
/// longer than kMaxLineBytes is an error (checked as it grows: a file of one endless line is not read
/// whole).
bool DeckReader::read_line(Source& s) const {
  s.text.clear();
  bool any = false;
  for (;;) {
    if (s.pos >= s.chunk.size() && !refill(s)) return any;
    const char* begin = s.chunk.data() + s.pos;
    const std::size_t available = s.chunk.size() - s.pos;
    const auto* newline = static_cast<const char*>(std::memchr(begin, '\n', available));
    const std::size_t length = newline != nullptr ? static_cast<std::size_t>(newline - begin) : available;
    any = true;
    if (s.text.size() + length > kMaxLineBytes) {
      // What the line holds names the file's encoding or line ends better than its length does.
      s.text.append(begin, kMaxLineBytes - s.text.size());
      const Location loc{s.file, s.line + 1};
      check_text(s.text, loc);
      throw FormatError(where(loc) + ": the line is longer than " + std::to_string(kMaxLineBytes) +
                        " bytes (Abaqus reads 256 characters a line): not an input deck");
    }
    s.text.append(begin, length);
    s.pos += length;
    if (newline != nullptr) {
      ++s.pos;
      return true;
    }
  }
}

/// FormatError naming the encoding or the line ends of text that is not a deck: a UTF-16 or UTF-32
/// byte-order mark (line 1), NUL bytes (UTF-16 or UTF-32 without a mark, or a binary file), a carriage
/// return inside a line (CR-only line ends), another control character (a binary file).
void DeckReader::check_text(std::string_view text, Location loc) const {
  const auto say = [&](const std::string& what) { throw FormatError(where(loc) + ": " + what); };
  if (loc.line == 1) {
    const std::string_view encoding = foreign_byte_order_mark(text);
    if (!encoding.empty()) {
      say("the file is " + std::string(encoding) +
          " text (by its byte-order mark); save the deck as UTF-8 or ASCII");
    }
  }
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 || c == '\t') continue;
    const std::string column = "column " + std::to_string(i + 1) + ": ";
    if (c == 0) {
      say(column +
          "a NUL byte: UTF-16 or UTF-32 text without a byte-order mark, or a binary file, not a deck "
          "(save the deck as UTF-8 or ASCII)");
    }
    if (c == '\r') {
      say(column +
          "a carriage return without a line feed (a file with CR-only line ends?): save the deck with "
          "LF or CRLF line ends");
    }
    if (c != '\f' && c != '\v') {
      char code[8];
      std::snprintf(code, sizeof code, "0x%02X", static_cast<unsigned>(c));
      say(column + "control character " + code + ": a binary file, not a deck");
    }
  }
}

bool DeckReader::next_line(std::string_view& line, Location& loc) {
  while (!stack_.empty()) {
    Source& s = *stack_.back();
    if (!read_line(s)) {
      stack_.pop_back();
      continue;
    }
    loc = {s.file, ++s.line};
    line = s.text;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (loc.line == 1 && line.substr(0, 3) == "\xEF\xBB\xBF")
      line.remove_prefix(3);  // a UTF-8 byte-order mark
    check_text(line, loc);
    return true;
  }
  return false;
}

std::string DeckReader::where(Location loc) const {
  return "'" + file_names_[static_cast<std::size_t>(loc.file)] + "':" + std::to_string(loc.line);
}

void DeckReader::fail(Location loc, std::string_view keyword_name, const std::string& message) const {
  throw FormatError(where(loc) + ": " + std::string(keyword_name) + ": " + message);
}

void DeckReader::keyword(std::string_view line, Location loc) {
  const std::vector<std::string_view> fields = split_fields(line.substr(1));
  const std::string name = keyword_form(fields[0]);
  Parameters params;
  for (std::size_t i = 1; i < fields.size(); ++i) {
    if (fields[i].empty()) continue;
    const std::size_t eq = fields[i].find('=');
    if (eq == std::string_view::npos) {
      params.entries.emplace_back(keyword_form(fields[i]), "");
    } else {
      params.entries.emplace_back(keyword_form(fields[i].substr(0, eq)), unquote(fields[i].substr(eq + 1)));
    }
  }
  // For messages: the keyword as the deck spells it, upper case, blanks as one ("*CONTACT PAIR", not the
  // compared form "*CONTACTPAIR").
  std::string shown = "*";
  for (const char c : upper(fields[0])) {
    const bool blank = c == ' ' || c == '\t';
    if (!blank) {
      shown.push_back(c);
    } else if (shown.back() != ' ') {
      shown.push_back(' ');
    }
  }
  // The included lines take the place of the *INCLUDE line: the current block goes on.
  if (name == "INCLUDE") {
    const auto input = params.get("INPUT");
    if (!input || input->empty()) fail(loc, shown, "missing INPUT=");
    push_file(*input, loc, shown);
    return;
  }
  finish_element(true);
  keyword_ = shown;
  block_ = Block::kSkip;
  target_set_.clear();
  generate_ = params.has("GENERATE");
  const auto required = [&](std::string_view parameter) {
    const auto value = params.get(parameter);
    if (!value || value->empty()) fail(loc, shown, "missing " + std::string(parameter) + "=");
    return *value;
  };
  if (name == "NODE") {
    block_ = Block::kNode;
    if (const auto system = params.get("SYSTEM"); system && keyword_form(*system) != "R") {
      fail(loc, shown,
           "SYSTEM=" + quote_text(*system) + " is not supported (only rectangular coordinates, SYSTEM=R)");
    }
    if (const auto set = params.get("NSET")) target_set_ = define_set(nsets_, *set, loc);
  } else if (name == "ELEMENT") {
    block_ = Block::kElement;
    element_type_ = type_index(required("TYPE"));
    if (const auto set = params.get("ELSET")) target_set_ = define_set(elsets_, *set, loc);
  } else if (name == "NSET") {
    block_ = Block::kNset;
    target_set_ = define_set(nsets_, required("NSET"), loc);
    if (const auto elset = params.get("ELSET")) nodes_of_element_set(*elset, loc);
  } else if (name == "ELSET") {
    block_ = Block::kElset;
    target_set_ = define_set(elsets_, required("ELSET"), loc);
  } else if (name == "SURFACE") {
    block_ = Block::kSurface;
    surface_ = define_surface(required("NAME"), params.get("TYPE").value_or("ELEMENT"), loc);
  } else if (name == "CONTACTPAIR") {
    block_ = Block::kContactPair;
    const auto type = params.get("TYPE");
    node_to_surface_ = !type || keyword_form(*type) == "NODETOSURFACE";
  } else if (name == "TIE" && params.has("CYCLICSYMMETRY")) {
    block_ = Block::kTie;
    ties_.push_back({required("NAME"), "", "", loc});
  } else if (name == "CYCLICSYMMETRYMODEL") {
    block_ = Block::kCyclic;
    PendingCyclic c;
    const std::string n = required("N");
    long sectors = 0;
    if (!parse_id(n, sectors) || sectors < 1 || sectors > 1000000) {
      fail(loc, shown, "N=" + quote_text(n) + " is not a number of sectors (a positive integer)");
    }
    c.sectors = static_cast<int>(sectors);
    c.tie = params.get("TIE").value_or("");
    c.where = loc;
    cyclic_.push_back(std::move(c));
  }
  if (block_ != Block::kSkip && block_ != Block::kSurface && block_ != Block::kContactPair &&
      block_ != Block::kTie && block_ != Block::kCyclic) {
    if (const auto input = params.get("INPUT")) push_file(*input, loc, shown);
  }
}

void DeckReader::data(std::string_view line, Location loc) {
  switch (block_) {
    case Block::kSkip: return;
    case Block::kNode: return node_line(line, loc);
    case Block::kElement: return element_line(line, loc);
    case Block::kNset: return set_line(nsets_, "node", line, loc);
    case Block::kElset: return set_line(elsets_, "element", line, loc);
    case Block::kSurface: return surface_line(line, loc);
    case Block::kContactPair: return pair_line(line, loc);
    case Block::kTie: return tie_line(line, loc);
    case Block::kCyclic: return cyclic_line(line, loc);
  }
}

}  // namespace contactnn::io::detail

namespace contactnn::io {

using detail::DeckReader;
using detail::InputFile;
using detail::open_regular_file;
using detail::OpenedFile;

mesh::ContactModel read_inp_deck(const std::filesystem::path& path) {
  OpenedFile opened = open_regular_file(path);
  if (opened.error != 0) {
    throw IoError("cannot open deck '" + path.string() +
                  "': " + std::generic_category().message(opened.error));
  }
  if (!opened.other_kind.empty()) {
    throw FormatError("'" + path.string() + "' is " + opened.other_kind +
                      ", not a regular file (a deck is read from a regular file)");
  }
  return DeckReader().read(std::move(opened.file), std::string(), path);
}

mesh::ContactModel parse_inp_deck(std::string_view text, const std::filesystem::path& name) {
  return DeckReader().read(InputFile(), std::string(text), name);
}

namespace {

void scan_geometry_keywords(const std::filesystem::path& path, int depth, std::vector<std::string>& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in || depth > 16) return;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.size() < 2 || line[0] != '*' || line[1] == '*') continue;
    std::string key;  // upper case, without blanks
    for (const char c : line) {
      if (c != ' ' && c != '\t' && c != '\r')
        key += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    const auto starts = [&](std::string_view k) { return key.compare(0, k.size(), k) == 0; };
    const auto has = [&](std::string_view p) { return key.find(p) != std::string::npos; };
    if (starts("*INCLUDE")) {
      // INPUT= as written (case kept), up to the next comma, blanks and quotes trimmed; relative to this
      // file.
      std::string upper = line;
      for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      const std::size_t at = upper.find("INPUT");
      const std::size_t eq = at == std::string::npos ? std::string::npos : line.find('=', at);
      if (eq == std::string::npos) continue;
      std::string input = line.substr(eq + 1);
      input = input.substr(0, input.find(','));
      const std::size_t first = input.find_first_not_of(" \t\"");
      const std::size_t last = input.find_last_not_of(" \t\r\"");
      if (first != std::string::npos) {
        scan_geometry_keywords(path.parent_path() / input.substr(first, last - first + 1), depth + 1, out);
      }
      continue;
    }
    const bool geometry = starts("*CLEARANCE") || (starts("*CONTACTPAIR") && has("ADJUST=")) ||
                          starts("*CONTACTINTERFERENCE") || (starts("*SHELLSECTION") && has("OFFSET="));
    if (!geometry) continue;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    out.push_back("'" + path.string() + "':" + std::to_string(number) + ": " +
                  escape_text(line.size() > 80 ? line.substr(0, 80) + "..." : line));
  }
}

}  // namespace

std::vector<std::string> unapplied_geometry_keywords(const std::filesystem::path& path) {
  std::vector<std::string> out;
  scan_geometry_keywords(path, 0, out);
  return out;
}

}  // namespace contactnn::io