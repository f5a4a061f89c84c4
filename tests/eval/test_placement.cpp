// Tests of lib/eval/placement: world coordinates for the evaluation.
#include <gtest/gtest.h>

#include "eval/placement.hpp"
#include "geometry/affine_frame.hpp"

namespace contactnn::eval {
namespace {

// Features of a mildly warped bilinear configuration well inside the paper's domain (canonical: z_S > 0).
constexpr std::array<double, 16> kFeatures = {1.1, 0.9, 0.12, -0.1, 0.95, 0.3, 0.4, 0.2,
                                              0,   0,   0,    0,    0,    0,   0,   0};
// Rounding of a similarity map with scale up to 1e2 and translation up to 1e3: ~1e-13 relative in the frame.
constexpr double kPlacementTol = 1e-11;

TEST(Placement, FeaturesRoundTripThroughAnyPlacement) {
  const geometry::Configuration local = configuration_from_features(SurfaceKind::kBilinear, kFeatures.data());
  for (std::uint64_t row = 0; row < 20; ++row) {
    const Placement p = random_placement(7, row);
    EXPECT_NEAR(p.rotation.determinant(), 1.0, 1e-14);
    EXPECT_NEAR((p.rotation.transpose() * p.rotation - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-14);
    const geometry::NormaliseOutcome n = geometry::normalise(place(local, p), SurfaceKind::kBilinear);
    ASSERT_TRUE(n.value);
    for (int f = 0; f < 8; ++f) {
      EXPECT_NEAR(n.value->features[static_cast<std::size_t>(f)], kFeatures[static_cast<std::size_t>(f)],
                  kPlacementTol)
          << "row " << row << " feature " << f;
    }
  }
  // A pure function of (seed, index).
  EXPECT_EQ(random_placement(7, 3).translation, random_placement(7, 3).translation);
  EXPECT_NE(random_placement(7, 3).translation, random_placement(7, 4).translation);
}

TEST(Placement, GregoryNormalsComeBackFromTheirFeatures) {
  std::array<double, 16> f = kFeatures;
  const std::array<double, 8> pq = {0.05, -0.1, 0.0, 0.12, -0.08, 0.02, 0.1, 0.1};
  for (int i = 0; i < 8; ++i) f[static_cast<std::size_t>(8 + i)] = pq[static_cast<std::size_t>(i)];
  const geometry::Configuration c = configuration_from_features(SurfaceKind::kGregory, f.data());
  const geometry::NormaliseOutcome n =
      geometry::normalise(place(c, random_placement(1, 0)), SurfaceKind::kGregory);
  ASSERT_TRUE(n.value);
  for (int i = 8; i < 16; ++i) {
    EXPECT_NEAR(n.value->features[static_cast<std::size_t>(i)], f[static_cast<std::size_t>(i)],
                kPlacementTol);
  }
}

}  // namespace
}  // namespace contactnn::eval
