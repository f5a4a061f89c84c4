// Tests of lib/dataset/sampling: random configurations of the paper's domains.
#include <gtest/gtest.h>
#include <omp.h>

#include "dataset/labeller.hpp"
#include "dataset/sampling.hpp"

namespace contactnn::dataset {
namespace {

EnumerationOptions paper(SurfaceKind kind) {
  EnumerationOptions o;
  o.surface = kind;
  if (kind == SurfaceKind::kGregory) {
    o.filters.min_angle_degrees = 60.0;
    o.filters.max_angle_degrees = 120.0;
  }
  o.seed = 5;
  return o;
}

TEST(Sampling, EveryRowIsInTheDomainInsideTheSegmentAndCanonical) {
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    const EnumerationOptions o = paper(kind);
    EnumerationSummary summary;
    const LabelledSet set = sample_configurations(o, 400, summary);
    ASSERT_EQ(set.size(), 400);
    EXPECT_EQ(summary.kept, 400);
    EXPECT_GT(summary.grid_points, summary.geometric_kept);  // the filters rejected something
    for (Eigen::Index r = 0; r < set.size(); ++r) {
      ASSERT_EQ(set.status[static_cast<std::size_t>(r)], Status::kOk);
      const geometry::Configuration c = [&] {
        geometry::Configuration x{};
        x.nodes[1] = geometry::Vec3(1, 0, 0);
        x.nodes[2] = geometry::Vec3(set.features(r, 0), set.features(r, 1), set.features(r, 2));
        x.nodes[3] = geometry::Vec3(set.features(r, 3), set.features(r, 4), 0);
        x.slave = geometry::Vec3(set.features(r, 5), set.features(r, 6), set.features(r, 7));
        return x;
      }();
      EXPECT_TRUE(o.filters.accepts(c, SurfaceKind::kBilinear, 1e-9)) << "row " << r;
      EXPECT_GE(set.features(r, 7), 0.0) << "z_S of the canonical frame";
      const ParamDomain d = param_domain(kind);
      for (int k = 0; k < 2; ++k) {
        EXPECT_GE(set.labels(r, k), d.lo - 1e-10);
        EXPECT_LE(set.labels(r, k), d.hi + 1e-10);
      }
    }
  }
}

TEST(Sampling, SameSetForAnyThreadCountAndAnotherForAnotherSeed) {
  EnumerationOptions o = paper(SurfaceKind::kGregory);
  EnumerationSummary s1, s2, s3;
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const LabelledSet one = sample_configurations(o, 300, s1);
  omp_set_num_threads(3);
  const LabelledSet three = sample_configurations(o, 300, s2);
  omp_set_num_threads(threads);
  EXPECT_EQ(one.features, three.features);
  EXPECT_EQ(one.labels, three.labels);
  EXPECT_EQ(s1.grid_points, s2.grid_points);
  o.seed = 6;
  const LabelledSet other = sample_configurations(o, 300, s3);
  EXPECT_NE(other.features(0, 0), one.features(0, 0));
}

/// Mean and variance of x over n draws.
struct Moments {
  double n = 0, sum = 0, sum2 = 0;
  void add(double x) {
    n += 1;
    sum += x;
    sum2 += x * x;
  }
  [[nodiscard]] double mean() const { return sum / n; }
  [[nodiscard]] double variance() const { return sum2 / n - mean() * mean(); }
};

TEST(Sampling, ShrunkProposalBoxesKeepTheDensityUniform) {
  // The sampler draws D, S from boxes shrunk to what the filters allow; a plain rejection sampler from the
  // full boxes (written here independently) must give the same distribution. Compared by the first two
  // moments of x_D, |D|^2, x_S, y_S, x_C over 20000 accepted draws each: standard errors are below 0.01, the
  // tolerance is 6 of them (fixed seeds: not flaky).
  const EnumerationOptions o = paper(SurfaceKind::kBilinear);
  constexpr int kDraws = 20000;
  constexpr double kTol = 0.06;
  std::array<Moments, 5> fast, plain;
  const auto add = [](std::array<Moments, 5>& m, const geometry::Configuration& c) {
    m[0].add(c.nodes[3].x());
    m[1].add(c.nodes[3].squaredNorm());
    m[2].add(c.slave.x());
    m[3].add(c.slave.y());
    m[4].add(c.nodes[2].x());
  };
  RandomStream a(11, 0), b(12, 0);
  for (int accepted = 0; accepted < kDraws;) {
    if (const auto c = draw_candidate(o, a)) {
      add(fast, *c);
      ++accepted;
    }
  }
  for (int accepted = 0; accepted < kDraws;) {
    geometry::Configuration c{};
    c.nodes[0] = geometry::Vec3::Zero();  // Eigen's vectors are not zeroed by {}
    c.nodes[1] = geometry::Vec3(1, 0, 0);
    c.nodes[3] = geometry::Vec3(b.uniform(-2, 2), b.uniform(0, 2), 0);
    c.slave = geometry::Vec3(b.uniform(-2, 2), b.uniform(-2, 2), b.uniform(-0.3, 0.3));
    c.nodes[2] = geometry::Vec3(b.uniform(-2, 2), b.uniform(-2, 2), b.uniform(-0.3, 0.3));
    if (!o.filters.accepts(c, SurfaceKind::kBilinear)) continue;
    add(plain, c);
    ++accepted;
  }
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(fast[k].mean(), plain[k].mean(), kTol) << "moment set " << k;
    EXPECT_NEAR(std::sqrt(fast[k].variance()), std::sqrt(plain[k].variance()), kTol) << "moment set " << k;
  }
}

}  // namespace
}  // namespace contactnn::dataset
