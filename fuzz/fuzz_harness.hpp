// The properties the fuzz targets check, one function per target, shared by the libFuzzer entry points
// (fuzz/fuzz_*.cpp, built by scripts/fuzz with clang and sanitizers) and the GoogleTest that replays the
// kept inputs in CI (tests/extremes/test_fuzz_regressions.cpp). Each returns "" when every property holds,
// otherwise what went wrong; a crash, a sanitizer report or a hang is a finding by itself.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <sstream>
#include <string>
#include <string_view>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "dataset/labeller.hpp"
#include "io/csv.hpp"
#include "io/raw_configurations.hpp"

namespace contactnn::fuzz {

/// Rows labelled per input: enough to reach every code path, few enough for ~1000 inputs/s.
inline constexpr std::size_t kLabelledRows = 8;

inline bool same_double(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0;
}

/// SPEC 2 on any label: finite values, bounded iterations, no gap unless converged; the value written to
/// a CSV reads back exactly.
inline std::string check_label(const dataset::Label& l) {
  const bool converged = l.status == Status::kOk || l.status == Status::kOutside;
  if (!std::isfinite(l.param[0]) || !std::isfinite(l.param[1])) return "non-finite coordinates in a label";
  if (!std::isfinite(l.gap)) return "non-finite gap in a label";
  if (l.iterations < 0 || l.iterations > projection::ProjectionOptions{}.max_iterations) {
    return "iterations out of range: " + std::to_string(l.iterations);
  }
  if (!converged && l.gap != 0.0) return "a gap on a label that did not converge";
  for (const double v : {l.param[0], l.param[1], l.gap}) {
    double back = 0.0;
    if (!io::parse_double(io::format_double(v), back) || !same_double(back, v)) {
      return "format_double(" + io::format_double(v) + ") does not read back";
    }
  }
  return "";
}

/// Target 1: CSV text. parse_csv either rejects it with a FormatError naming the file, or gives a table
/// that is rectangular, writes back with append_csv_row and reads back the same; fields parse as numbers
/// consistently; RAW.csv of either surface reads or is rejected, and its first rows label sanely.
inline std::string fuzz_csv(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string name = "fuzz.csv";
  io::CsvTable table;
  try {
    table = io::parse_csv(text, name);
  } catch (const FormatError& e) {
    if (std::string(e.what()).find(name) == std::string::npos)
      return std::string("message without the file: ") + e.what();
    return "";
  } catch (const std::exception& e) {
    return std::string("parse_csv threw a non-contactnn exception: ") + e.what();
  }
  if (table.header.empty() || table.rows.empty()) return "an empty table was accepted";
  std::size_t previous_line = 1;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    if (table.rows[r].size() != table.header.size()) return "a ragged row was accepted";
    if (table.line_numbers[r] <= previous_line) return "line numbers not increasing";
    previous_line = table.line_numbers[r];
  }
  // Write back and read again: the same header and fields (a one-column row with an empty field would be a
  // blank line, which the reader skips by design).
  if (table.header.size() >= 2) {
    std::string out;
    io::append_csv_row(out, table.header);
    for (const auto& row : table.rows) io::append_csv_row(out, row);
    try {
      const io::CsvTable back = io::parse_csv(out, name);
      if (back.header != table.header) return "header does not survive a write and read";
      if (back.rows != table.rows) return "rows do not survive a write and read";
    } catch (const std::exception& e) {
      return std::string("a table written by append_csv_row does not read back: ") + e.what();
    }
  }
  // Numbers: parse_double and CsvTable::number agree.
  for (std::size_t r = 0; r < table.rows.size() && r < 64; ++r) {
    for (std::size_t c = 0; c < table.header.size(); ++c) {
      double direct = 0.0;
      const bool ok = io::parse_double(table.rows[r][c], direct);
      try {
        const double via_table = table.number(r, c);
        if (!ok || !same_double(direct, via_table)) return "number() and parse_double disagree";
      } catch (const FormatError& e) {
        if (ok) return "number() threw for a field parse_double accepts";
        if (std::string(e.what()).find(name) == std::string::npos) return "number() message without the file";
      }
    }
  }
  // RAW.csv of each surface, and the labels of its first rows.
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    try {
      const io::RawConfigurations raw = io::parse_raw_configurations(text, name, kind);
      if (raw.configs.size() != raw.table.rows.size()) return "configurations and rows differ in number";
      for (std::size_t i = 0; i < raw.configs.size() && i < kLabelledRows; ++i) {
        const std::string problem = check_label(dataset::label_configuration(raw.configs[i], kind));
        if (!problem.empty())
          return std::string(to_string(kind)) + " row " + std::to_string(i) + ": " + problem;
      }
    } catch (const FormatError& e) {
      if (std::string(e.what()).find(name) == std::string::npos)
        return std::string("message without the file: ") + e.what();
    } catch (const std::exception& e) {
      return std::string("RAW.csv reading or labelling threw a non-format exception: ") + e.what();
    }
  }
  return "";
}

