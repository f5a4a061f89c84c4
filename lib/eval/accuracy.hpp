// Accuracy of each method against the Newton labels of a dataset: per-row estimates, then signed errors
// with failures counted (paper Sections 5.3.1 and 6.3.3, Table 1).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dataset/labelled_set.hpp"
#include "eval/error_statistics.hpp"
#include "eval/methods.hpp"

namespace contactnn::eval {

/// One method's estimates for rows 0..N-1 of a set of world configurations.
struct Estimates {
  Method method;
  std::vector<std::array<double, 2>> param;
  std::vector<Status> status;
  std::vector<int> iterations;

  [[nodiscard]] std::size_t size() const { return param.size(); }
  void resize(std::size_t n);
};

/// The network on every configuration, rows in parallel (OpenMP; each thread copies `predictor`).
/// The result does not depend on the thread count.
template <FeaturePredictor P>
[[nodiscard]] Estimates network_estimates(const std::vector<geometry::Configuration>& world, SurfaceKind kind,
                                          const P& predictor, const geometry::TrainingDomain* domain) {
  Estimates out;
  out.method = Method{Method::Kind::kNetwork, 0};
  out.resize(world.size());
  const auto n = static_cast<std::int64_t>(world.size());
#pragma omp parallel
  {
    P local = predictor;
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      const auto r = static_cast<std::size_t>(i);
      const Estimate e = network_estimate(world[r], kind, local, domain);
      out.param[r] = e.param;
      out.status[r] = e.status;
      out.iterations[r] = 0;
    }
  }
  return out;
}

/// A Newton method (kNewtonFixed, kNewtonConverged or kReference) on every configuration, rows in parallel.
[[nodiscard]] Estimates newton_estimates(const std::vector<geometry::Configuration>& world, SurfaceKind kind,
                                         const Method& method, const NewtonMethodOptions& options);

/// Errors of one method against the labels.
struct MethodErrors {
  Method method;
  std::array<ErrorStatistics, 2> stats;      ///< per local coordinate (xi, eta) or (u, v)
  std::int64_t rows = 0;
  std::int64_t failures_reference = 0;       ///< label status is not ok (the row has no reference)
  std::int64_t failures_method = 0;          ///< label ok, estimate unusable (see compare_with_labels)
  std::int64_t outside_domain = 0;           ///< rows in the statistics whose estimate is outside the parameter domain
  std::array<std::int64_t, kStatusCount> status_counts{};  ///< the estimates' statuses, all rows
  /// Signed errors (estimate - label) per coordinate and the failure flag of every row; errors of failed
  /// rows are 0 and must not be used.
  std::array<std::vector<double>, 2> errors;
  std::vector<std::uint8_t> failed;
};

/// Compares `estimates` with `labels` (N x 2). A row is a failure, counted and never averaged in, when its
/// label status is not ok, or the estimate's status is neither ok nor outside (a network input out of
/// domain, a Newton that did not converge, a degenerate or invalid input), or the estimate is non-finite or
/// outside the parameter domain enlarged by `failure_box_margin` domain widths (inside_box). The rest enter
/// the statistics with error = estimate - label; outside_domain counts those beyond the domain itself
/// (by more than 1e-10).
[[nodiscard]] MethodErrors compare_with_labels(const Estimates& estimates, const dataset::MatrixRM<double>& labels,
                                               const std::vector<Status>& label_status, SurfaceKind kind,
                                               double failure_box_margin);

/// Counts of an integer column: counts[k] is the number of rows with value k for 0 <= k < size - 1; the last
/// entry counts values >= size - 1. Rows where `include[i]` is false are skipped; negative values count in 0.
[[nodiscard]] std::vector<std::int64_t> count_values(const std::vector<int>& values, const std::vector<bool>& include,
                                                     int size);

}  // namespace contactnn::eval
