// What every contactnn app does the same way: the error boundary, the --config file, the effective config
// written beside the outputs, and progress lines. CLI11 appears only under apps/.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace contactnn::cli {

/// Parses the command line and runs `body` inside the error boundary of every app:
///  - CLI11 parse errors print CLI11's message and return 2 (0 for --help); an error in the --config file
///    (unknown key, bad value) names the file, the line and the key;
///  - contactnn::Error prints "error: <message>" and returns its exit code (README "Exit codes");
///  - any other std::exception prints "error: internal: ..." and returns 1.
/// Nothing below main exits the process.
int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body);

/// Adds `--config FILE` reading section [section] of a TOML file; keys in that section that are not
/// options of the app are an error (CLI11 would ignore them by default). Sections of other apps are skipped;
/// a section no app has, a malformed section header, or a key before any section is an error. Options added
/// after this call capture their defaults (shown by --help, written by write_effective_config).
void add_config_option(CLI::App& app, const std::string& section);

/// Parses config file text into `app` as --config would (after add_config_option): the section filter,
/// unknown keys, value checks. Returns the message an app prints for a bad file ("" when it parsed), without
/// the "error: config file 'F'" prefix. For tests and the fuzzer, which have text rather than a file.
[[nodiscard]] std::string parse_config_text(CLI::App& app, const std::string& text);

/// Writes the effective configuration (every option's final value, defaults included; options without a
/// value, such as an absent --input, are left out) as TOML under [section] to `<output>.config.toml`,
/// atomically. The file can be given back with --config.
void write_effective_config(const CLI::App& app, const std::string& section, const std::filesystem::path& output);

/// The effective configuration as TOML text (for provenance attributes in output files).
/// Keys in `omit` (e.g. output paths and thread counts, which do not change the result) are left out, so
/// that an output file's provenance is the same for runs that compute the same thing.
[[nodiscard]] std::string effective_config(const CLI::App& app, const std::string& section,
                                           const std::vector<std::string>& omit = {});

/// Range validators with a readable message ("must be > 0, got -1"); CLI11 2.1's PositiveNumber prints
/// the largest double in full as the upper end of its range. NaN is rejected by both.
extern const CLI::Validator kPositive;
extern const CLI::Validator kNonNegative;

/// Adds the exit-code table to the app's --help footer.
void add_exit_code_footer(CLI::App& app);

/// A one-line progress display on stderr ("\r"-updated), rate and ETA included; silent when `quiet`.
class Progress {
 public:
  Progress(std::string label, bool quiet);
  void update(std::int64_t done, std::int64_t total);
  void finish();

 private:
  std::string label_;
  bool quiet_;
  bool printed_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace contactnn::cli
