#include "eval/error_statistics.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace contactnn::eval {

double percentile(std::span<const double> sorted, double p) {
  CONTACTNN_REQUIRE(!sorted.empty(), "percentile of an empty set");
  CONTACTNN_REQUIRE(p >= 0.0 && p <= 100.0, "percentile p = " << p << " is outside [0, 100]");
  const double h = static_cast<double>(sorted.size() - 1) * p / 100.0;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted[sorted.size() - 1];
  const double fraction = h - static_cast<double>(lo);
  return sorted[lo] + fraction * (sorted[lo + 1] - sorted[lo]);
}

ErrorStatistics summarize_errors(std::span<const double> signed_errors,
                                 std::span<const std::uint8_t> failed) {
  CONTACTNN_REQUIRE(
      signed_errors.size() == failed.size(),
      "summarize_errors: " << signed_errors.size() << " errors but " << failed.size() << " failure flags");
  ErrorStatistics s;
  s.rows = static_cast<std::int64_t>(signed_errors.size());
  std::vector<double> abs_errors;
  abs_errors.reserve(signed_errors.size());
  long double sum = 0.0L, sum_abs = 0.0L;
  s.failures = for_each_kept(signed_errors, failed, "summarize_errors", "error", [&](std::size_t, double e) {
    sum += e;
    sum_abs += std::abs(e);
    abs_errors.push_back(std::abs(e));
  });
  s.n = static_cast<std::int64_t>(abs_errors.size());
  if (s.n == 0) return s;
  const auto n = static_cast<long double>(s.n);
  s.mean_signed = static_cast<double>(sum / n);
  s.mean_abs = static_cast<double>(sum_abs / n);
  // Second pass about the mean: no cancellation from E[x^2] - E[x]^2 when the spread is far below the mean.
  long double sq = 0.0L, sq_abs = 0.0L;
  for (std::size_t i = 0; i < signed_errors.size(); ++i) {
    if (failed[i] != 0) continue;
    const long double d = static_cast<long double>(signed_errors[i]) - s.mean_signed;
    const long double d_abs = static_cast<long double>(std::abs(signed_errors[i])) - s.mean_abs;
    sq += d * d;
    sq_abs += d_abs * d_abs;
  }
  s.std_signed = static_cast<double>(std::sqrt(sq / n));
  s.std_abs = static_cast<double>(std::sqrt(sq_abs / n));
  std::sort(abs_errors.begin(), abs_errors.end());
  s.median_abs = percentile(abs_errors, 50.0);
  s.p99_abs = percentile(abs_errors, 99.0);
  s.max_abs = abs_errors.back();
  return s;
}

}  // namespace contactnn::eval
