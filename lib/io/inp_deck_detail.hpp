// The .inp deck reader's parts (inp_deck.cpp: the files, their lines and the keyword lines;
// inp_deck_mesh.cpp: nodes, elements and sets; inp_deck_contact.cpp: surfaces, contact pairs, cyclic
// symmetry and the resolution of names). Private to lib/io: not installed, not included outside it.
#pragma once

#include <unistd.h>

#include <array>
#include <cerrno>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "io/inp_deck.hpp"

namespace contactnn::io::detail {

namespace fs = std::filesystem;

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

std::string_view trim(std::string_view s);
std::string upper(std::string_view s);
/// Upper case without blanks: how keywords and parameter names compare ("Contact Pair" = "CONTACTPAIR").
std::string keyword_form(std::string_view s);
/// Comma-separated fields, trimmed; commas inside double quotes do not split. Empty fields are kept.
std::vector<std::string_view> split_fields(std::string_view line);
std::vector<std::string_view> non_empty(const std::vector<std::string_view>& fields);
std::string unquote(std::string_view s);
/// A whole field as a positive integer id.
bool parse_id(std::string_view field, long& id);
/// A whole field as a finite number; a Fortran D exponent (1.5D+03) is accepted.
bool parse_coordinate(std::string_view field, double& value);
/// S1..S99 -> 1..99; SPOS -> -1, SNEG -> -2 (shell faces: counted, never segments); 0 if not a face label.
int parse_face_label(std::string_view field);

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
  mesh::ContactModel read(InputFile input, std::string text, const fs::path& name);

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
  static fs::path canonical_or_empty(const fs::path& p);
  void push_source(InputFile input, std::string text, const fs::path& name, fs::path canonical);
  void push_file(const std::string& input, Location loc, std::string_view keyword_name);
  bool refill(Source& s) const;
  bool read_line(Source& s) const;
  void check_text(std::string_view text, Location loc) const;
  bool next_line(std::string_view& line, Location& loc);
  [[nodiscard]] std::string where(Location loc) const;
  [[noreturn]] void fail(Location loc, std::string_view keyword_name, const std::string& message) const;

  // ---- Keyword lines ------------------------------------------------------------------------------------
  Block block_ = Block::kSkip;
  std::string keyword_;     // "*NODE", for messages
  std::string target_set_;  // NSET= / ELSET= of *NODE, *ELEMENT, *NSET, *ELSET (keyword_form), or ""
  bool generate_ = false;
  int element_type_ = -1;
  int surface_ = -1;
  bool node_to_surface_ = true;

  void keyword(std::string_view line, Location loc);

  // ---- Data lines (inp_deck_mesh.cpp, inp_deck_contact.cpp) ---------------------------------------------
  void data(std::string_view line, Location loc);
  long id_field(std::string_view field, std::size_t index, Location loc, std::string_view what) const;

  // Nodes go straight into the mesh; where each was defined is kept for the duplicate message.
  mesh::ContactModel model_;
  std::vector<Location> node_where_;
  void node_line(std::string_view line, Location loc);

  // Elements are resolved at the end (their nodes may be defined later).
  std::vector<mesh::ElementType> types_;
  std::vector<PendingElement> elements_;
  std::vector<long> element_node_ids_;
  std::unordered_map<long, std::size_t> element_by_id_;
  bool element_open_ = false;
  PendingElement current_;
  int type_index(const std::string& name);
  void element_line(std::string_view line, Location loc);
  void finish_element(bool at_keyword);

  // ---- Sets: resolved when read (a set named inside a set contributes what it holds at that line) --------
  std::unordered_map<std::string, NamedSet> nsets_, elsets_;
  static std::string define_set(std::unordered_map<std::string, NamedSet>& sets, const std::string& name,
                                Location loc);
  void set_line(std::unordered_map<std::string, NamedSet>& sets, std::string_view kind, std::string_view line,
                Location loc);
  void nodes_of_element_set(const std::string& elset, Location loc);

  // ---- Surfaces and pairs: names resolved at the end --------------------------------------------------
  std::vector<PendingSurface> surfaces_;
  std::unordered_map<std::string, int> surface_by_key_;  // upper(name) + "\n" + type
  std::vector<PendingPair> pairs_;
  int define_surface(const std::string& raw_name, const std::string& type_text, Location loc);
  void surface_line(std::string_view line, Location loc);
  void pair_line(std::string_view line, Location loc);

  // ---- Cyclic symmetry ----------------------------------------------------------------------------------
  std::vector<PendingTie> ties_;
  std::vector<PendingCyclic> cyclic_;
  void tie_line(std::string_view line, Location loc);
  void cyclic_line(std::string_view line, Location loc);
  void resolve_cyclic();

  // ---- Resolution ---------------------------------------------------------------------------------------
  mesh::ContactModel resolve();
  [[nodiscard]] int find_surface(const std::string& name, const std::string& type) const;
  mesh::SurfaceDefinition resolve_surface(const PendingSurface& s) const;
};

}  // namespace contactnn::io::detail
