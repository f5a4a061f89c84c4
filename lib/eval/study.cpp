#include "eval/study.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "core/error.hpp"

namespace contactnn::eval {

std::vector<geometry::Configuration> world_configurations(const dataset::LabelledSet& set,
                                                          const StudyOptions& options) {
  std::vector<geometry::Configuration> world(static_cast<std::size_t>(set.size()));
  const std::int64_t n = set.size();
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    const geometry::Configuration local =
        configuration_from_features(set.surface, set.features.row(static_cast<Eigen::Index>(i)).data());
    world[static_cast<std::size_t>(i)] =
        options.random_placement ? place(local, random_placement(options.seed, static_cast<std::uint64_t>(i))) : local;
  }
  return world;
}

void add_network_errors(const dataset::LabelledSet& set, const Estimates& network, const StudyOptions& options,
                        StudyResult& result) {
  for (const Status s : set.status) ++result.label_status_counts[static_cast<std::size_t>(s)];
  MethodErrors m = compare_with_labels(network, set.labels, set.status, set.surface, options.failure_box_margin);
  result.network_out_of_domain = m.status_counts[static_cast<std::size_t>(Status::kOutOfDomain)];

  // Histogram range: fixed, or nice_ceil of the 99.9th percentile of |e| over both coordinates.
  double range = options.hist_range;
  if (!(range > 0.0)) {
    std::vector<double> abs_errors;
    for (int c = 0; c < 2; ++c) {
      for (std::size_t r = 0; r < m.failed.size(); ++r) {
        if (m.failed[r] == 0) abs_errors.push_back(std::abs(m.errors[static_cast<std::size_t>(c)][r]));
      }
    }
    std::sort(abs_errors.begin(), abs_errors.end());
    range = abs_errors.empty() ? 1.0 : nice_ceil(percentile(abs_errors, 99.9));
  }
  for (int c = 0; c < 2; ++c) {
    result.histograms[static_cast<std::size_t>(c)] =
        make_histogram(m.errors[static_cast<std::size_t>(c)], m.failed, -range, range, options.hist_bins);
  }
  result.errors.insert(result.errors.begin(), std::move(m));
}

void add_newton_errors(const dataset::LabelledSet& set, const std::vector<geometry::Configuration>& world,
                       const StudyOptions& options, StudyResult& result, const StudyLog& log) {
  // The dataset's own iteration counts (the label solver's start that produced each label).
  std::vector<int> label_iterations(set.iterations.data(), set.iterations.data() + set.iterations.size());
  std::vector<bool> ok(set.status.size());
  for (std::size_t r = 0; r < ok.size(); ++r) ok[r] = set.status[r] == Status::kOk;
  result.label_iterations = count_values(label_iterations, ok, kIterationBins);
  result.label_rows_ok = std::count(ok.begin(), ok.end(), true);

  for (const Method& method : error_table_methods(options.max_fixed_iterations)) {
    if (method.kind == Method::Kind::kNetwork) continue;
    if (log) log("accuracy: " + method.name());
    const Estimates e = newton_estimates(world, set.surface, method, options.newton);
    MethodErrors m = compare_with_labels(e, set.labels, set.status, set.surface, options.failure_box_margin);
    for (auto& v : m.errors) std::vector<double>().swap(v);  // only the network's rows are kept
    std::vector<std::uint8_t>().swap(m.failed);
    if (method.kind == Method::Kind::kNewtonConverged) {
      std::vector<bool> converged(e.size());
      for (std::size_t r = 0; r < e.size(); ++r) {
        converged[r] = e.status[r] == Status::kOk || e.status[r] == Status::kOutside;
      }
      result.newton_converged_iterations = count_values(e.iterations, converged, kIterationBins);
      result.newton_converged_failures =
          static_cast<std::int64_t>(std::count(converged.begin(), converged.end(), false));
    }
    result.errors.push_back(std::move(m));
  }
}

