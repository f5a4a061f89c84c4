// User text quoted in a message, short: the one helper every module uses for a field, a name or a method a
// user wrote, so that a 10 MB field never ends up on stderr or in contactnn_last_error().
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace contactnn {

/// The most bytes of user text a message quotes.
inline constexpr std::size_t kQuotedBytes = 40;

/// `text` as printable text: valid UTF-8 as it is, every other byte (a control character, DEL, a byte of no
/// valid UTF-8 sequence: a binary or Latin-1 file's) as \xHH, so that a message never writes raw bytes to
/// a terminal or a log.
[[nodiscard]] inline std::string escape_text(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  const auto escaped = [&](unsigned char c) {
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
  };
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    // A UTF-8 sequence: its length from the lead byte, continuation bytes 10xxxxxx, no overlong form, no
    // surrogate, nothing above U+10FFFF.
    const std::size_t length = c >= 0xc2 && c <= 0xdf   ? 2
                               : c >= 0xe0 && c <= 0xef ? 3
                               : c >= 0xf0 && c <= 0xf4 ? 4
                                                        : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k) {
      valid = (static_cast<unsigned char>(text[i + k]) & 0xc0) == 0x80;
    }
    if (valid && length >= 3) {
      const auto c1 = static_cast<unsigned char>(text[i + 1]);
      valid = !(c == 0xe0 && c1 < 0xa0) && !(c == 0xed && c1 >= 0xa0) && !(c == 0xf0 && c1 < 0x90) &&
              !(c == 0xf4 && c1 >= 0x90);
    }
    if (valid) {
      out.append(text.substr(i, length));
      i += length;
    } else {
      escaped(c);
      ++i;
    }
  }
  return out;
}

/// 'text' (escaped as escape_text does) when it is at most kQuotedBytes long, otherwise its first
/// kQuotedBytes bytes followed by "...' (N bytes)".
[[nodiscard]] inline std::string quote_text(std::string_view text) {
  if (text.size() <= kQuotedBytes) return "'" + escape_text(text) + "'";
  return "'" + escape_text(text.substr(0, kQuotedBytes)) + "...' (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace contactnn
