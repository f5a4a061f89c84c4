// Text for the files the tools write: a string quoted and escaped (a JSON string and, the same text, a TOML
// basic string: report.json, plan.toml), a number to 17 digits for JSON (null where it is not finite: JSON
// has no NaN or infinity).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace contactnn::io::detail {

/// `"..."` with `"` and `\` escaped and the control characters (and DEL, which TOML requires) as \u00XX.
inline std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c == 0x7f) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      out += b;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

inline std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

}  // namespace contactnn::io::detail
