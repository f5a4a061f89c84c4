// Writing a method comparison out: errors.csv, speed.csv, hist_<coordinate>.csv/.svg and report.md (per set:
// every method's accuracy and speed side by side, the fastest method at each accuracy level; the paper's
// Table 1, Figs 4, 10 and 11 and the statements of Sections 5.3 and 6.3.3 beside the measured numbers).
#pragma once

#include <filesystem>
#include <string>

#include "eval/method_comparison.hpp"
#include "eval/ranking.hpp"

namespace contactnn::eval {

/// Where and how a comparison ran: what report.md states about provenance.
struct RunInfo {
  std::string command_line;
  std::string cpu_model;  ///< cpu_model()
  int hardware_threads = 0;
  int accuracy_threads = 0;  ///< OpenMP threads of the accuracy part
  std::string compiler;
  std::string build_type;
  std::string cxx_flags;         ///< CMAKE_CXX_FLAGS and the build type's flags, plus contactnn::flags
  std::string effective_config;  ///< the [evaluate-net] TOML the run used
};

/// "model name" of the first processor in /proc/cpuinfo ("unknown" if not readable).
[[nodiscard]] std::string cpu_model();

/// errors.csv: header set,method,coordinate,rows,n,failures,failures_reference,failures_method,out_of_domain,
/// mean_abs,std_abs,mean_signed,std_signed,median_abs,p99_abs,max_abs,outside_domain,gap_rel_mean_abs,
/// gap_rel_max_abs,inside_agreement; one row per set, method and coordinate. failures = failures_reference +
/// failures_method = rows - n; gap_rel: |gap - reference gap| / segment size; inside_agreement: the fraction
/// of rows in the statistics that the method puts inside the segment (its estimate inside and its status not
/// outside) exactly when the reference does.
[[nodiscard]] std::string errors_csv(const ComparisonResult& result);

/// speed.csv: header set,method,queries,repetitions,one_ns,one_min_ns,batched_ns,batched_min_ns,threads,
/// threads_ns,threads_min_ns,batched_per_newton_5; ns per query, medians and minimums over the repetitions;
/// the ratio is of the 1-thread batched medians (empty without newton:5).
[[nodiscard]] std::string speed_csv(const ComparisonResult& result);

/// report.md text.
[[nodiscard]] std::string comparison_markdown(const ComparisonResult& result, const RunInfo& info,
                                              const ComparisonOptions& options);

/// Writes every file of the report into `directory` (created if missing), each atomically: errors.csv,
/// speed.csv (when timed), hist_<c>.csv and hist_<c>.svg for each coordinate name c (with a network),
/// report.md.
void write_report(const std::filesystem::path& directory, const ComparisonResult& result, const RunInfo& info,
                  const ComparisonOptions& options);

}  // namespace contactnn::eval