std::vector<TimedMethod> newton_timed_methods(std::span<const geometry::Configuration> batch, SurfaceKind kind,
                                              const StudyOptions& options) {
  const auto n = static_cast<std::int64_t>(batch.size());
  std::vector<TimedMethod> methods;
  for (int k = 1; k <= options.max_fixed_iterations; ++k) {
    const Method m{Method::Kind::kNewtonFixed, k};
    methods.push_back({m.name(), m.description(), n,
                       batch_runner(batch, [kind, k](const geometry::Configuration& c) {
                         return newton_fixed_estimate(c, kind, k).param;
                       })});
  }
  const NewtonMethodOptions newton = options.newton;
  const Method converged{Method::Kind::kNewtonConverged, 0};
  methods.push_back({converged.name(), converged.description(), n,
                     batch_runner(batch, [kind, newton](const geometry::Configuration& c) {
                       return newton_converged_estimate(c, kind, newton).param;
                     })});
  const Method reference{Method::Kind::kReference, 0};
  methods.push_back({reference.name(), reference.description(), n,
                     batch_runner(batch, [kind, newton](const geometry::Configuration& c) {
                       return reference_estimate(c, kind, newton).param;
                     })});
  return methods;
}

std::vector<std::size_t> timing_sample(const dataset::LabelledSet& set, std::int64_t count, std::uint64_t seed) {
  CONTACTNN_REQUIRE(count >= 1, "timing_queries = " << count << ", expected >= 1");
  std::vector<std::size_t> ok_rows;
  for (std::size_t r = 0; r < set.status.size(); ++r) {
    if (set.status[r] == Status::kOk) ok_rows.push_back(r);
  }
  CONTACTNN_REQUIRE_AS(FormatError, !ok_rows.empty(), "the dataset has no row with status ok to time on");
  // Partial Fisher-Yates: the first `count` entries become a uniform sample in random order (random order
  // so that no method profits from the grid order, e.g. Newton's branch history).
  mlp::Rng rng(mlp::Rng::derive_seed(seed, 0x7173ULL));
  const std::size_t take = std::min<std::size_t>(ok_rows.size(), static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < take; ++i) {
    const std::size_t j = i + static_cast<std::size_t>(rng.below(ok_rows.size() - i));
    std::swap(ok_rows[i], ok_rows[j]);
  }
  ok_rows.resize(take);
  return ok_rows;
}

namespace {
// Upper iteration bound of each class; the last class takes the rest and the failures.
constexpr std::array<int, 3> kClassUpper = {5, 7, 10};
constexpr std::array<const char*, 4> kClassLabels = {"1-5 iterations", "6-7 iterations", "8-10 iterations",
                                                     "more than 10 or not converged"};
}  // namespace

std::vector<ConfigurationClass> split_by_newton_iterations(const std::vector<geometry::Configuration>& batch,
                                                           SurfaceKind kind, const StudyOptions& options) {
  std::vector<ConfigurationClass> groups(kClassLabels.size());
  for (std::size_t g = 0; g < groups.size(); ++g) groups[g].label = kClassLabels[g];
  for (const geometry::Configuration& c : batch) {
    const Estimate e = newton_converged_estimate(c, kind, options.newton);
    const bool converged = e.status == Status::kOk || e.status == Status::kOutside;
    std::size_t g = kClassUpper.size();
    for (std::size_t k = 0; converged && k < kClassUpper.size(); ++k) {
      if (e.iterations <= kClassUpper[k]) {
        g = k;
        break;
      }
    }
    groups[g].items.push_back(c);
  }
  return groups;
}

void finish_timings(StudyResult& result, const StudyOptions& options) {
  result.timed = true;
  std::vector<double> k, t, t_min;
  for (const Timing& timing : result.timings) {
    for (int i = 1; i <= options.max_fixed_iterations; ++i) {
      if (timing.name == Method{Method::Kind::kNewtonFixed, i}.name()) {
        k.push_back(i);
        t.push_back(timing.median_ns);
        t_min.push_back(timing.min_ns);
      }
    }
  }
  if (k.size() >= 2) {
    result.newton_fit = fit_line(k, t);
    result.newton_fit_min = fit_line(k, t_min);
  }
}

}  // namespace contactnn::eval
