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

namespace contactnn::io {

namespace {

namespace fs = std::filesystem;

// A GENERATE line expanding to more ids than this is taken for a typo, not for a mesh.
constexpr long kMaxGeneratedIds = 100'000'000;
// The longest line a deck may hold: Abaqus reads 256 characters a line, CalculiX 132. Anything longer is not
// a deck (a binary file, CR-only line ends read as one line) and is refused before it fills memory.
constexpr std::size_t kMaxLineBytes = std::size_t{64} << 10;
// Files are read this many bytes at a time.
constexpr std::size_t kChunkBytes = std::size_t{1} << 20;
// Linux's PATH_MAX: an INPUT= longer than this names no file.
constexpr std::size_t kMaxPathBytes = 4096;

/// A file descriptor open for reading, closed when it goes.
class InputFile {
 public:
  InputFile() = default;
  explicit InputFile(int fd) : fd_(fd) {}
  InputFile(InputFile&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  InputFile& operator=(InputFile&& other) noexcept {
    if (this != &other) {
      close();
      fd_ = std::exchange(other.fd_, -1);
    }
    return *this;
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  ~InputFile() { close(); }

  [[nodiscard]] bool is_open() const { return fd_ >= 0; }
  /// Up to `size` bytes into `data`: the count read (0 at the end), or -errno.
  long read(char* data, std::size_t size) const {
    for (;;) {
      const ssize_t got = ::read(fd_, data, size);
      if (got >= 0) return static_cast<long>(got);
      if (errno != EINTR) return -static_cast<long>(errno);
    }
  }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_ = -1;
};

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

/// Upper case without blanks: how keywords and parameter names compare ("Contact Pair" = "CONTACTPAIR").
std::string keyword_form(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c != ' ' && c != '\t') out.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  }
  return out;
}

/// Comma-separated fields, trimmed; commas inside double quotes do not split. Empty fields are kept.
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

/// A whole field as a positive integer id.
bool parse_id(std::string_view field, long& id) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  const char* end = field.data() + field.size();
  const auto r = std::from_chars(field.data(), end, id);
  return r.ec == std::errc() && r.ptr == end && !field.empty();
}

/// A whole field as a finite number; a Fortran D exponent (1.5D+03) is accepted.
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

/// S1..S99 -> 1..99; SPOS -> -1, SNEG -> -2 (shell faces: counted, never segments); 0 if not a face label.
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

struct Location {
  int file = -1;
  long line = 0;
};

/// Keyword parameters: NAME=VALUE or NAME, names compared in keyword_form.
struct Parameters {
  std::vector<std::pair<std::string, std::string>> entries;  // (keyword_form(name), value as written)

  [[nodiscard]] std::optional<std::string> get(std::string_view name) const {
    for (const auto& [key, value] : entries) {
      if (key == name) return value;
    }
    return std::nullopt;
  }
  [[nodiscard]] bool has(std::string_view name) const { return get(name).has_value(); }
};

struct NamedSet {
  std::string name;  // as first written
  std::vector<long> ids;
  Location where;
};

struct PendingElement {
  long id = 0;
  int type = 0;                    // index into Reader::types_
  std::size_t begin = 0, end = 0;  // node ids in Reader::element_node_ids_
  Location where;
};

struct SurfaceEntry {
  std::string reference;  // element / node id or set name, as written
  int face = 0;           // element surfaces: 1.. or -1/-2 (SPOS/SNEG)
  Location where;
};

struct PendingSurface {
  std::string name;
  mesh::SurfaceType type = mesh::SurfaceType::kElement;
  std::string type_text;
  std::vector<SurfaceEntry> entries;
  Location where;
};

struct PendingPair {
  std::string slave, master;
  bool node_to_surface = true;
  Location where;
};

/// A *TIE, CYCLIC SYMMETRY data line: "dependent surface, independent surface".
struct PendingTie {
  std::string name, dependent, independent;
  Location where;
};

/// A *CYCLIC SYMMETRY MODEL: N=, TIE= (empty: the deck's only cyclic tie) and its axis line.
struct PendingCyclic {
  int sectors = 0;
  std::string tie;
  std::array<double, 6> axis{};
  bool has_axis = false;
  Location where;
};

enum class Block { kSkip, kNode, kElement, kNset, kElset, kSurface, kContactPair, kTie, kCyclic };

class DeckReader {
 public:
  /// Reads the deck from `input` (open) or, when it is not open, from `text`; `name` names it in messages.
  mesh::ContactModel read(InputFile input, std::string text, const fs::path& name) {
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

 private:
  // ---- Sources: the deck and its includes, a stack of files read line by line ----------------------------
  // A file is streamed in chunks of kChunkBytes (a deck given as text is one chunk): the reader holds one
  // chunk and one line per open file, whatever the file's size.
  struct Source {
    InputFile input;    // not open for a deck given as text
    std::string chunk;  // bytes read; those from `pos` on are not consumed yet
    std::size_t pos = 0;
    std::string text;  // the current line, without its line end
    long line = 0;     // its number, from 1
    int file = 0;      // index into file_names_
    fs::path canonical;
  };
  std::vector<std::unique_ptr<Source>> stack_;
  std::vector<std::string> file_names_;

  static fs::path canonical_or_empty(const fs::path& p) {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(p, ec);
    return ec ? fs::path() : c;
  }

  void push_source(InputFile input, std::string text, const fs::path& name, fs::path canonical) {
    auto source = std::make_unique<Source>();
    source->input = std::move(input);
    source->chunk = std::move(text);
    source->file = static_cast<int>(file_names_.size());
    source->canonical = std::move(canonical);
    file_names_.push_back(name.string());
    stack_.push_back(std::move(source));
  }

  /// Opens the file `input` (INPUT= of the line at `loc`) and makes it the current source.
  void push_file(const std::string& input, Location loc, std::string_view keyword_name) {
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
      fail(
          loc, keyword_name,
          "INPUT='" + input + "' (" + target.string() + ") is " + opened.other_kind + ", not a regular file");
    }
    push_source(std::move(opened.file), std::string(), target, canonical);
  }

