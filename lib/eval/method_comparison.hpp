// The method comparison: every search method (lib/search: networks, Newton, the closed form, the hybrids) on
// one or more evaluation sets (the paper's grid, a held-out random sample, a scene's pairs), each method's
// accuracy against the reference labels, and its speed one query at a time and in batches at 1 and several
// threads, all measured in one run so the figures compare. What evaluate-net's report mode computes;
// report.hpp writes it out.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "eval/accuracy.hpp"
#include "eval/evaluation_set.hpp"
#include "eval/histogram.hpp"
#include "eval/timing.hpp"
#include "search/local_search.hpp"

namespace contactnn::eval {

/// A network taking part in the comparison.
struct EvaluatedNetwork {
  std::string name;     ///< its methods are called "network[name]", "network+newton:1[name]", ...
  std::string summary;  ///< e.g. "16-48-2, float, U0 = 2, affine inputs"
  const search::NetworkModel* model = nullptr;
};

/// Settings of a comparison. Every field but `search` is a key of the [evaluate-net] config section with the
/// same name; search.max_iterations and search.tol_param are its converged_max_iterations and
/// converged_tol_param.
struct ComparisonOptions {
  /// Comma-separated search methods (search::Method names); a network method is run with every network.
  /// The item "default" stands for the default list (default_methods()); empty: the default list alone.
  std::string methods;
  int max_fixed_iterations = 10;  ///< the default list's newton:1..this (the paper: "more than ten")
  /// An estimate further than this many domain widths outside the parameter domain is a failure: half a width
  /// out is no contact point on this segment; an FE code would reject it rather than use it.
  double failure_box_margin = 0.5;
  search::SearchOptions search;  ///< every method's settings (Newton's limits, boxes, the domain check)
  /// start+newton:K (the caller's own start): its starts are each reference point moved this far (parameter
  /// units) in a random direction (starts_near_reference, from `seed`): how near a start must be for K steps.
  /// < 0: no starts, such a method is refused (an evaluation set has no previous time step to give).
  double start_offset = -1.0;
  /// Datasets are placed in world coordinates by: false, the identity (their own frame); true,
  /// random_placement(seed, row) (nothing may depend on the frame). Pairs files are world coordinates.
  bool random_placement = false;
  std::uint64_t seed = 1;  ///< placements and the timing sample
  int hist_bins = 100;     ///< bins of the first network's error histograms (first set)
  /// Histogram range [-r, r]; 0 picks r = nice_ceil of the 99.9th percentile of |error| over both
  /// coordinates.
  double hist_range = 0.0;
  bool timing = true;                    ///< run the speed part
  std::int64_t timing_queries = 100000;  ///< queries per timed pass (rows drawn at random, cycled when fewer)
  int timing_threads = 2;  ///< threads of the batched multi-thread timing (1-thread is always timed)
  TimingOptions timing_options;
};

/// The default methods, the same list for both surfaces: (with networks) network and network+newton:K
/// for K = 1, 2, 3, 5, 8, each run with every network; closed_form and closed_form+newton:K for the same K
/// (on a Gregory patch the closed form of its corner facet); newton:1..max_fixed_iterations; newton (to
/// convergence).
[[nodiscard]] std::string default_methods(int max_fixed_iterations, bool with_networks);

/// One method's timings, ns per query: one query per call, a batch of all on 1 thread, on timing_threads.
struct MethodTiming {
  std::string method;
  Timing one_at_a_time, batched, batched_threads;
};

/// Counts of Newton iterations: counts[k] rows needed k iterations (last entry: kIterationBins - 1 or more).
inline constexpr int kIterationBins = 51;

/// A comparison's results on one set.
struct SetResult {
  std::string name, source;
  std::int64_t rows = 0;
  std::int64_t skipped_no_segment = 0;
  std::array<std::int64_t, kStatusCount> label_status_counts{};
  std::vector<MethodErrors> errors;            ///< in the comparison's method order
  std::vector<std::int64_t> label_iterations;  ///< the reference's iterations (datasets), ok rows
  std::int64_t label_rows_ok = 0;
  std::vector<std::int64_t> newton_iterations;  ///< "newton" to convergence, converged rows
  std::int64_t newton_failures = 0;             ///< "newton": not converged, degenerate or invalid

  bool timed = false;
  std::int64_t timing_queries = 0;    ///< queries per timed pass
  std::int64_t timing_distinct = 0;   ///< distinct rows among them
  std::vector<MethodTiming> timings;  ///< in the comparison's method order
  LinearFit newton_fit;               ///< batched 1-thread median ns/query of newton:k against k
  LinearFit newton_fit_one;           ///< the same one query at a time
  /// Time per class of configuration (5.3.2: the network's cost is constant, Newton's is not): the timing
  /// sample split by the steps "newton" needs on each query.
  struct ClassTiming {
    std::string label;         ///< e.g. "6-7 iterations"
    std::int64_t queries = 0;  ///< distinct queries in the class
    double network_ns = 0.0;   ///< batched, 1 thread, median: the first network
    double newton_ns = 0.0;    ///< the same for "newton"
  };
  std::vector<ClassTiming> class_timings;
};

struct ComparisonResult {
  SurfaceKind surface = SurfaceKind::kBilinear;
  std::vector<std::string> methods;  ///< expanded method names, in order
  std::vector<EvaluatedNetwork> networks;
  std::vector<SetResult> sets;
  std::array<Histogram, 2> histograms;  ///< the first network's signed errors on the first set
  std::string histogram_method;         ///< e.g. "network[bilinear-8]" (empty: no network)
  int timing_threads = 0;               ///< threads of the multi-thread batched timing
};

/// Compares the methods: every method on every set. Accuracy runs in parallel (OpenMP); timing as described
/// in timing.hpp, the three modes of every method interleaved in one round-robin per set. InvalidArgument for
/// no set, sets of other surfaces than the networks', an unknown method, a network method without a network.
[[nodiscard]] ComparisonResult compare_methods(const std::vector<EvaluationSet>& sets,
                                               const std::vector<EvaluatedNetwork>& networks,
                                               const ComparisonOptions& options, const ProgressLog& log = {});

/// The network's cost in Newton iterations on one set: the k at which the fitted line of newton:k reaches the
/// network's time (the paper's sense: "equal to that of seven iterations"), batched and one at a time.
struct NetworkCostInIterations {
  bool available = false;
  double batched = 0.0;
  double one_at_a_time = 0.0;
};
[[nodiscard]] NetworkCostInIterations network_cost_in_iterations(const SetResult& set,
                                                                 const std::string& network_method);

}  // namespace contactnn::eval
