#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "geometry/affine_frame.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/segment_checks.hpp"
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
    const Configuration world =
        testing::transform(local, testing::random_rotation(rng), scale, Vec3(3, -100, 7));
    const auto frame = AffineFrame::from_nodes(world.nodes[0], world.nodes[1], world.nodes[3]);
    ASSERT_TRUE(frame.has_value());
    EXPECT_LT(frame->to_normalised(world.nodes[0]).norm(), kRoundTripTol * 100);
    EXPECT_LT((frame->to_normalised(world.nodes[1]) - Vec3(1, 0, 0)).norm(), kRoundTripTol);
    const Vec3 d = frame->to_normalised(world.nodes[3]);
    EXPECT_NEAR(d.z(), 0.0, kRoundTripTol);
    EXPECT_GT(d.y(), 0.0);
    EXPECT_NEAR(frame->rotation().determinant(), 1.0, 1e-14);  // proper: the normal side is kept
    // The map recovers the configuration it came from (same frame convention both ways).
    for (int i = 0; i < 4; ++i)
      EXPECT_LT((frame->to_normalised(world.nodes[i]) - local.nodes[i]).norm(), kRoundTripTol);
    EXPECT_LT((frame->to_normalised(world.slave) - local.slave).norm(), kRoundTripTol);
    EXPECT_LT((frame->to_world(frame->to_normalised(world.slave)) - world.slave).norm(),
              kRoundTripTol * scale * 100);
  }
}

TEST(AffineFrame, FeaturesAreTheEightCoordinatesOfSpecSection4) {
  const Configuration c{
      {Vec3(1, 1, 1), Vec3(3, 1, 1), Vec3(3.2, 2.8, 1.4), Vec3(0.8, 2.6, 1)}, Vec3(1.4, 1.6, 0.8), {}};
  const auto n = normalise(c, SurfaceKind::kBilinear);
  ASSERT_TRUE(n.value.has_value());
  // A is the node nearest S and |AD| < |AB|: no relabelling. AB = (2,0,0): scale 1/2, no rotation; S lies
  // below the plane (z = -0.1), so the canonical z axis points down (z_S >= 0) and z_C changes sign.
  // Expected values worked out by hand.
  const std::array<double, 8> expected = {1.1, 0.9, -0.2, -0.1, 0.8, 0.2, 0.3, 0.1};
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(n.value->features[i], expected[i], 1e-15) << kFeatureNames[i];
  EXPECT_DOUBLE_EQ(n.value->frame.scale(), 0.5);
  EXPECT_EQ(n.value->symmetry, (SquareSymmetry{0, false}));
  EXPECT_EQ(n.value->orientation, -1.0);  // the reflected frame: the caller's normal is the frame's -z
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
  c.normals[1] = Vec3(1, 0, 0);                     // in the segment plane: no slope exists
  EXPECT_FALSE(normalise(c, SurfaceKind::kGregory).value.has_value());
}

// ---- The canonical configuration (SPEC 4) ----

using testing::relabel;

/// A segment and slave placed anywhere in a box around it: A is not the nearest node, |AD| > |AB| half the
/// time.
Configuration random_world_configuration(std::mt19937_64& rng, bool gregory) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Configuration local{
      {Vec3(0, 0, 0), Vec3(1 + 0.5 * u(rng), 0.1 * u(rng), 0.1 * u(rng)),
       Vec3(1 + 0.4 * u(rng), 1 + 0.4 * u(rng), 0.2 * u(rng)), Vec3(0.1 * u(rng), 1 + 0.5 * u(rng), 0)},
      Vec3(0.5 + 0.8 * u(rng), 0.5 + 0.8 * u(rng), 0.4 * u(rng)),
      {}};
  for (auto& n : local.normals) n = Vec3(0.15 * u(rng), 0.15 * u(rng), 1.0) * (1.5 + u(rng));
  (void)gregory;
  return testing::transform(local, testing::random_rotation(rng), std::exp(3 * u(rng)),
                            Vec3(u(rng), u(rng), u(rng)) * 50);
}

