// Fixed-width histograms of signed errors (paper Figs 4 and 10), with outliers counted, not dropped.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace contactnn::eval {

/// `bins` equal bins over [lo, hi]. Bin k holds lo + k w <= x < lo + (k + 1) w (w = (hi - lo) / bins):
/// a value exactly on an inner edge goes to the bin on its right (the upper bin). The last bin is closed:
/// x == hi goes to bin bins-1. x < lo counts in `underflow`, x > hi in `overflow`. Edges are computed as
/// lo + k w for every k (never accumulated), and each value is compared with the edges themselves, so the
/// side of an edge value never depends on the rounding of (x - lo) / w.
struct Histogram {
  double lo = 0.0;
  double hi = 0.0;
  std::vector<std::int64_t> counts;  ///< one per bin
  std::int64_t underflow = 0;        ///< x < lo
  std::int64_t overflow = 0;         ///< x > hi
  std::int64_t excluded = 0;         ///< rows flagged as failures (not histogrammed)

  [[nodiscard]] int bins() const { return static_cast<int>(counts.size()); }
  /// Edge k, 0 <= k <= bins(): lo + k (hi - lo) / bins; edge(bins()) is exactly hi.
  [[nodiscard]] double edge(int k) const;
  /// Bin of a finite x in [lo, hi] (the rule above); -1 below lo, bins() above hi.
  [[nodiscard]] int bin_of(double x) const;
  /// Every counted value: sum(counts) + underflow + overflow.
  [[nodiscard]] std::int64_t total() const;
};

/// Histogram of `values` over the rows where `failed[i]` is 0 (failed rows are counted in `excluded`).
/// InvalidArgument unless lo < hi (both finite), bins >= 1 and the spans have equal length; NumericalError
/// for a non-finite value in a row that is not failed.
[[nodiscard]] Histogram make_histogram(std::span<const double> values, std::span<const std::uint8_t> failed,
                                       double lo, double hi, int bins);

/// The smallest "nice" number (1, 2 or 5 times a power of ten) that is >= x, for x > 0; 1 for x <= 0 or
/// non-finite x. Used for automatic symmetric ranges [-r, r] and axis ticks.
[[nodiscard]] double nice_ceil(double x);

/// CSV text: header `bin,lower_edge,upper_edge,count`, one row per bin, then the rows `underflow` (lower edge
/// -inf, upper edge lo), `overflow` (lo: hi, upper: inf) and `excluded` (edges empty). Numbers round-trip.
[[nodiscard]] std::string histogram_csv(const Histogram& histogram);

}  // namespace contactnn::eval