  /// Reads the next chunk of `s`'s file; false at its end (and for a deck given as text, whose one chunk is
  /// its whole text).
  bool refill(Source& s) const {
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
  bool read_line(Source& s) const {
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
  void check_text(std::string_view text, Location loc) const {
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

  bool next_line(std::string_view& line, Location& loc) {
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

  [[nodiscard]] std::string where(Location loc) const {
    return "'" + file_names_[static_cast<std::size_t>(loc.file)] + "':" + std::to_string(loc.line);
  }

  [[noreturn]] void fail(Location loc, std::string_view keyword_name, const std::string& message) const {
    throw FormatError(where(loc) + ": " + std::string(keyword_name) + ": " + message);
  }

  // ---- Keyword lines ------------------------------------------------------------------------------------
  Block block_ = Block::kSkip;
  std::string keyword_;     // "*NODE", for messages
  std::string target_set_;  // NSET= / ELSET= of *NODE, *ELEMENT, *NSET, *ELSET (keyword_form), or ""
  bool generate_ = false;
  int element_type_ = -1;
  int surface_ = -1;
  bool node_to_surface_ = true;

  void keyword(std::string_view line, Location loc) {
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

  // ---- Data lines ---------------------------------------------------------------------------------------
  void data(std::string_view line, Location loc) {
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

  long id_field(std::string_view field, std::size_t index, Location loc, std::string_view what) const {
    long id = 0;
    if (!parse_id(field, id) || id <= 0) {
      fail(loc, keyword_,
           "field " + std::to_string(index + 1) + ": " + quote_text(field) + " is not a " +
               std::string(what) + " (a positive integer)");
    }
    return id;
  }

  // Nodes go straight into the mesh; where each was defined is kept for the duplicate message.
  mesh::ContactModel model_;
  std::vector<Location> node_where_;

  void node_line(std::string_view line, Location loc) {
    const std::vector<std::string_view> f = split_fields(line);
    const long id = id_field(f[0], 0, loc, "node id");
    if (f.size() < 2) fail(loc, keyword_, "node " + std::to_string(id) + " has no coordinates");
    mesh::Vec3 x = mesh::Vec3::Zero();
    for (std::size_t k = 1; k < f.size() && k <= 3; ++k) {
      if (f[k].empty()) continue;  // a blank coordinate is 0, as in Abaqus
      double value = 0.0;
      if (!parse_coordinate(f[k], value)) {
        fail(loc, keyword_,
             "node " + std::to_string(id) + ": field " + std::to_string(k + 1) + ": " + quote_text(f[k]) +
                 " is not a finite number");
      }
      x[static_cast<Eigen::Index>(k - 1)] = value;
    }
    const int existing = model_.mesh.find_node(id);
    if (existing >= 0) {
      if (model_.mesh.position(existing) != x) {
        fail(loc, keyword_,
             "node " + std::to_string(id) + " is defined again with other coordinates (first at " +
                 where(node_where_[static_cast<std::size_t>(existing)]) + ")");
      }
    } else {
      model_.mesh.add_node(id, x);
      node_where_.push_back(loc);
    }
    if (!target_set_.empty()) nsets_[target_set_].ids.push_back(id);
  }

  // Elements are resolved at the end (their nodes may be defined later).
  std::vector<mesh::ElementType> types_;
  std::vector<PendingElement> elements_;
  std::vector<long> element_node_ids_;
  std::unordered_map<long, std::size_t> element_by_id_;
  bool element_open_ = false;
  PendingElement current_;

  int type_index(const std::string& name) {
    const mesh::ElementType type = mesh::element_type(name);
    for (std::size_t i = 0; i < types_.size(); ++i) {
      if (types_[i].name == type.name) return static_cast<int>(i);
    }
    types_.push_back(type);
    return static_cast<int>(types_.size() - 1);
  }

  void element_line(std::string_view line, Location loc) {
    const std::vector<std::string_view> f = non_empty(split_fields(line));
    if (f.empty()) return;
    std::size_t first = 0;
    if (!element_open_) {
      current_ = {};
      current_.id = id_field(f[0], 0, loc, "element id");
      current_.type = element_type_;
      current_.begin = current_.end = element_node_ids_.size();
      current_.where = loc;
      element_open_ = true;
      first = 1;
    }
    for (std::size_t i = first; i < f.size(); ++i) {
      element_node_ids_.push_back(id_field(f[i], i, loc, "node id"));
      ++current_.end;
    }
    const mesh::ElementType& type = types_[static_cast<std::size_t>(current_.type)];
    const auto count = static_cast<int>(current_.end - current_.begin);
    if (type.node_count > 0) {
      if (count > type.node_count) {
        fail(loc, keyword_,
             "element " + std::to_string(current_.id) + " (" + type.name + ") has " + std::to_string(count) +
                 " node ids, expected " + std::to_string(type.node_count));
      }
      if (count == type.node_count) finish_element(false);
    } else if (line.back() != ',') {
      finish_element(false);
    }
  }

  /// Closes the open element. At a keyword (`at_keyword`), an element still short of nodes is an error.
  void finish_element(bool at_keyword) {
    if (!element_open_) return;
    element_open_ = false;
    const mesh::ElementType& type = types_[static_cast<std::size_t>(current_.type)];
    const auto count = static_cast<int>(current_.end - current_.begin);
    if (at_keyword && type.node_count > 0 && count < type.node_count) {
      fail(current_.where, "*ELEMENT",
           "element " + std::to_string(current_.id) + " (" + type.name + ") has " + std::to_string(count) +
               " node ids before the next keyword, expected " + std::to_string(type.node_count));
    }
    if (count == 0)
      fail(current_.where, "*ELEMENT", "element " + std::to_string(current_.id) + " has no nodes");
    const auto [it, inserted] = element_by_id_.emplace(current_.id, elements_.size());
    if (!inserted) {
      const PendingElement& old = elements_[it->second];
      const bool same = old.type == current_.type && old.end - old.begin == current_.end - current_.begin &&
                        std::equal(element_node_ids_.begin() + static_cast<long>(old.begin),
                                   element_node_ids_.begin() + static_cast<long>(old.end),
                                   element_node_ids_.begin() + static_cast<long>(current_.begin));
      if (!same) {
        fail(current_.where, "*ELEMENT",
             "element " + std::to_string(current_.id) + " is defined again differently (first at " +
                 where(old.where) + ")");
      }
      element_node_ids_.resize(current_.begin);
    } else {
      elements_.push_back(current_);
    }
    if (!target_set_.empty()) elsets_[target_set_].ids.push_back(current_.id);
  }

  // ---- Sets: resolved when read (a set named inside a set contributes what it holds at that line) --------
  std::unordered_map<std::string, NamedSet> nsets_, elsets_;

  static std::string define_set(std::unordered_map<std::string, NamedSet>& sets, const std::string& name,
                                Location loc) {
    std::string key = upper(trim(name));
    auto [it, inserted] = sets.try_emplace(key);
    if (inserted) it->second = {std::string(trim(name)), {}, loc};
    return key;
  }

  void set_line(std::unordered_map<std::string, NamedSet>& sets, std::string_view kind, std::string_view line,
                Location loc) {
    const std::vector<std::string_view> f = non_empty(split_fields(line));
    std::vector<long>& ids = sets[target_set_].ids;
    if (generate_) {
      if (f.size() < 2 || f.size() > 3) {
        fail(loc, keyword_,
             "GENERATE needs 'first, last[, increment]', got " + std::to_string(f.size()) + " fields");
      }
      const long first = id_field(f[0], 0, loc, std::string(kind) + " id");
      const long last = id_field(f[1], 1, loc, std::string(kind) + " id");
      const long step = f.size() == 3 ? id_field(f[2], 2, loc, "increment") : 1;
      if (last < first || (last - first) / step >= kMaxGeneratedIds) {
        fail(loc, keyword_,
             "GENERATE range " + std::to_string(first) + ".." + std::to_string(last) + " step " +
                 std::to_string(step) + " is empty or too long");
      }
      for (long id = first; id <= last; id += step) ids.push_back(id);
      return;
    }
    for (std::size_t i = 0; i < f.size(); ++i) {
      long id = 0;
      if (parse_id(f[i], id)) {
        if (id <= 0) id_field(f[i], i, loc, std::string(kind) + " id");
        ids.push_back(id);
        continue;
      }
      const auto it = sets.find(upper(f[i]));
      if (it == sets.end()) {
        fail(
            loc, keyword_,
            "field " + std::to_string(i + 1) + ": unknown " + std::string(kind) + " set " + quote_text(f[i]));
      }
      const std::vector<long> copy = it->second.ids;  // the set may be the one being extended
      ids.insert(ids.end(), copy.begin(), copy.end());
    }
  }

  void nodes_of_element_set(const std::string& elset, Location loc) {
    const auto it = elsets_.find(upper(trim(elset)));
    if (it == elsets_.end()) fail(loc, keyword_, "ELSET=" + quote_text(elset) + ": unknown element set");
    std::vector<long>& ids = nsets_[target_set_].ids;
    for (long e : it->second.ids) {
      const auto el = element_by_id_.find(e);
      if (el == element_by_id_.end()) {
        fail(loc, keyword_,
             "ELSET=" + quote_text(elset) + " holds element " + std::to_string(e) + ", which is not defined");
      }
      const PendingElement& p = elements_[el->second];
      ids.insert(ids.end(), element_node_ids_.begin() + static_cast<long>(p.begin),
                 element_node_ids_.begin() + static_cast<long>(p.end));
    }
  }

  // ---- Surfaces and pairs: names resolved at the end --------------------------------------------------
  std::vector<PendingSurface> surfaces_;
  std::unordered_map<std::string, int> surface_by_key_;  // upper(name) + "\n" + type
  std::vector<PendingPair> pairs_;

  int define_surface(const std::string& raw_name, const std::string& type_text, Location loc) {
    const std::string type_key = keyword_form(type_text);
    mesh::SurfaceType type = mesh::SurfaceType::kUnsupported;
    if (type_key == "ELEMENT") type = mesh::SurfaceType::kElement;
    if (type_key == "NODE") type = mesh::SurfaceType::kNode;
    const std::string name(trim(raw_name));
    const std::string key =
        upper(name) + "\n" + (type == mesh::SurfaceType::kUnsupported ? "OTHER" : type_key);
    const auto [it, inserted] = surface_by_key_.emplace(key, static_cast<int>(surfaces_.size()));
    if (inserted) surfaces_.push_back({name, type, type_text, {}, loc});
    return it->second;
  }

  void surface_line(std::string_view line, Location loc) {
    PendingSurface& s = surfaces_[static_cast<std::size_t>(surface_)];
    if (s.type == mesh::SurfaceType::kUnsupported) return;
    const std::vector<std::string_view> f = non_empty(split_fields(line));
    if (f.empty()) return;
    SurfaceEntry entry{std::string(f[0]), 0, loc};
    if (s.type == mesh::SurfaceType::kElement) {
      if (f.size() < 2) {
        fail(loc, keyword_,
             "surface " + quote_text(s.name) + ": " + quote_text(f[0]) +
                 " needs a face label (S1..S6) in field 2");
      }
      entry.face = parse_face_label(f[1]);
      if (entry.face == 0) {
        fail(loc, keyword_,
             "surface " + quote_text(s.name) + ": field 2: " + quote_text(f[1]) +
                 " is not a face label (S1..S6)");
      }
    }
    s.entries.push_back(std::move(entry));
  }

  void pair_line(std::string_view line, Location loc) {
    const std::vector<std::string_view> f = non_empty(split_fields(line));
    if (f.size() != 2) {
      fail(loc, keyword_,
           "expected 'slave surface, master surface', got " + std::to_string(f.size()) + " fields");
    }
    pairs_.push_back({std::string(f[0]), std::string(f[1]), node_to_surface_, loc});
  }

  // ---- Cyclic symmetry ----------------------------------------------------------------------------------
  std::vector<PendingTie> ties_;
  std::vector<PendingCyclic> cyclic_;

  void tie_line(std::string_view line, Location loc) {
    PendingTie& tie = ties_.back();
    if (!tie.dependent.empty())
      fail(loc, keyword_, "tie " + quote_text(tie.name) + " has a second data line");
    const std::vector<std::string_view> f = non_empty(split_fields(line));
    if (f.size() != 2) {
      fail(loc, keyword_,
           "expected 'dependent surface, independent surface', got " + std::to_string(f.size()) + " fields");
    }
    tie.dependent = std::string(f[0]);
    tie.independent = std::string(f[1]);
  }

  void cyclic_line(std::string_view line, Location loc) {
    PendingCyclic& c = cyclic_.back();
    if (c.has_axis) fail(loc, keyword_, "a second data line (the axis is one line: ax, ay, az, bx, by, bz)");
    const std::vector<std::string_view> f = non_empty(split_fields(line));
    if (f.size() != 6) {
      fail(loc, keyword_,
           "expected the axis 'ax, ay, az, bx, by, bz', got " + std::to_string(f.size()) + " fields");
    }
    for (std::size_t k = 0; k < 6; ++k) {
      if (!parse_coordinate(f[k], c.axis[k])) {
        fail(loc, keyword_,
             "field " + std::to_string(k + 1) + ": " + quote_text(f[k]) + " is not a finite number");
      }
    }
    const mesh::Vec3 a(c.axis[0], c.axis[1], c.axis[2]), b(c.axis[3], c.axis[4], c.axis[5]);
    if (!((b - a).norm() > 0.0)) fail(loc, keyword_, "the axis points a and b coincide");
    c.has_axis = true;
  }

  void resolve_cyclic() {
    std::vector<const PendingTie*> cyclic_ties;
    for (const PendingTie& t : ties_) {
      if (t.dependent.empty())
        fail(t.where, "*TIE", "tie " + quote_text(t.name) + " has no 'dependent, independent' line");
      cyclic_ties.push_back(&t);
    }
    for (const PendingCyclic& c : cyclic_) {
      if (!c.has_axis) fail(c.where, "*CYCLIC SYMMETRY MODEL", "no axis line (ax, ay, az, bx, by, bz)");
      const PendingTie* tie = nullptr;
      if (c.tie.empty()) {
        if (cyclic_ties.size() != 1) {
          fail(c.where, "*CYCLIC SYMMETRY MODEL",
               "TIE= is needed: the deck has " + std::to_string(cyclic_ties.size()) +
                   " *TIE, CYCLIC SYMMETRY cards");
        }
        tie = cyclic_ties.front();
      } else {
        for (const PendingTie* t : cyclic_ties) {
          if (upper(trim(t->name)) == upper(trim(c.tie))) tie = t;
        }
        if (tie == nullptr) {
          fail(c.where, "*CYCLIC SYMMETRY MODEL",
               "TIE=" + quote_text(c.tie) + ": no *TIE, CYCLIC SYMMETRY of that name");
        }
      }
      mesh::CyclicSymmetry s;
      s.sectors = c.sectors;
      s.axis_a = mesh::Vec3(c.axis[0], c.axis[1], c.axis[2]);
      s.axis_b = mesh::Vec3(c.axis[3], c.axis[4], c.axis[5]);
      s.tie = tie->name;
      s.dependent = tie->dependent;
      s.independent = tie->independent;
      s.where = where(c.where);
      model_.cyclic.push_back(std::move(s));
    }
  }

  // ---- Resolution ---------------------------------------------------------------------------------------
  mesh::ContactModel resolve() {
    mesh::SolidMesh& mesh = model_.mesh;
    std::vector<int> nodes;
    for (const PendingElement& e : elements_) {
      nodes.clear();
      for (std::size_t i = e.begin; i < e.end; ++i) {
        const int n = mesh.find_node(element_node_ids_[i]);
        if (n < 0) {
          fail(e.where, "*ELEMENT",
               "element " + std::to_string(e.id) + ": node " + std::to_string(element_node_ids_[i]) +
                   " (node " + std::to_string(i - e.begin + 1) + " of the element) is not defined");
        }
        nodes.push_back(n);
      }
      mesh.add_element(e.id, types_[static_cast<std::size_t>(e.type)], nodes);
    }
    for (const PendingSurface& s : surfaces_) model_.surfaces.push_back(resolve_surface(s));
    resolve_cyclic();
    for (const PendingPair& p : pairs_) {
      mesh::ContactPairDefinition pair;
      pair.slave_name = p.slave;
      pair.master_name = p.master;
      pair.node_to_surface = p.node_to_surface;
      pair.where = where(p.where);
      const int slave_node = find_surface(p.slave, "NODE");
      const int slave_element = find_surface(p.slave, "ELEMENT");
      const int master_element = find_surface(p.master, "ELEMENT");
      const int master_node = find_surface(p.master, "NODE");
      pair.slave = p.node_to_surface && slave_node >= 0 ? slave_node
                   : slave_element >= 0                 ? slave_element
                   : slave_node >= 0                    ? slave_node
                                                        : find_surface(p.slave, "OTHER");
      pair.master = master_element >= 0 ? master_element
                    : master_node >= 0  ? master_node
                                        : find_surface(p.master, "OTHER");
      if (pair.slave < 0)
        fail(p.where, "*CONTACT PAIR", "unknown slave surface " + quote_text(p.slave) + " (field 1)");
      if (pair.master < 0)
        fail(p.where, "*CONTACT PAIR", "unknown master surface " + quote_text(p.master) + " (field 2)");
      model_.pairs.push_back(std::move(pair));
    }
    return std::move(model_);
  }

  [[nodiscard]] int find_surface(const std::string& name, const std::string& type) const {
    const auto it = surface_by_key_.find(upper(trim(name)) + "\n" + type);
    return it == surface_by_key_.end() ? -1 : it->second;
  }

  mesh::SurfaceDefinition resolve_surface(const PendingSurface& s) const {
    mesh::SurfaceDefinition out;
    out.name = s.name;
    out.type = s.type;
    out.type_text = s.type_text;
    out.where = where(s.where);
    const mesh::SolidMesh& mesh = model_.mesh;
    for (const SurfaceEntry& entry : s.entries) {
      const std::string context = "surface " + quote_text(s.name);
      std::vector<long> ids;
      std::string from_set;
      long id = 0;
      if (parse_id(entry.reference, id)) {
        ids.push_back(id);
      } else {
        const auto& sets = s.type == mesh::SurfaceType::kNode ? nsets_ : elsets_;
        const auto it = sets.find(upper(entry.reference));
        if (it == sets.end()) {
          fail(entry.where, "*SURFACE",
               context + ": field 1: unknown " + (s.type == mesh::SurfaceType::kNode ? "node" : "element") +
                   " set " + quote_text(entry.reference));
        }
        ids = it->second.ids;
        from_set = " (in set " + quote_text(it->second.name) + ", " + where(it->second.where) + ")";
      }
      for (long i : ids) {
        if (s.type == mesh::SurfaceType::kNode) {
          const int n = mesh.find_node(i);
          if (n < 0)
            fail(entry.where, "*SURFACE",
                 context + ": node " + std::to_string(i) + from_set + " is not defined");
          out.nodes.push_back(n);
          continue;
        }
        const int e = mesh.find_element(i);
        if (e < 0)
          fail(entry.where, "*SURFACE",
               context + ": element " + std::to_string(i) + from_set + " is not defined");
        const mesh::ElementType& type = mesh.element_type(e);
        const bool shell_label = entry.face < 0;
        if (type.face_count > 0 && (shell_label || entry.face > type.face_count)) {
          fail(entry.where, "*SURFACE",
               context + ": element " + std::to_string(i) + from_set + " is a " + type.name +
                   ", whose faces are S1..S" + std::to_string(type.face_count) + "; the face label says " +
                   (shell_label ? std::string(entry.face == -1 ? "SPOS" : "SNEG")
                                : "S" + std::to_string(entry.face)));
        }
        out.faces.push_back({e, entry.face});
      }
    }
    return out;
  }
};

}  // namespace

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
