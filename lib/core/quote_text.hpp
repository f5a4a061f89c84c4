// User text quoted in a message, short: the one helper every module uses for a field, a name or a method a
// user wrote, so that a 10 MB field never ends up on stderr or in contactnn_last_error().
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace contactnn {

/// The most bytes of user text a message quotes.
inline constexpr std::size_t kQuotedBytes = 40;

/// 'text' when it is at most kQuotedBytes long, otherwise its first kQuotedBytes bytes followed by
/// "...' (N bytes)".
[[nodiscard]] inline std::string quote_text(std::string_view text) {
  if (text.size() <= kQuotedBytes) return "'" + std::string(text) + "'";
  return "'" + std::string(text.substr(0, kQuotedBytes)) + "...' (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace contactnn
