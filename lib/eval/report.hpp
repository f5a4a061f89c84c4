// Writing a study out: errors.csv, speed.csv, hist_<coordinate>.csv/.svg and report.md (paper Table 1,
// Figs 4, 10 and 11, and the statements of Sections 5.3 and 6.3.3 beside the measured numbers).
#pragma once

#include <filesystem>
#include <string>

#include "eval/study.hpp"

namespace contactnn::eval {

/// Where and how a study ran: what report.md states about provenance.
struct RunInfo {
  std::string command_line;
  std::string dataset_path;
  std::string network_path;
  std::string network_summary;  ///< e.g. "8-8-2, float, U0 = 1"
  std::string cpu_model;        ///< cpu_model()
  int hardware_threads = 0;
  int accuracy_threads = 0;     ///< OpenMP threads of the accuracy part (timing is single-thread)
  std::string compiler;
  std::string build_type;
  std::string cxx_flags;        ///< CMAKE_CXX_FLAGS and the build type's flags, plus contactnn::flags
  std::string effective_config; ///< the [evaluate-net] TOML the run used
};

/// "model name" of the first processor in /proc/cpuinfo ("unknown" if not readable).
[[nodiscard]] std::string cpu_model();

/// errors.csv: header method,coordinate,rows,n,failures,failures_reference,failures_method,mean_abs,std_abs,
/// mean_signed,std_signed,median_abs,p99_abs,max_abs,outside_domain; one row per method and coordinate,
/// failures = failures_reference + failures_method = rows - n.
[[nodiscard]] std::string errors_csv(const StudyResult& result);

/// speed.csv: header method,queries,repetitions,ns_per_query_median,ns_per_query_min,ns_per_query_max,
/// ratio_to_newton_5,ratio_to_newton_converged (ratios of medians; empty where the denominator is missing).
[[nodiscard]] std::string speed_csv(const StudyResult& result);

/// The network's cost in Newton iterations, three ways (report.md says which is which).
struct NetworkCostInIterations {
  bool available = false;
  double equivalent_iterations = 0.0;  ///< k with fit(k) = t(network): (t_net - intercept) / slope
  double per_iteration_units = 0.0;    ///< t_net / slope (the network's time in units of one more iteration)
  double newton10_units = 0.0;         ///< t_net / (t(newton_10) / 10)
  double equivalent_iterations_min = 0.0;  ///< as equivalent_iterations, from minimum times and newton_fit_min
};
[[nodiscard]] NetworkCostInIterations network_cost_in_iterations(const StudyResult& result);

/// report.md text.
[[nodiscard]] std::string report_markdown(const StudyResult& result, const RunInfo& info, const StudyOptions& options);

/// Writes every file of the report into `directory` (created if missing), each atomically: errors.csv,
/// speed.csv (when timed; an older speed.csv is removed otherwise), hist_<c>.csv and hist_<c>.svg for each
/// coordinate name c, report.md.
void write_report(const std::filesystem::path& directory, const StudyResult& result, const RunInfo& info,
                  const StudyOptions& options);

}  // namespace contactnn::eval
