#include <gtest/gtest.h>
#include <omp.h>

#include "dataset/enumeration.hpp"
#include "geometry/affine_frame.hpp"
#include "geometry/bilinear_patch.hpp"
#include "test_support.hpp"

namespace contactnn::dataset {
namespace {

EnumerationOptions small_grid() {
  EnumerationOptions o;
  o.d_xy_points = 8;
  o.c_xy_points = 8;
  o.c_z_points = 3;
  o.s_xy_points = 10;
  o.s_z_points = 3;
  return o;
}

geometry::Configuration row_configuration(const LabelledSet& set, Eigen::Index i) {
  const auto f = set.features.row(i);
  return {{geometry::Vec3::Zero(), geometry::Vec3(1, 0, 0), geometry::Vec3(f[0], f[1], f[2]),
           geometry::Vec3(f[3], f[4], 0)},
          geometry::Vec3(f[5], f[6], f[7]),
          {}};
}

TEST(Enumeration, GridValuesAreSymmetricCellCentresInsideTheOpenInterval) {
  const auto v = grid_values(2.0, 20);
  ASSERT_EQ(v.size(), 20u);
  EXPECT_DOUBLE_EQ(v.front(), -1.9);
  EXPECT_DOUBLE_EQ(v.back(), 1.9);
  for (std::size_t k = 0; k < v.size(); ++k) EXPECT_EQ(v[k], -v[v.size() - 1 - k]);
  EXPECT_EQ(grid_values(0.3, 5)[2], 0.0);  // an odd grid holds z = 0 exactly
}

TEST(Enumeration, EveryRowPassesTheFiltersAndCarriesItsOwnLabel) {
  EnumerationSummary summary;
  const LabelledSet set = enumerate_configurations(small_grid(), summary);
  ASSERT_GT(set.size(), 100);
  EXPECT_EQ(summary.kept, set.size());
  std::int64_t labelled = 0;
  for (auto c : summary.status_counts) labelled += c;
  EXPECT_EQ(labelled, summary.geometric_kept);  // every candidate is counted under exactly one status
  for (Eigen::Index i = 0; i < set.size(); ++i) {
    const geometry::Configuration c = row_configuration(set, i);
    ASSERT_TRUE(set.filters.accepts(c, SurfaceKind::kBilinear)) << i;
    ASSERT_EQ(set.status[static_cast<std::size_t>(i)], Status::kOk);
    EXPECT_LE(std::abs(set.labels(i, 0)), 1.0 + 1e-10);
    EXPECT_LE(std::abs(set.labels(i, 1)), 1.0 + 1e-10);
    // The stored label is the projection of the stored inputs (re-projected independently of the grid).
    if (i % 37 == 0) {
      const geometry::BilinearPatch p(c.nodes);
      const auto oracle = testing::oracle_closest_point(p, c.slave, 201);
      if (std::abs(oracle[0]) < 1 - 1e-6 && std::abs(oracle[1]) < 1 - 1e-6) {
        EXPECT_NEAR(set.labels(i, 0), oracle[0], 1e-9) << i;
        EXPECT_NEAR(set.labels(i, 1), oracle[1], 1e-9) << i;
      }
    }
  }
}

TEST(Enumeration, ResultIsIdenticalForAnyThreadCount) {
  EnumerationSummary s1, s2;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const LabelledSet one = enumerate_configurations(small_grid(), s1);
  omp_set_num_threads(3);  // more threads than cores still splits the work differently
  const LabelledSet three = enumerate_configurations(small_grid(), s2);
  omp_set_num_threads(saved);
  ASSERT_EQ(one.size(), three.size());
  EXPECT_TRUE(one.features == three.features);
  EXPECT_TRUE(one.labels == three.labels);
  EXPECT_TRUE(one.gap == three.gap);
  EXPECT_TRUE(one.iterations == three.iterations);
  EXPECT_EQ(s1.status_counts, s2.status_counts);
}

TEST(Enumeration, DroppingTheInsideFilterKeepsEveryGeometricCandidate) {
  EnumerationOptions o = small_grid();
  o.require_projection_inside = false;
  EnumerationSummary summary;
  const LabelledSet set = enumerate_configurations(o, summary);
  EXPECT_EQ(set.size(), summary.geometric_kept);
  EXPECT_GT(summary.status_counts[static_cast<std::size_t>(Status::kOutside)], 0);
}

}  // namespace
}  // namespace contactnn::dataset

