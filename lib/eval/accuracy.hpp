// Accuracy of one search method on one evaluation set, against the reference labels: errors of the local
// coordinates with failures counted (paper Sections 5.3.1 and 6.3.3, Table 1), the gap error relative to the
// segment size, and whether the method puts the contact point inside or outside the segment as the reference
// does.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "eval/error_statistics.hpp"
#include "eval/evaluation_set.hpp"
#include "search/local_search.hpp"

namespace contactnn::eval {

/// A method's answers for every row of a set (caller's order).
struct Estimates {
  std::vector<double> param;             ///< rows x 2
  std::vector<double> gap;               ///< rows
  std::vector<Status> status;            ///< rows
  std::vector<std::int32_t> iterations;  ///< rows
  [[nodiscard]] std::size_t size() const { return status.size(); }
};

/// Runs `search` on every row of `set` with `threads` OpenMP threads (0: OpenMP's default). The results do
/// not depend on the thread count (lib/search's guarantee). `start` (rows x 2, or null): what the results'
/// param holds when the run begins, the starts of start+newton:K.
[[nodiscard]] Estimates run_on_set(const search::LocalSearch& search, const EvaluationSet& set, int threads,
                                   const std::vector<double>* start = nullptr);

/// The starts of start+newton:K on `set` as evaluate-net --start_offset makes them: each row's reference
/// point moved `offset` (parameter units) in a direction drawn from `seed` and the row (the same for any
/// method); the domain centre where the reference has no point.
[[nodiscard]] std::vector<double> starts_near_reference(const EvaluationSet& set, double offset,
                                                        std::uint64_t seed);

/// Errors of one method against a set's labels.
struct MethodErrors {
  std::string method;                    ///< e.g. "newton:5", "network+newton:1[gregory-48]"
  std::array<ErrorStatistics, 2> stats;  ///< per local coordinate
  std::int64_t rows = 0;
  std::int64_t failures_reference = 0;  ///< the label's status is not ok or outside: no reference point
  std::int64_t failures_method = 0;     ///< reference usable, estimate not (see compare_with_labels)
  std::int64_t out_of_domain = 0;       ///< network estimates flagged out_of_domain (in the statistics)
  std::int64_t outside_domain = 0;      ///< estimates in the statistics beyond the parameter domain
  std::array<std::int64_t, kStatusCount> status_counts{};  ///< the estimates' statuses, every row
  /// |g - g_ref| / size (the segment's longest node distance), over the rows in the statistics that have both
  /// gaps: signed values' statistics, the mean_abs and max_abs being what reports show.
  ErrorStatistics gap_relative;
  /// Inside/outside: rows in the statistics whose estimate lies inside the parameter domain (1e-10 margin)
  /// exactly when the reference's does (status ok versus outside).
  std::int64_t inside_agree = 0;
  std::int64_t inside_compared = 0;
  /// Per-row signed errors and failure flags (kept only when asked: the histograms' network).
  std::array<std::vector<double>, 2> errors;
  std::vector<std::uint8_t> failed;
  /// Newton steps of the rows whose estimate is ok or outside (for iteration histograms), -1 otherwise.
  std::vector<std::int32_t> converged_iterations;
};

/// Compares `estimates` with `set`'s labels. A row is a failure, counted and never averaged in, when its
/// label has no point (status neither ok nor outside), or the estimate's status is not ok, outside or
/// out_of_domain (a network's estimate outside its training domain is still its answer, and is counted in
/// out_of_domain), or the estimate is non-finite or further than `failure_box_margin` domain widths outside
/// the parameter domain (an FE code would reject it rather than use it). `keep_rows`: keep the per-row
/// errors.
[[nodiscard]] MethodErrors compare_with_labels(std::string method, const Estimates& estimates,
                                               const EvaluationSet& set, double failure_box_margin,
                                               bool keep_rows);

/// True when `p` (a local coordinate pair) lies in the parameter domain enlarged by `margin` (parameter
/// units).
[[nodiscard]] bool inside_domain(const double* p, SurfaceKind kind, double margin);

/// Counts of an integer column: counts[k] is the number of values k for 0 <= k < size - 1; the last entry
/// counts values >= size - 1; negative values are skipped.
[[nodiscard]] std::vector<std::int64_t> count_values(const std::vector<std::int32_t>& values, int size);

}  // namespace contactnn::eval
