// The evaluation study of one network on one labelled dataset: every method's errors against the labels,
// the network's error histograms, the Newton iteration counts and the single-thread timings. What
// evaluate-net's report mode computes; report.hpp writes it out.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "dataset/labelled_set.hpp"
#include "eval/accuracy.hpp"
#include "eval/histogram.hpp"
#include "eval/placement.hpp"
#include "eval/timing.hpp"
#include "mlp/random.hpp"

namespace contactnn::eval {

/// Settings of a study. Every field is a key of the [evaluate-net] config section with the same name.
struct StudyOptions {
  int max_fixed_iterations = 10;      ///< Newton with k = 1..this fixed iterations (paper: "more than ten")
  /// An estimate further than this many domain widths outside the parameter domain is a failure
  /// (inside_box): [-2, 2]^2 for bilinear. Half a width out is no contact point on this segment; an FE
  /// code would reject it rather than use it.
  double failure_box_margin = 0.5;
  NewtonMethodOptions newton;
  /// Accuracy runs on the dataset's configurations placed in world coordinates by: false, the identity
  /// (the dataset's own frame, so the TrainingDomain test sees the grid's exact values, ties included);
  /// true, random_placement(seed, row) (a check that nothing depends on the frame). Timing always uses
  /// random placements.
  bool random_placement = false;
  std::uint64_t seed = 1;            ///< placements and the timing sample
  int hist_bins = 100;               ///< bins of the network's error histograms
  /// Histogram range [-r, r]; 0 picks r = nice_ceil of the 99.9th percentile of |error| over both coordinates.
  double hist_range = 0.0;
  bool timing = true;                ///< run the speed part
  std::int64_t timing_queries = 100000;  ///< batch size (configurations drawn at random from the ok rows)
  TimingOptions timing_options;
};

/// Counts of Newton iterations: counts[k] rows needed k iterations (last entry: kIterationBins - 1 or more).
inline constexpr int kIterationBins = 51;

struct StudyResult {
  SurfaceKind surface = SurfaceKind::kBilinear;
  std::int64_t rows = 0;
  std::array<std::int64_t, kStatusCount> label_status_counts{};
  std::vector<MethodErrors> errors;        ///< error_table_methods order; per-row errors kept for the network only
  std::array<Histogram, 2> histograms;     ///< the network's signed errors per coordinate
  std::int64_t network_out_of_domain = 0;  ///< rows whose normalised input is outside the network's domain

  std::vector<std::int64_t> label_iterations;   ///< the dataset's iterations column, rows with status ok
  std::int64_t label_rows_ok = 0;
  std::vector<std::int64_t> newton_converged_iterations;  ///< plain Newton to convergence, converged rows
  std::int64_t newton_converged_failures = 0;  ///< plain Newton: did not converge (or degenerate/invalid)

  /// Timing per class of configuration (5.3.2: the network's cost is constant, Newton's is not): the timing
  /// batch split by the iterations plain Newton to convergence needs on each configuration.
  struct ClassTiming {
    std::string label;           ///< e.g. "6-7 iterations"
    std::int64_t queries = 0;    ///< distinct configurations in the class (cycled to the batch size when timed)
    double network_ns = 0.0;     ///< median ns/query of `network` on this class
    double converged_ns = 0.0;   ///< median ns/query of `newton_converged` on this class
  };
  std::vector<ClassTiming> class_timings;