/// check(kind, world, its normalised form) for `count` random world configurations of each surface kind.
template <class Check>
void for_random_worlds(std::uint64_t seed, int count, const Check& check) {
  std::mt19937_64 rng(seed);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    for (int k = 0; k < count; ++k) {
      const Configuration world = random_world_configuration(rng, kind == SurfaceKind::kGregory);
      const auto base = normalise(world, kind);
      ASSERT_TRUE(base.value);
      check(kind, world, base, rng);
    }
  }
}

TEST(CanonicalConfiguration, EveryNodeOrderReachesTheSameFeaturesBitForBit) {
  for_random_worlds(41, 200, [](SurfaceKind kind, const Configuration& world, const auto& base, auto&) {
    for (const SquareSymmetry& order : all_square_symmetries()) {
      const auto other = normalise(relabel(world, order), kind);
      ASSERT_TRUE(other.value);
      EXPECT_EQ(other.value->features, base.value->features) << "order " << order.rotation << order.mirror;
      // A relabelling that reverses the node order reverses the caller's normal, hence its gap sign.
      EXPECT_EQ(other.value->orientation, base.value->orientation * order.orientation());
    }
  });
}

TEST(CanonicalConfiguration, OrdersReflectedThroughSpaceAgreeToRounding) {
  // The mirror of SPEC 4 as a caller may present it: the node order A, D, C, B of a reflected copy of space,
  // which keeps the front side. Same problem, same features up to the rounding of the reflection.
  for_random_worlds(42, 100, [](SurfaceKind kind, const Configuration& world, const auto& base, auto& rng) {
    const Vec3 plane = testing::random_rotation(rng).col(0);
    const Eigen::Matrix3d reflection = Eigen::Matrix3d::Identity() - 2.0 * plane * plane.transpose();
    Configuration reflected = testing::transform(world, reflection, 1.0, Vec3(3, -2, 1));
    for (const SquareSymmetry& order : all_square_symmetries()) {
      const auto other = normalise(relabel(reflected, order), kind);
      ASSERT_TRUE(other.value);
      for (int f = 0; f < feature_count(kind); ++f) {
        EXPECT_NEAR(other.value->features[f], base.value->features[f], kRoundTripTol) << kFeatureNames[f];
      }
    }
  });
}

TEST(CanonicalConfiguration, IsThePapersForm) {
  // A is the node nearest S, |AD| <= |AB| = 1, and (our orientation) z_S >= 0: the domain of the paper's
  // study.
  std::mt19937_64 rng(43);
  for (int k = 0; k < 500; ++k) {
    const Configuration world = random_world_configuration(rng, false);
    const auto n = normalise(world, SurfaceKind::kBilinear);
    ASSERT_TRUE(n.value);
    const Configuration& c = n.value->config;
    EXPECT_TRUE(first_node_is_nearest(c.nodes, c.slave, 1e-12));
    EXPECT_LE(c.nodes[3].squaredNorm(), 1.0 + 1e-12);
    EXPECT_GE(c.slave.z(), 0.0);
    EXPECT_GT(c.nodes[3].y(), 0.0);
  }
}

TEST(CanonicalConfiguration, CanonicalCoordinatesNameTheSamePointInTheCallersOrder) {
  std::mt19937_64 rng(44);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int k = 0; k < 200; ++k) {
    const Configuration world = random_world_configuration(rng, false);
    const auto n = normalise(world, SurfaceKind::kBilinear);
    ASSERT_TRUE(n.value);
    std::array<Vec3, 4> canonical_nodes;
    for (int i = 0; i < 4; ++i) canonical_nodes[i] = world.nodes[n.value->symmetry.caller_node(i)];
    const BilinearPatch canonical(canonical_nodes), caller(world.nodes);
    const std::array<double, 2> st = {u(rng), u(rng)};
    const auto xi_eta = n.value->to_caller(st, SurfaceKind::kBilinear);
    const double size = (world.nodes[1] - world.nodes[0]).norm();
    EXPECT_LT((canonical.position(st[0], st[1]) - caller.position(xi_eta[0], xi_eta[1])).norm(),
              1e-13 * size * 100);
  }
}

