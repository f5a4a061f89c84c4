// The text files the project reads (CSV, .inp decks) must be UTF-8 or ASCII; a byte-order mark of another
// encoding names what the file is instead.
#pragma once

#include <string_view>

namespace contactnn::io {

/// The encoding whose byte-order mark `head` (a file's first bytes, at least 4 where the file has them)
/// starts with: "UTF-32 (little-endian)", "UTF-32 (big-endian)", "UTF-16 (little-endian)", "UTF-16
/// (big-endian)"; empty for UTF-8's mark and for none.
inline std::string_view foreign_byte_order_mark(std::string_view head) {
  const auto starts = [&](std::string_view mark) { return head.substr(0, mark.size()) == mark; };
  if (starts(std::string_view("\xFF\xFE\x00\x00", 4))) return "UTF-32 (little-endian)";
  if (starts(std::string_view("\x00\x00\xFE\xFF", 4))) return "UTF-32 (big-endian)";
  if (starts("\xFF\xFE")) return "UTF-16 (little-endian)";
  if (starts("\xFE\xFF")) return "UTF-16 (big-endian)";
  return {};
}

}  // namespace contactnn::io
