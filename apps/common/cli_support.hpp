// What every contactnn app does the same way: the error boundary, the --config file, the effective config
// written beside the outputs, option checks, and progress lines. CLI11 appears only under apps/.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "io/atomic_output.hpp"

namespace contactnn::cli {

/// Parses the command line and runs `body` inside the error boundary of every app:
///  - SIGINT, SIGTERM and SIGHUP remove every temporary file and end the run with 128 + signal (130, 143,
///    129); SIGPIPE is ignored, so a closed pipe is an I/O error (io/interrupt_cleanup.hpp). The handler is
///    installed before main, by this library's static initialisation, so that it is in place from the
///    process's first moments;
///  - CLI11 parse errors print CLI11's message and return 2 (0 for --help); an error in the --config file
///    (TOML syntax, unknown section or key, wrong type, bad value) names the file, the line and the key;
///  - contactnn::Error prints "error: <message>" and returns its exit code (docs/tools.md, exit codes);
///  - running out of memory (std::bad_alloc) prints "error: out of memory" and returns 4, like any other
///    resource the system refuses (a full disk);
///  - any other std::exception prints "error: internal: ..." and returns 1 (a bug).
/// Before parsing, OpenMP's default thread count is capped at kMaxThreads (cap_openmp_threads). Nothing below
/// main exits the process.
int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body);

/// Adds `--config FILE`: a TOML 1.0 file (read with toml++) of which this app reads section [section].
/// Like a command line it is strict: a TOML syntax error (a duplicated key included), a section that no app
/// has, a key outside any section, a key the app does not know, a value of the wrong TOML type (a string
/// where a number is expected, a float where an integer is) or out of range is an error naming the file,
/// the line and the key. An integer is accepted where a real is expected, and 0 or 1 where a boolean is (as
/// the effective configs of earlier versions wrote them). Sections of the other apps are skipped. Options
/// added after this call capture their defaults (shown by --help, written by the effective config).
void add_config_option(CLI::App& app, const std::string& section);

/// Parses config file text into `app` as --config would (after add_config_option). Returns the message an
/// app prints for a bad file ("" when it parsed), without the "error: config file 'F'" prefix. For tests
/// and the fuzzer, which have text rather than a file.
[[nodiscard]] std::string parse_config_text(CLI::App& app, const std::string& text);

/// The --config file given ("" if none).
[[nodiscard]] std::filesystem::path config_path(const CLI::App& app);

/// The effective configuration as TOML text: every option's final value (defaults included; options
/// without a value, such as an absent --input, are left out), each written in its TOML type (strings
/// quoted and escaped, numbers as CLI11 read them, booleans as true/false), so that the text given back
/// with --config reads back to the same settings and the same text. Keys in `omit` (e.g. output paths and
/// thread counts, which do not change the result) are left out, so that an output file's provenance is
/// the same for runs that compute the same thing.
[[nodiscard]] std::string effective_config(const CLI::App& app, const std::string& section,
                                           const std::vector<std::string>& omit = {});

/// The settings in which two effective configs (TOML text of one section) differ, keys in `ignore` left
/// out: one line per key, "  key: VALUE_A vs VALUE_B" ("(absent)" for a key one lacks); "" when they agree.
/// Values are compared as values (2.0 equals 2), so configs written by earlier versions, which spelled some
/// numbers differently, still compare equal. Text that is not TOML is compared as text.
[[nodiscard]] std::string config_differences(const std::string& a, const std::string& b,
                                             const std::vector<std::string>& ignore);

/// `<output>.config.toml`: where the effective config of a run writing `output` goes.
[[nodiscard]] std::filesystem::path effective_config_path(const std::filesystem::path& output);

/// Writes the effective configuration to `<output>.config.toml` and leaves it uncommitted, to be committed
/// together with the output (io::commit_together), so the pair always comes from one run. Returns null when
/// `output` is written in place (a device or FIFO such as /dev/null): such an output has no "beside".
[[nodiscard]] std::unique_ptr<io::AtomicOutput> write_effective_config(const CLI::App& app,
                                                                       const std::string& section,
                                                                       const std::filesystem::path& output);

/// Range validators with a readable message ("must be a finite number > 0, got -1"); CLI11 2.1's
/// PositiveNumber prints the largest double in full as the upper end of its range. NaN and infinities are
/// rejected by both (no contactnn setting means anything at infinity).
extern const CLI::Validator kPositive;
extern const CLI::Validator kNonNegative;
/// A finite number in [lo, hi] ("must be a finite number in 0..1e+06, got 1e308").
[[nodiscard]] CLI::Validator real_in(double lo, double hi);

/// An integer in [lo, hi], written in decimal ("must be an integer in 1..400, got 4000000000"). CLI11 2.1
/// alone converts "-1" to 18446744073709551615 for an unsigned option and reads "010" as octal; this
/// validator rejects the first and rewrites the input in canonical decimal before CLI11 converts it, so
/// add it with Option::transform (check() would discard the rewrite).
[[nodiscard]] CLI::Validator integer_in(std::int64_t lo, std::int64_t hi);

/// --threads: 0 (OpenMP's default) .. kMaxThreads (the C interface's CONTACTNN_MAX_THREADS).
inline constexpr std::int64_t kMaxThreads = 1024;

/// Caps OpenMP's default thread count at kMaxThreads, as --threads is capped, with a warning on stderr when
/// it was more: libgomp takes any OMP_NUM_THREADS and then fails inside every parallel region whose team it
/// cannot start (100000 threads), ending the process without the apps' cleanup. Returns the default in force.
int cap_openmp_threads();

/// --seed: 0 .. 2^63 - 1 (a TOML integer is 64-bit signed, and the effective config must read back).
inline constexpr std::int64_t kMaxSeed = INT64_MAX;

/// The warnings after a RAW.csv went through io::map_raw_configurations to `output`: each input column
/// the tool replaced by its own column of the same name (`tools` is its possessive: "gen-configs'"), and an
/// input with a header and no rows.
void warn_about_raw_output(const char* tools, const std::string& input, const std::string& output,
                           const std::vector<std::string>& replaced, std::size_t rows);

/// The keywords of `deck` that change the contact geometry CalculiX uses and that the project does not apply
/// (io::unapplied_geometry_keywords: *CLEARANCE, *CONTACT PAIR with ADJUST=, ...), each named on stderr as a
/// warning from `tool`; returned for the tool's summary.
std::vector<std::string> warn_unapplied_geometry(const char* tool, const std::string& deck);

/// The command line as one shell-quoted string (an argument with a space, a quote, '$' or '\' in single
/// quotes), for the provenance lines of a tool's outputs.
[[nodiscard]] std::string join_command_line(int argc, char** argv);

/// "16,32,48" -> {16, 32, 48}: comma-separated integers in [lo, hi]; InvalidArgument "<expected>, got 'TEXT'"
/// for an empty item, a non-integer or one out of range. An empty text is an empty list.
[[nodiscard]] std::vector<int> integer_list(const std::string& text, int lo, int hi,
                                            const std::string& expected);

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