namespace contactnn::dataset {
namespace {

TEST(TrainingDomain, GridCellsCoverTheirHalfStepSoASquareSegmentIsInside) {
  EnumerationSummary summary;
  const LabelledSet set = enumerate_configurations(small_grid(), summary);
  const geometry::TrainingDomain domain = geometry::TrainingDomain::from_features(
      set.surface, set.features.data(), static_cast<long>(set.size()), set.status, set.filters);
  // y_D takes the values 0.25, 0.75 (8 points over (-2, 2), |AD| <= 1): widened by half the step, 0.25.
  EXPECT_NEAR(domain.feature_max[4], 1.0, 1e-12);
  EXPECT_NEAR(domain.feature_min[4], 0.0, 1e-12);
  const geometry::Configuration square{
      {geometry::Vec3::Zero(), geometry::Vec3(1, 0, 0), geometry::Vec3(1, 1, 0), geometry::Vec3(0, 1, 0)},
      geometry::Vec3(0.25, 0.3, 0.2),
      {}};
  const auto n = geometry::normalise(square, SurfaceKind::kBilinear);
  ASSERT_TRUE(n.value.has_value());
  EXPECT_TRUE(domain.contains(n.value->config, n.value->features.data()));
  geometry::Configuration far = square;
  far.slave = geometry::Vec3(0.25, 0.3, 0.5);  // z_S beyond the study's 0.3
  const auto nf = geometry::normalise(far, SurfaceKind::kBilinear);
  EXPECT_FALSE(domain.contains(nf.value->config, nf.value->features.data()));
}

TEST(TrainingDomain, ConfigurationsOnAFilterBoundaryStayInsideAfterAnyPlacement) {
  // S equidistant from A and B (a tie the grid produces); A, D and C on one line (a 180-degree corner at D,
  // rows 59827.. of the bilinear set). The domain must accept them after the rounding of any placement.
  const std::array<geometry::Configuration, 2> boundary = {
      geometry::Configuration{{geometry::Vec3::Zero(), geometry::Vec3(1, 0, 0), geometry::Vec3(0.9, 0.7, 0.1),
                               geometry::Vec3(-0.1, 0.7, 0)},
                              geometry::Vec3(0.5, 0.1, 0.1),
                              {}},
      geometry::Configuration{{geometry::Vec3::Zero(), geometry::Vec3(1, 0, 0), geometry::Vec3(-1.5, 0.5, 0),
                               geometry::Vec3(-0.9, 0.3, 0)},
                              geometry::Vec3(-0.3, 0.1, -0.24),
                              {}}};
  geometry::TrainingDomain domain;
  domain.feature_min.assign(8, -2.0);
  domain.feature_max.assign(8, 2.0);
  std::mt19937_64 rng(53);
  for (const auto& config : boundary) {
    for (int k = 0; k < 200; ++k) {
      const double scale = std::pow(10.0, std::uniform_real_distribution<double>(-3, 3)(rng));
      const auto world = testing::transform(config, testing::random_rotation(rng), scale,
                                            scale * geometry::Vec3(30, -70, 11));
      const auto n = geometry::normalise(world, SurfaceKind::kBilinear);
      ASSERT_TRUE(n.value.has_value());
      EXPECT_TRUE(domain.contains(n.value->config, n.value->features.data())) << k;
    }
  }
}

}  // namespace
}  // namespace contactnn::dataset