/// The options of a representative app (those of gen-configs and train-net, every kind of value and check).
struct ConfigApp {
  CLI::App app{"fuzz"};
  std::string surface = "bilinear", input, output, hidden = "8";
  int threads = 0, d_xy_points = 20, checkpoint_every = 0;
  double xy_limit = 2.0, min_angle_degrees = 0.0, tol_param = 1e-13;
  bool convex = true, quiet = false;
  std::uint64_t seed = 1;

  ConfigApp() {
    cli::add_config_option(app, "gen-configs");
    app.add_option("--surface", surface)->check(CLI::IsMember({"bilinear", "gregory"}));
    app.add_option("--input", input)->check(CLI::ExistingFile);
    app.add_option("--output", output);
    app.add_option("--threads", threads)->check(CLI::NonNegativeNumber);
    app.add_flag("--quiet", quiet);
    app.add_option("--seed", seed);
    app.add_option("--d_xy_points", d_xy_points)->check(CLI::Range(1, 400));
    app.add_option("--xy_limit", xy_limit)->check(CLI::PositiveNumber);
    app.add_option("--min_angle_degrees", min_angle_degrees)->check(CLI::Range(0.0, 180.0));
    app.add_option("--tol_param", tol_param)->check(CLI::PositiveNumber);
    app.add_option("--convex", convex);
    app.add_option("--hidden", hidden);
    app.add_option("--checkpoint-every", checkpoint_every)->check(CLI::NonNegativeNumber);
  }
};

/// Target 2: config file text. It parses, or gives a message (never another exception); a config that parsed
/// has an effective config (cli::effective_config) that parses again to the same effective config.
inline std::string fuzz_config(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string first;
  try {
    ConfigApp a;
    const std::string message = cli::parse_config_text(a.app, text);
    if (!message.empty()) return "";
    first = cli::effective_config(a.app, "gen-configs");
  } catch (const std::exception& e) {
    return std::string("config parsing threw outside CLI::ParseError: ") + e.what();
  }
  try {
    ConfigApp b;
    const std::string message = cli::parse_config_text(b.app, first);
    if (!message.empty()) return "the effective config does not parse again: " + message + "\n" + first;
    const std::string second = cli::effective_config(b.app, "gen-configs");
    if (second != first) return "the effective config changes when read back:\n" + first + "---\n" + second;
  } catch (const std::exception& e) {
    return std::string("reading the effective config back threw: ") + e.what();
  }
  return "";
}

/// A libFuzzer target's verdict on one input: a `problem` ("" for none) is printed, named by the `target`,
/// and aborts the process (libFuzzer's finding); otherwise 0, what LLVMFuzzerTestOneInput returns.
inline int verdict(const char* target, const std::string& problem) {
  if (!problem.empty()) {
    std::fprintf(stderr, "%s: %s\n", target, problem.c_str());
    std::abort();
  }
  return 0;
}

}  // namespace contactnn::fuzz
