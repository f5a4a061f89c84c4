#include "eval/accuracy.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace contactnn::eval {

void Estimates::resize(std::size_t n) {
  param.assign(n, {0.0, 0.0});
  status.assign(n, Status::kOk);
  iterations.assign(n, 0);
}

Estimates newton_estimates(const std::vector<geometry::Configuration>& world, SurfaceKind kind, const Method& method,
                           const NewtonMethodOptions& options) {
  CONTACTNN_REQUIRE(method.kind != Method::Kind::kNetwork, "newton_estimates: " << method.name() << " is not a Newton method");
  Estimates out;
  out.method = method;
  out.resize(world.size());
  const auto n = static_cast<std::int64_t>(world.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(i);
    Estimate e;
    switch (method.kind) {
      case Method::Kind::kNewtonFixed:
        e = newton_fixed_estimate(world[r], kind, method.iterations);
        break;
      case Method::Kind::kNewtonConverged:
        e = newton_converged_estimate(world[r], kind, options);
        break;
      default:
        e = reference_estimate(world[r], kind, options);
        break;
    }
    out.param[r] = e.param;
    out.status[r] = e.status;
    out.iterations[r] = e.iterations;
  }
  return out;
}

MethodErrors compare_with_labels(const Estimates& estimates, const dataset::MatrixRM<double>& labels,
                                 const std::vector<Status>& label_status, SurfaceKind kind, double failure_box_margin) {
  const std::size_t n = estimates.size();
  CONTACTNN_REQUIRE(static_cast<std::size_t>(labels.rows()) == n && labels.cols() == 2 && label_status.size() == n,
                    "compare_with_labels: " << n << " estimates, labels " << labels.rows() << " x " << labels.cols()
                                            << ", " << label_status.size() << " label statuses");
  MethodErrors m;
  m.method = estimates.method;
  m.rows = static_cast<std::int64_t>(n);
  m.failed.assign(n, 0);
  for (auto& e : m.errors) e.assign(n, 0.0);
  for (std::size_t r = 0; r < n; ++r) {
    const Status s = estimates.status[r];
    ++m.status_counts[static_cast<std::size_t>(s)];
    if (label_status[r] != Status::kOk) {
      m.failed[r] = 1;
      ++m.failures_reference;
      continue;
    }
    const std::array<double, 2>& p = estimates.param[r];
    const bool usable = (s == Status::kOk || s == Status::kOutside) && inside_box(p, kind, failure_box_margin);
    if (!usable) {
      m.failed[r] = 1;
      ++m.failures_method;
      continue;
    }
    const auto row = static_cast<Eigen::Index>(r);
    m.errors[0][r] = p[0] - labels(row, 0);
    m.errors[1][r] = p[1] - labels(row, 1);
    if (!inside_domain(p, kind, 1e-10)) ++m.outside_domain;
  }
  for (int c = 0; c < 2; ++c) m.stats[static_cast<std::size_t>(c)] = summarize_errors(m.errors[static_cast<std::size_t>(c)], m.failed);
  return m;
}

std::vector<std::int64_t> count_values(const std::vector<int>& values, const std::vector<bool>& include, int size) {
  CONTACTNN_REQUIRE(size >= 1 && values.size() == include.size(),
                    "count_values: size " << size << ", " << values.size() << " values, " << include.size() << " flags");
  std::vector<std::int64_t> counts(static_cast<std::size_t>(size), 0);
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!include[i]) continue;
    const int k = std::clamp(values[i], 0, size - 1);
    ++counts[static_cast<std::size_t>(k)];
  }
  return counts;
}

}  // namespace contactnn::eval