TEST(CanonicalConfiguration, ExactTieOfEdgeLengthsIsBrokenTheSameWayInEveryOrder) {
  // A rhombus: |AB| = |AD| exactly. SPEC 4 mirrors only for |AD| > |AB|; the tie is broken by the side of the
  // diagonal S lies on, so all 8 orders still agree.
  // |AB| = |AD| = 5 exactly in binary.
  for (const Vec3& slave : {Vec3(2, 0.5, 0.4), Vec3(1, 1.5, 0.2)}) {  // nearer AB; nearer AD (then mirrored)
    const Configuration rhombus{{Vec3(0, 0, 0), Vec3(5, 0, 0), Vec3(8, 4, 0.3), Vec3(3, 4, 0)}, slave, {}};
    const auto base = normalise(rhombus, SurfaceKind::kBilinear);
    ASSERT_TRUE(base.value);
    EXPECT_EQ(base.value->symmetry.mirror, slave.y() > 1.0);
    for (const SquareSymmetry& order : all_square_symmetries()) {
      EXPECT_EQ(normalise(relabel(rhombus, order), SurfaceKind::kBilinear).value->features,
                base.value->features);
    }
  }
}

TEST(CanonicalConfiguration, SymmetriesAreTheSameAtEveryScaleDownTo1eMinus300AndUpTo1e300) {
  // The choice of node order must not depend on the unit of the coordinates. Near 1e+-300 the squares in the
  // distances and in the |AB| = |AD| test under- or overflow unless the configuration is scaled first: a kite
  // of 0.1 degrees got the other mirror at 1e-300, and coordinates of 1e308 had no nearest node.
  const double t = 0.1 * std::numbers::pi / 180.0;
  const std::array<Vec3, 4> none = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  const std::vector<Configuration> cases = {
      {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.3 * std::cos(t / 2), 1.3 * std::sin(t / 2), 0),
        Vec3(std::cos(t), std::sin(t), 0)},
       Vec3(0.2, 0.01, 0.01),
       none},                                                                                     // thin kite
      {{Vec3(0, 0, 0), Vec3(5, 0, 0), Vec3(8, 4, 0.3), Vec3(3, 4, 0)}, Vec3(1, 1.5, 0.2), none},  // rhombus
      {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0.1), Vec3(0, 1, 0)},
       Vec3(0.3, 0.3, 0.2),
       none},                                                                                     // diagonal
      {{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)}, Vec3(1, 0.3, 0.1), none},    // A and B
      {{Vec3(1, 1, 1), Vec3(3, 1, 2), Vec3(3, 4, 1), Vec3(0, 3, 1)}, Vec3(2.5, 3.2, 1.7), none},  // plain
  };
  for (const Configuration& unit : cases) {
    const CanonicalSymmetries base = canonical_symmetries(unit.nodes, unit.slave);
    ASSERT_GE(base.count, 1);
    for (const double scale : {0x1p-1000, 1e-300, 1e-150, 1e150, 1e300, 0x1p1020}) {
      Configuration c = unit;
      for (Vec3& x : c.nodes) x *= scale;
      c.slave *= scale;
      const CanonicalSymmetries got = canonical_symmetries(c.nodes, c.slave);
      ASSERT_EQ(got.count, base.count) << "scale " << scale;
      for (int k = 0; k < got.count; ++k)
        EXPECT_EQ(got.symmetries[k], base.symmetries[k]) << "scale " << scale;
    }
  }
  // Coordinates whose differences overflow: a nearest node is still found (the frame then does not exist).
  const Configuration huge{
      {Vec3(-1.5e308, 0, 0), Vec3(1.5e308, 0, 0), Vec3(1.5e308, 1.5e308, 0), Vec3(-1.5e308, 1.5e308, 0)},
      Vec3(-1e308, 1e307, 1e307),
      none};
  const CanonicalSymmetries far = canonical_symmetries(huge.nodes, huge.slave);
  ASSERT_EQ(far.count, 1);
  EXPECT_EQ(far.symmetries[0].rotation, 0);
  EXPECT_FALSE(normalise(huge, SurfaceKind::kBilinear).value);
}

