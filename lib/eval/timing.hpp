// Honest single-thread timing of the study's methods (paper Sections 5.3.2 and 6.3.3, Fig 11).
//
// How a number is made: every method runs over the same batch of raw world configurations, in a plain loop
// on the calling thread (never inside an OpenMP region), and includes its own preprocessing (the network:
// the Section 4 normalisation; Newton: building its patch from the world nodes). Each result is folded into
// a checksum that is written to a volatile sink, so no work can be optimised away. After `warmup_passes`
// untimed passes, the methods are timed round-robin (method 1, 2, ..., then the next repetition), so a
// clock or load drift spreads over all methods instead of biasing the last one. A repetition is one whole
// batch timed with std::chrono::steady_clock; ns/query = elapsed / batch size; the median, min and max over
// the repetitions are reported. Everything is compiled with the same flags (contactnn::flags).
// The numbers are throughput of a loop over independent queries, as a contact search runs them: the
// out-of-order core may overlap consecutive queries, for every method alike.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace contactnn::eval {

struct TimingOptions {
  int repetitions = 7;    ///< timed passes per method (median, min, max reported)
  int warmup_passes = 1;  ///< untimed passes per method first (caches, branch predictors, page faults)
};

/// One pass over a batch; returns a checksum of the results it computed.
using BatchRunner = std::function<double()>;

struct TimedMethod {
  std::string name;
  std::string description;
  std::int64_t queries = 0;  ///< batch size of one pass
  BatchRunner run;
};

struct Timing {
  std::string name;
  std::string description;
  std::int64_t queries = 0;
  int repetitions = 0;
  double median_ns = 0.0;  ///< nanoseconds per query, median over repetitions
  double min_ns = 0.0;
  double max_ns = 0.0;
  std::vector<double> samples_ns;  ///< per repetition, in run order
};

/// Times every method as described in the header comment. InvalidArgument for repetitions < 1,
/// warmup_passes < 0 or a method with queries < 1.
[[nodiscard]] std::vector<Timing> time_methods(const std::vector<TimedMethod>& methods,
                                               const TimingOptions& options);

/// A BatchRunner that calls `query(item)` for every item of `batch` (which must outlive the runner) and
/// sums param[0] + 0.5 param[1] of the returned std::array<double, 2>. `query` is copied into the runner
/// and inlined into its loop.
template <class Item, class QueryFn>
[[nodiscard]] BatchRunner batch_runner(std::span<const Item> batch, QueryFn query) {
  return [batch, query]() mutable {
    double sum = 0.0;
    for (const Item& item : batch) {
      const std::array<double, 2> p = query(item);
      sum += p[0] + 0.5 * p[1];
    }
    return sum;
  };
}

/// Least-squares line y = intercept + slope x.
struct LinearFit {
  double intercept = 0.0;
  double slope = 0.0;
  double r_squared = 0.0;  ///< 1 - SS_res / SS_tot (1 when all y are equal and fitted exactly)
};
/// InvalidArgument for fewer than 2 points, spans of different length or all x equal.
[[nodiscard]] LinearFit fit_line(std::span<const double> x, std::span<const double> y);

}  // namespace contactnn::eval
