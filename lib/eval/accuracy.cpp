#include "eval/accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mlp/random.hpp"

namespace contactnn::eval {

Estimates run_on_set(const search::LocalSearch& search, const EvaluationSet& set, int threads,
                     const std::vector<double>* start) {
  CONTACTNN_REQUIRE(search.surface() == set.surface, "a " << to_string(search.surface()) << " search on the "
                                                          << to_string(set.surface) << " set '" << set.name
                                                          << "'");
  Estimates e;
  const auto n = static_cast<std::size_t>(set.rows());
  CONTACTNN_REQUIRE(
      start == nullptr || start->size() == 2 * n,
      "run_on_set: " << start->size() / 2 << " starts for the " << n << " rows of '" << set.name << "'");
  e.param = start != nullptr ? *start : std::vector<double>(2 * n);
  e.gap.resize(n);
  e.status.resize(n);
  e.iterations.resize(n);
  search.run(n, set.raw.data(),
             search::Results<double>{e.param.data(), e.gap.data(), e.status.data(), e.iterations.data()},
             threads);
  return e;
}

std::vector<double> starts_near_reference(const EvaluationSet& set, double offset, std::uint64_t seed) {
  const ParamDomain d = param_domain(set.surface);
  const double centre = 0.5 * (d.lo + d.hi);
  const auto n = static_cast<std::size_t>(set.rows());
  std::vector<double> start(2 * n, centre);
  mlp::Rng rng(mlp::Rng::derive_seed(seed, 0x5354415254ULL));  // "START"
  for (std::size_t i = 0; i < n; ++i) {
    const double angle = rng.uniform(0.0, 2.0 * std::numbers::pi);
    if (set.label_status[i] != Status::kOk && set.label_status[i] != Status::kOutside) continue;
    const auto r = static_cast<Eigen::Index>(i);
    start[2 * i] = set.labels(r, 0) + offset * std::cos(angle);
    start[2 * i + 1] = set.labels(r, 1) + offset * std::sin(angle);
  }
  return start;
}

bool inside_domain(const double* p, SurfaceKind kind, double margin) {
  const ParamDomain d = param_domain(kind);
  // False for NaN: a non-finite estimate is inside nothing.
  return p[0] >= d.lo - margin && p[0] <= d.hi + margin && p[1] >= d.lo - margin && p[1] <= d.hi + margin;
}

MethodErrors compare_with_labels(std::string method, const Estimates& estimates, const EvaluationSet& set,
                                 double failure_box_margin, bool keep_rows) {
  const std::size_t n = estimates.size();
  CONTACTNN_REQUIRE(
      static_cast<std::int64_t>(n) == set.rows(),
      "compare_with_labels: " << n << " estimates for the " << set.rows() << " rows of '" << set.name << "'");
  const ParamDomain d = param_domain(set.surface);
  const double box = failure_box_margin * (d.hi - d.lo);
  constexpr double kInsideMargin = 1e-10;  // the reference solver's domain_margin: ok versus outside
  MethodErrors m;
  m.method = std::move(method);
  m.rows = static_cast<std::int64_t>(n);
  std::vector<std::uint8_t> failed(n, 0);
  std::array<std::vector<double>, 2> errors{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
  std::vector<double> gap_errors;
  std::vector<std::uint8_t> gap_failed;
  m.converged_iterations.assign(n, -1);
  for (std::size_t r = 0; r < n; ++r) {
    const Status s = estimates.status[r];
    ++m.status_counts[static_cast<std::size_t>(s)];
    if (s == Status::kOk || s == Status::kOutside) m.converged_iterations[r] = estimates.iterations[r];
    const Status label = set.label_status[r];
    if (label != Status::kOk && label != Status::kOutside) {
      failed[r] = 1;
      ++m.failures_reference;
      continue;
    }
    const double* p = &estimates.param[2 * r];
    const bool answered = s == Status::kOk || s == Status::kOutside || s == Status::kOutOfDomain;
    if (!answered || !inside_domain(p, set.surface, box)) {
      failed[r] = 1;
      ++m.failures_method;
      continue;
    }
    const auto row = static_cast<Eigen::Index>(r);
    errors[0][r] = p[0] - set.labels(row, 0);
    errors[1][r] = p[1] - set.labels(row, 1);
    if (s == Status::kOutOfDomain) ++m.out_of_domain;
    const bool inside = inside_domain(p, set.surface, kInsideMargin);
    if (!inside) ++m.outside_domain;
    // The method's own verdict where it gives one: a hybrid on a Gregory patch holds a node whose nearest
    // point lies beyond an edge on that edge (coordinates inside, status outside), where the reference
    // reports the stationary point beyond it. A network reports no outside: its coordinates decide.
    const bool says_inside = inside && s != Status::kOutside;
    ++m.inside_compared;
    if (says_inside == (label == Status::kOk)) ++m.inside_agree;
    if (set.size[r] > 0.0 && std::isfinite(estimates.gap[r])) {
      gap_errors.push_back((estimates.gap[r] - set.label_gap[r]) / set.size[r]);
      gap_failed.push_back(0);
    }
  }
  for (std::size_t c = 0; c < 2; ++c) m.stats[c] = summarize_errors(errors[c], failed);
  m.gap_relative = summarize_errors(gap_errors, gap_failed);
  if (keep_rows) {
    m.errors = std::move(errors);
    m.failed = std::move(failed);
  }
  return m;
}

std::vector<std::int64_t> count_values(const std::vector<std::int32_t>& values, int size) {
  CONTACTNN_REQUIRE(size >= 1, "count_values: size " << size);
  std::vector<std::int64_t> counts(static_cast<std::size_t>(size), 0);
  for (const std::int32_t v : values) {
    if (v < 0) continue;
    ++counts[static_cast<std::size_t>(std::min(v, size - 1))];
  }
  return counts;
}

}  // namespace contactnn::eval