TEST(CanonicalConfiguration, TiesGiveEveryCanonicalFormTheSameSetInEveryOrder) {
  // A 2 x 1 rectangle: S over the midpoint of AD is as near A as D (2 forms); over the centre of a unit
  // square it is as near all four nodes, each with |AB| = |AD| and S on the diagonal (8 forms).
  const std::array<Vec3, 4> none = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  const Configuration strip{
      {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)}, Vec3(0, 0.5, 0.1), none};
  const Configuration square{
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, Vec3(0.5, 0.5, 0.1), none};
  const std::vector<std::pair<Configuration, int>> cases = {{strip, 2}, {square, 8}};
  for (const auto& [c, expected] : cases) {
    const CanonicalForms base = canonical_forms(c, SurfaceKind::kBilinear);
    ASSERT_EQ(base.count, expected);
    EXPECT_EQ(base.form[0].features, normalise(c, SurfaceKind::kBilinear).value->features);  // SPEC 4's first
    std::vector<std::array<double, 16>> reference;
    for (int k = 0; k < base.count; ++k) reference.push_back(base.form[k].features);
    std::sort(reference.begin(), reference.end());
    for (const SquareSymmetry& order : all_square_symmetries()) {
      const CanonicalForms other = canonical_forms(relabel(c, order), SurfaceKind::kBilinear);
      std::vector<std::array<double, 16>> got;
      for (int k = 0; k < other.count; ++k) got.push_back(other.form[k].features);
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, reference) << "order " << order.rotation << order.mirror;
    }
  }
  // No tie: one form.
  const Configuration plain{
      {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)}, Vec3(0.3, 0.2, 0.1), {}};
  EXPECT_EQ(canonical_forms(plain, SurfaceKind::kBilinear).count, 1);
}

TEST(CanonicalConfiguration, SlaveOnAFlatMasterIsOrientedTheSameWhereverPlaced) {
  // S in the plane of a flat segment: its height is rounding after any placement, and must not orient z.
  std::mt19937_64 rng(46);
  Configuration c{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.1, 0.9, 0), Vec3(0, 0.8, 0)}, Vec3(0.3, 0.2, 0), {}};
  for (auto& n : c.normals) n = Vec3(0.05, -0.03, 1);
  c.normals[2] = Vec3(-0.1, 0.02, 1);
  const auto base = canonical_forms(c, SurfaceKind::kGregory);
  ASSERT_EQ(base.count, 2);  // z_S = z_C = 0: both orientations (the slopes differ)
  for (int k = 0; k < 20; ++k) {
    const Configuration placed = testing::transform(c, testing::random_rotation(rng), 3.0, Vec3(10, -4, 7));
    const auto forms = canonical_forms(placed, SurfaceKind::kGregory);
    ASSERT_EQ(forms.count, 2);
    for (int f = 0; f < 16; ++f) EXPECT_NEAR(forms.form[0].features[f], base.form[0].features[f], 1e-12);
  }
}

TEST(CanonicalConfiguration, StraightAngleAtTheCanonicalCornerTakesAnotherCorner) {
  // B is nearest S, and A, B, C are collinear: no frame at B. The segment (a triangle) is still usable.
  const Configuration c{
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)}, Vec3(0.9, 0.3, 0.2), {}};
  EXPECT_EQ(canonical_symmetry(c.nodes, c.slave).rotation, 1);
  const auto n = normalise(c, SurfaceKind::kBilinear);
  ASSERT_TRUE(n.value);
  EXPECT_FALSE(n.value->canonical);
  EXPECT_NE(n.value->symmetry.rotation, 1);
}

TEST(CanonicalConfiguration, GregoryNormalsAllReversedGiveTheSamePatchAndFeatures) {
  std::mt19937_64 rng(45);
  for (int k = 0; k < 50; ++k) {
    const Configuration world = random_world_configuration(rng, true);
    Configuration reversed = world;
    for (auto& n : reversed.normals) n = -n;
    const auto a = normalise(world, SurfaceKind::kGregory);
    const auto b = normalise(reversed, SurfaceKind::kGregory);
    ASSERT_TRUE(a.value && b.value);
    EXPECT_EQ(a.value->features, b.value->features);
    Configuration mixed = world;
    mixed.normals[2] = -mixed.normals[2];
    EXPECT_FALSE(normalise(mixed, SurfaceKind::kGregory).value.has_value());
  }
}

}  // namespace
}  // namespace contactnn::geometry
