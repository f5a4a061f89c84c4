// Summary statistics of signed errors (estimate - reference) with failures counted, never averaged in:
// the numbers of the paper's Table 1 and of evaluate-net's errors.csv.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/error.hpp"

namespace contactnn::eval {

/// Calls use(i, value) for every row i whose `failed` flag is 0, and returns how many rows are flagged. A row
/// not flagged whose value is not finite is a caller bug: NumericalError "WHO: row I is not marked failed but
/// its WHAT is VALUE" (a NaN is never counted in silently).
template <class Use>
std::int64_t for_each_kept(std::span<const double> values, std::span<const std::uint8_t> failed,
                           const char* who, const char* what, Use&& use) {
  std::int64_t flagged = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (failed[i] != 0) {
      ++flagged;
      continue;
    }
    CONTACTNN_REQUIRE_AS(
        NumericalError, std::isfinite(values[i]),
        who << ": row " << i << " is not marked failed but its " << what << " is " << values[i]);
    use(i, values[i]);
  }
  return flagged;
}

/// Statistics over the rows that are not failures. With n = 0 every statistic is 0 (never NaN).
struct ErrorStatistics {
  std::int64_t rows = 0;      ///< every row offered, failures included
  std::int64_t n = 0;         ///< rows that entered the statistics (rows - failures)
  std::int64_t failures = 0;  ///< rows excluded: the reference or the estimate is not usable
  double mean_abs = 0.0;      ///< mean |e|: the paper's "average error" (Section 6.3.3)
  /// Standard deviation of |e| (population, divide by n). The paper's Table 1 gives a "standard deviation"
  /// below the mean |e| for u, which fits the spread of |e| rather than of e; both are reported.
  double std_abs = 0.0;
  double mean_signed = 0.0;  ///< mean e (bias)
  double std_signed = 0.0;   ///< standard deviation of e (population, divide by n)
  double median_abs = 0.0;   ///< 50th percentile of |e| (percentile() below)
  double p99_abs = 0.0;      ///< 99th percentile of |e|
  double max_abs = 0.0;      ///< largest |e|
};

/// Statistics of `signed_errors` over the rows where `failed[i]` is 0. Both spans have the same length
/// (InvalidArgument otherwise). A row that is not failed but whose error is non-finite is a caller bug:
/// NumericalError naming the row (a NaN is never averaged in silently).
/// Sums are accumulated in long double and the spread about the mean (two passes).
[[nodiscard]] ErrorStatistics summarize_errors(std::span<const double> signed_errors,
                                               std::span<const std::uint8_t> failed);

/// The p-th percentile (p in [0, 100]) of `sorted` (ascending, non-empty) by linear interpolation between
/// order statistics: position h = (n - 1) p / 100, value x[floor h] + (h - floor h)(x[floor h + 1] - x[floor
/// h]) (Hyndman & Fan 1996 definition 7; numpy's default). p = 50 of an even count is the mean of the middle
/// two. InvalidArgument for an empty input or p outside [0, 100].
[[nodiscard]] double percentile(std::span<const double> sorted, double p);

}  // namespace contactnn::eval
