// Tests of lib/eval/accuracy: running a search method on a set (and start+newton:K from starts near the
// references), and the failure rules and statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "dataset/sampling.hpp"
#include "eval/accuracy.hpp"

namespace contactnn::eval {
namespace {

/// A set of `rows` unit squares with made-up labels; only the labels, statuses, gaps and sizes matter here.
EvaluationSet synthetic_set(int rows) {
  EvaluationSet s;
  s.name = "synthetic";
  s.surface = SurfaceKind::kBilinear;
  s.raw.assign(static_cast<std::size_t>(15 * rows), 0.0);
  s.labels.resize(rows, 2);
  for (int r = 0; r < rows; ++r) {
    s.labels(r, 0) = 0.1 * r;
    s.labels(r, 1) = -0.1 * r;
    s.label_status.push_back(Status::kOk);
    s.label_gap.push_back(0.5);
    s.size.push_back(2.0);
    s.label_iterations.push_back(3);
  }
  return s;
}

Estimates estimates_for(const EvaluationSet& s) {
  Estimates e;
  const auto n = static_cast<std::size_t>(s.rows());
  e.param.resize(2 * n);
  e.gap.assign(n, 0.5);
  e.status.assign(n, Status::kOk);
  e.iterations.assign(n, 2);
  for (std::size_t r = 0; r < n; ++r) {
    e.param[2 * r] = s.labels(static_cast<Eigen::Index>(r), 0) + 0.01;
    e.param[2 * r + 1] = s.labels(static_cast<Eigen::Index>(r), 1);
  }
  return e;
}

TEST(CompareWithLabels, FailureRulesAndStatistics) {
  EvaluationSet s = synthetic_set(7);
  Estimates e = estimates_for(s);
  s.label_status[1] = Status::kNoConvergence;             // no reference point
  e.param[4] = std::numeric_limits<double>::quiet_NaN();  // row 2: non-finite estimate
  e.param[6] = 2.0 + 1e-9;                                // row 3: beyond the box [-2, 2]
  e.status[4] = Status::kNoConvergence;                   // row 4: the method failed
  e.param[10] = 1.5;                                      // row 5: outside the domain, inside the box
  e.param[11] = -0.5;
  e.status[6] = Status::kOutOfDomain;  // row 6: a network's answer out of its domain
  e.gap[0] = 0.5 + 0.2;                // row 0: gap off by 0.2 of size 2
  const MethodErrors m = compare_with_labels("m", e, s, 0.5, true);
  EXPECT_EQ(m.failures_reference, 1);
  EXPECT_EQ(m.failures_method, 3);
  EXPECT_EQ(m.stats[0].n, 3);  // rows 0, 5, 6
  EXPECT_EQ(m.out_of_domain, 1);
  EXPECT_EQ(m.outside_domain, 1);
  // Errors in xi: row 0 0.01, row 5 1.5 - 0.5 = 1.0, row 6 0.01.
  EXPECT_NEAR(m.stats[0].mean_abs, (0.01 + 1.0 + 0.01) / 3, 1e-15);
  EXPECT_NEAR(m.stats[1].max_abs, 0.0, 1e-15);
  // Gap error relative to the size: 0.2 / 2 on row 0, 0 elsewhere.
  EXPECT_NEAR(m.gap_relative.max_abs, 0.1, 1e-15);
  EXPECT_NEAR(m.gap_relative.mean_abs, 0.1 / 3, 1e-15);
  // Inside agreement: every reference is ok (inside); row 5's estimate is outside.
  EXPECT_EQ(m.inside_compared, 3);
  EXPECT_EQ(m.inside_agree, 2);
  EXPECT_EQ(m.errors[0].size(), 7u);
  EXPECT_EQ(m.failed, (std::vector<std::uint8_t>{0, 1, 1, 1, 1, 0, 0}));
  EXPECT_EQ(m.converged_iterations, (std::vector<std::int32_t>{2, 2, 2, 2, -1, 2, -1}));
}

TEST(CompareWithLabels, InsideAgreementTakesTheMethodsOutsideStatus) {
  // Four references just beyond the edge xi = 1 (outside), the estimates held on that edge (coordinates
  // inside): with status outside the method agrees with the reference, with status ok it does not; a network
  // (ok or out_of_domain, never outside) is judged by its coordinates. Row 3's estimate lies beyond the edge.
  EvaluationSet s = synthetic_set(4);
  Estimates e = estimates_for(s);
  for (Eigen::Index r = 0; r < 4; ++r) {
    s.labels(r, 0) = 1.0 + 1e-6;
    s.label_status[static_cast<std::size_t>(r)] = Status::kOutside;
    e.param[2 * static_cast<std::size_t>(r)] = 1.0;
  }
  e.status = {Status::kOutside, Status::kOk, Status::kOutOfDomain, Status::kOk};
  e.param[6] = 1.0 + 1e-6;
  const MethodErrors m = compare_with_labels("m", e, s, 0.5, false);
  EXPECT_EQ(m.inside_compared, 4);
  EXPECT_EQ(m.inside_agree, 2);  // rows 0 (outside by status) and 3 (outside by coordinates)
}

/// 200 random configurations of the paper's bilinear domain restricted to well-shaped segments (angles
/// 60-120, nearly flat), placed at random in world coordinates.
EvaluationSet well_shaped_set() {
  dataset::EnumerationOptions o;
  o.filters.min_angle_degrees = 60;
  o.filters.max_angle_degrees = 120;
  o.filters.z_limit = 0.05;
  dataset::EnumerationSummary summary;
  return set_from_dataset(dataset::sample_configurations(o, 200, summary), "s", "s", true, 2);
}

TEST(RunOnSet, NewtonFromWorldCoordinatesReachesTheLabels) {
  // On well-shaped segments newton:10 from the centre converges to the reference; every estimate agrees to
  // rounding.
  const EvaluationSet s = well_shaped_set();
  const search::LocalSearch newton(SurfaceKind::kBilinear, search::Method::parse("newton:10"));
  const Estimates e = run_on_set(newton, s, 0);
  const MethodErrors m = compare_with_labels("newton:10", e, s, 0.5, false);
  EXPECT_EQ(m.failures_method, 0);
  EXPECT_LT(m.stats[0].max_abs, 1e-10);
  EXPECT_LT(m.stats[1].max_abs, 1e-10);
  EXPECT_LT(m.gap_relative.max_abs, 1e-10);
  EXPECT_EQ(m.inside_agree, m.inside_compared);
  // The same with one thread: lib/search's answers do not depend on the thread count.
  const Estimates one = run_on_set(newton, s, 1);
  EXPECT_EQ(one.param, e.param);
}

TEST(StartsNearReference, MoveEachReferencePointByTheOffsetAndGiveTheCentreWithoutOne) {
  EvaluationSet s = synthetic_set(200);
  s.label_status[3] = Status::kNoConvergence;
  s.label_status[4] = Status::kOutside;
  const std::vector<double> a = starts_near_reference(s, 0.01, 7);
  ASSERT_EQ(a.size(), 400u);
  double sum_du = 0.0, sum_dv = 0.0;
  for (std::size_t r = 0; r < 200; ++r) {
    const double du = a[2 * r] - s.labels(static_cast<Eigen::Index>(r), 0);
    const double dv = a[2 * r + 1] - s.labels(static_cast<Eigen::Index>(r), 1);
    if (r == 3) {  // no reference point: the centre
      EXPECT_EQ(a[2 * r], 0.0);
      EXPECT_EQ(a[2 * r + 1], 0.0);
      continue;
    }
    EXPECT_NEAR(std::hypot(du, dv), 0.01, 1e-13) << "row " << r;  // labels up to 20: rounding 4e-15
    sum_du += du;
    sum_dv += dv;
  }
  // Directions spread around the circle (a fixed direction would sum to about 2).
  EXPECT_LT(std::abs(sum_du) + std::abs(sum_dv), 0.5);
  // The seed decides: the same starts again, others with another seed; offset 0 is the reference itself.
  EXPECT_EQ(starts_near_reference(s, 0.01, 7), a);
  EXPECT_NE(starts_near_reference(s, 0.01, 8), a);
  const std::vector<double> zero = starts_near_reference(s, 0.0, 7);
  EXPECT_EQ(zero[2 * 10], s.labels(10, 0));
  EXPECT_EQ(zero[2 * 10 + 1], s.labels(10, 1));
}

TEST(RunOnSet, StartPlusNewtonStartsFromTheGivenStarts) {
  const EvaluationSet s = well_shaped_set();
  const std::vector<double> start = starts_near_reference(s, 0.02, 1);
  const Estimates alone =
      run_on_set(search::LocalSearch(SurfaceKind::kBilinear, search::Method::parse("start")), s, 0, &start);
  EXPECT_EQ(alone.param, start);  // the start itself
  const Estimates refined = run_on_set(
      search::LocalSearch(SurfaceKind::kBilinear, search::Method::parse("start+newton:3")), s, 0, &start);
  const MethodErrors m = compare_with_labels("start+newton:3", refined, s, 0.5, false);
  EXPECT_EQ(m.failures_method, 0);
  EXPECT_LT(m.stats[0].max_abs, 1e-10);
  EXPECT_LT(m.stats[1].max_abs, 1e-10);
  // One value per row is not a start per row.
  const auto too_few = [&] {
    return run_on_set(search::LocalSearch(SurfaceKind::kBilinear, search::Method::parse("start")), s, 0,
                      &alone.gap);
  };
  EXPECT_THROW((void)too_few(), InvalidArgument);
}

TEST(CountValues, LastBinTakesTheRestNegativesAreSkipped) {
  EXPECT_EQ(count_values({0, 3, 3, 5, 99, -1, 4}, 5), (std::vector<std::int64_t>{1, 0, 0, 2, 3}));
}

}  // namespace
}  // namespace contactnn::eval