  bool timed = false;
  std::vector<Timing> timings;  ///< network, network_forward_only, network_with_domain_check, newton_k, newton_converged, reference
  LinearFit newton_fit;         ///< median ns/query of newton_k against k, k = 1..max_fixed_iterations
  /// The same over the minimum ns/query: on a loaded machine the minimum is the least disturbed pass.
  LinearFit newton_fit_min;
};

/// Log line callback for progress on stderr.
using StudyLog = std::function<void(std::string_view)>;

/// The world configurations of `set` (configuration_from_features, then the placement of `options`).
[[nodiscard]] std::vector<geometry::Configuration> world_configurations(const dataset::LabelledSet& set,
                                                                        const StudyOptions& options);

/// Non-template parts of run_study: the Newton methods' errors, the iteration counts and the histograms
/// (given the network's estimates).
void add_newton_errors(const dataset::LabelledSet& set, const std::vector<geometry::Configuration>& world,
                       const StudyOptions& options, StudyResult& result, const StudyLog& log);
void add_network_errors(const dataset::LabelledSet& set, const Estimates& network, const StudyOptions& options,
                        StudyResult& result);
/// The Newton methods and the reference as timed methods over `batch`.
[[nodiscard]] std::vector<TimedMethod> newton_timed_methods(std::span<const geometry::Configuration> batch,
                                                            SurfaceKind kind, const StudyOptions& options);
/// `count` distinct rows with status ok, in random order (seeded); all ok rows when there are fewer.
[[nodiscard]] std::vector<std::size_t> timing_sample(const dataset::LabelledSet& set, std::int64_t count,
                                                     std::uint64_t seed);
/// Configurations grouped by how many iterations plain Newton to convergence needs on them.
struct ConfigurationClass {
  std::string label;
  std::vector<geometry::Configuration> items;
};
/// The classes 1-5, 6-7, 8-10 iterations and "more than 10 or not converged", in that order (possibly empty).
[[nodiscard]] std::vector<ConfigurationClass> split_by_newton_iterations(
    const std::vector<geometry::Configuration>& batch, SurfaceKind kind, const StudyOptions& options);
/// Sets `timed` and the line fit over the newton_k timings.
void finish_timings(StudyResult& result, const StudyOptions& options);

/// Runs the whole study of `predictor` (the network; its TrainingDomain is `domain`) on `set`.
/// Accuracy runs in parallel (OpenMP); timing on the calling thread only.
template <FeaturePredictor P>
[[nodiscard]] StudyResult run_study(const dataset::LabelledSet& set, const P& predictor,
                                    const geometry::TrainingDomain& domain, const StudyOptions& options,
                                    const StudyLog& log = {}) {
  const auto say = [&](std::string_view s) {
    if (log) log(s);
  };
  StudyResult result;
  result.surface = set.surface;
  result.rows = set.size();

  // 1. Accuracy: every method from the same world coordinates.
  say("accuracy: placing configurations");
  const std::vector<geometry::Configuration> world = world_configurations(set, options);
  say("accuracy: network");
  const Estimates network = network_estimates(world, set.surface, predictor, &domain);
  add_network_errors(set, network, options, result);
  add_newton_errors(set, world, options, result, log);
  if (!options.timing) return result;

  // 2. Speed: one batch of randomly placed world configurations, shared by every method.
  say("speed: preparing the batch");
  const std::vector<std::size_t> rows = timing_sample(set, options.timing_queries, options.seed);
  std::vector<geometry::Configuration> batch(rows.size());
  dataset::MatrixRM<double> features(static_cast<Eigen::Index>(rows.size()), feature_count(set.surface));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const geometry::Configuration local =
        configuration_from_features(set.surface, set.features.row(static_cast<Eigen::Index>(rows[i])).data());
    batch[i] = place(local, random_placement(options.seed ^ 0x5eedULL, rows[i]));
    const geometry::NormaliseOutcome n = geometry::normalise(batch[i], set.surface);
    for (int f = 0; f < feature_count(set.surface); ++f) {
      features(static_cast<Eigen::Index>(i), f) = n.value ? n.value->features[static_cast<std::size_t>(f)] : 0.0;
    }
  }
  const std::span<const geometry::Configuration> batch_span(batch);
  std::vector<std::size_t> feature_rows(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) feature_rows[i] = i;
  const auto n_queries = static_cast<std::int64_t>(batch.size());
  const SurfaceKind kind = set.surface;
  std::vector<TimedMethod> methods;
  methods.push_back({"network", "Section 4 normalisation of the world coordinates + forward pass", n_queries,
                     batch_runner(batch_span, [p = predictor, kind](const geometry::Configuration& c) mutable {
                       return network_estimate(c, kind, p, nullptr).param;
                     })});
  methods.push_back({"network_forward_only", "forward pass on precomputed normalised features (no preprocessing)",
                     n_queries,
                     batch_runner(std::span<const std::size_t>(feature_rows),
                                  [p = predictor, &features](std::size_t i) mutable {
                                    std::array<double, 2> out{};
                                    p.predict(features.row(static_cast<Eigen::Index>(i)).data(), out.data());
                                    return out;
                                  })});
  methods.push_back({"network_with_domain_check",
                     "normalisation + forward pass + TrainingDomain test (what evaluate-net --input does per row)",
                     n_queries,
                     batch_runner(batch_span, [p = predictor, kind, &domain](const geometry::Configuration& c) mutable {
                       return network_estimate(c, kind, p, &domain).param;
                     })});
  for (TimedMethod& m : newton_timed_methods(batch_span, kind, options)) methods.push_back(std::move(m));
  say("speed: timing (single thread)");
  result.timings = time_methods(methods, options.timing_options);
  finish_timings(result, options);

  // 3. The same two methods per class of configuration (by plain Newton's iteration count).
  say("speed: timing per iteration class");
  for (const ConfigurationClass& group_class : split_by_newton_iterations(batch, kind, options)) {
    if (group_class.items.empty()) continue;
    // A small class is cycled up to the main batch's size, so that one pass is long enough for the clock
    // and a preemption does not dominate it; `queries` reports the distinct configurations.
    std::vector<geometry::Configuration> group = group_class.items;
    for (std::size_t i = 0; group.size() < batch.size(); ++i) group.push_back(group_class.items[i % group_class.items.size()]);
    const std::span<const geometry::Configuration> g(group);
    std::vector<TimedMethod> pair;
    pair.push_back({"network", "", static_cast<std::int64_t>(group.size()),
                    batch_runner(g, [p = predictor, kind](const geometry::Configuration& c) mutable {
                      return network_estimate(c, kind, p, nullptr).param;
                    })});
    const NewtonMethodOptions newton = options.newton;
    pair.push_back({"newton_converged", "", static_cast<std::int64_t>(group.size()),
                    batch_runner(g, [kind, newton](const geometry::Configuration& c) {
                      return newton_converged_estimate(c, kind, newton).param;
                    })});
    const std::vector<Timing> t = time_methods(pair, options.timing_options);
    StudyResult::ClassTiming ct;
    ct.label = group_class.label;
    ct.queries = static_cast<std::int64_t>(group_class.items.size());
    ct.network_ns = t[0].median_ns;
    ct.converged_ns = t[1].median_ns;
    result.class_timings.push_back(ct);
  }
  return result;
}

}  // namespace contactnn::eval
