#include "geometry/affine_frame.hpp"

#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"

namespace contactnn::geometry {
namespace {

// The translation below is up to ~2e4 element sizes: inputs carry rounding of 2e4 * 1e-16 relative to
// the element, which no normalisation can undo.
constexpr double kRoundTripTol = 1e-10;

TEST(AffineFrame, MapsAToOriginBToUnitXAndDIntoUpperXyPlane) {
  std::mt19937_64 rng(11);
  for (int k = 0; k < 100; ++k) {
    const Configuration local = testing::random_paper_configuration(rng);
    const double scale = std::exp(std::uniform_real_distribution<double>(-5, 5)(rng));
    const Configuration world = testing::transform(local, testing::random_rotation(rng), scale, Vec3(3, -100, 7));
    const auto frame = AffineFrame::from_nodes(world.nodes[0], world.nodes[1], world.nodes[3]);
    ASSERT_TRUE(frame.has_value());
    EXPECT_LT(frame->to_normalised(world.nodes[0]).norm(), kRoundTripTol * 100);
    EXPECT_LT((frame->to_normalised(world.nodes[1]) - Vec3(1, 0, 0)).norm(), kRoundTripTol);
    const Vec3 d = frame->to_normalised(world.nodes[3]);
    EXPECT_NEAR(d.z(), 0.0, kRoundTripTol);
    EXPECT_GT(d.y(), 0.0);
    EXPECT_NEAR(frame->rotation().determinant(), 1.0, 1e-14);  // proper: the normal side is kept
    // The map recovers the configuration it came from (same frame convention both ways).
    for (int i = 0; i < 4; ++i) EXPECT_LT((frame->to_normalised(world.nodes[i]) - local.nodes[i]).norm(), kRoundTripTol);
    EXPECT_LT((frame->to_normalised(world.slave) - local.slave).norm(), kRoundTripTol);
    EXPECT_LT((frame->to_world(frame->to_normalised(world.slave)) - world.slave).norm(), kRoundTripTol * scale * 100);
  }
}

TEST(AffineFrame, FeaturesAreTheEightCoordinatesOfSpecSection4) {
  const Configuration c{{Vec3(1, 1, 1), Vec3(3, 1, 1), Vec3(3.2, 2.8, 1.4), Vec3(0.8, 2.6, 1)}, Vec3(1.4, 1.6, 0.8), {}};
  const auto n = normalise(c, SurfaceKind::kBilinear);
  ASSERT_TRUE(n.value.has_value());
  // AB = (2,0,0): scale 1/2, no rotation needed. Expected values worked out by hand.
  const std::array<double, 8> expected = {1.1, 0.9, 0.2, -0.1, 0.8, 0.2, 0.3, -0.1};
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(n.value->features[i], expected[i], 1e-15) << kFeatureNames[i];
  EXPECT_DOUBLE_EQ(n.value->frame.scale(), 0.5);
}

TEST(AffineFrame, DoesNotExistForCoincidentOrCollinearNodesOrNonFiniteInput) {
  EXPECT_FALSE(AffineFrame::from_nodes(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(0, 1, 0)).has_value());
  EXPECT_FALSE(AffineFrame::from_nodes(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0)).has_value());
  EXPECT_FALSE(AffineFrame::from_nodes(Vec3(0, 0, 0), Vec3(NAN, 0, 0), Vec3(0, 1, 0)).has_value());
  Configuration bad{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, Vec3(INFINITY, 0, 0), {}};
  EXPECT_EQ(normalise(bad, SurfaceKind::kBilinear).failure, NormaliseFailure::kNonFinite);
  bad.slave = Vec3(0.5, 0.5, 1);
  bad.nodes[3] = Vec3(2, 0, 0);  // D on the line AB
  const auto outcome = normalise(bad, SurfaceKind::kBilinear);
  EXPECT_FALSE(outcome.value.has_value());
  EXPECT_EQ(outcome.failure, NormaliseFailure::kDegenerate);
}

TEST(AffineFrame, GregoryNormalsEnterAsSlopesAndMustFaceTheSegment) {
  Configuration c{{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0)}, Vec3(1, 1, 1), {}};
  for (auto& n : c.normals) n = Vec3(0, 0, 5);  // any positive length
  c.normals[2] = Vec3(0.1, -0.2, 1.0);
  const auto n = normalise(c, SurfaceKind::kGregory);
  ASSERT_TRUE(n.value.has_value());
  EXPECT_DOUBLE_EQ(n.value->features[8], 0.0);
  EXPECT_NEAR(n.value->features[12], 0.1, 1e-15);   // n_x / n_z at C
  EXPECT_NEAR(n.value->features[13], -0.2, 1e-15);  // n_y / n_z at C
  c.normals[1] = Vec3(1, 0, 0);  // in the segment plane: no slope exists
  EXPECT_FALSE(normalise(c, SurfaceKind::kGregory).value.has_value());
}

}  // namespace
}  // namespace contactnn::geometry
