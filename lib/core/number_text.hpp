// A number as text by a printf format (the reports' table cells): one definition for every report.
#pragma once

#include <cstdio>
#include <string>

namespace contactnn {

/// `x` written by the printf `format` (one double conversion, at most 63 characters).
[[nodiscard]] inline std::string fmt(const char* format, double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}

}  // namespace contactnn
