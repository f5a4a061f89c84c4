// Tests of lib/dataset/labeller: labels in the caller's node order (SPEC 4: the projection runs in the
// canonical configuration and is mapped back).
#include <gtest/gtest.h>

#include <random>

#include "dataset/labeller.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "test_support.hpp"

namespace contactnn::dataset {
namespace {

using geometry::Configuration;
using geometry::Vec3;

// The acceptance of the scenes issue: every node order of a pair gives the same label to 1e-12. Without ties
// the canonical configuration is the same bit for bit, so the labels agree to the last bit of the map back
// (exact for xi, eta; u -> 1 - u rounds).
constexpr double kOrderTol = 1e-12;

using testing::relabel;

Configuration random_world(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Configuration local{
      {Vec3(0, 0, 0), Vec3(1 + 0.5 * u(rng), 0.1 * u(rng), 0.1 * u(rng)),
       Vec3(1 + 0.3 * u(rng), 1 + 0.3 * u(rng), 0.2 * u(rng)), Vec3(0.1 * u(rng), 1 + 0.5 * u(rng), 0)},
      Vec3(0.5 + 0.6 * u(rng), 0.5 + 0.6 * u(rng), 0.3 * u(rng)),
      {Vec3(0.1 * u(rng), 0.1 * u(rng), 1), Vec3(0.1 * u(rng), 0.1 * u(rng), 1),
       Vec3(0.1 * u(rng), 0.1 * u(rng), 1), Vec3(0.1 * u(rng), 0.1 * u(rng), 1)}};
  return testing::transform(local, testing::random_rotation(rng), std::exp(2 * u(rng)),
                            Vec3(u(rng), u(rng), u(rng)) * 10);
}

/// The world point of local coordinates `p` on the caller's surface.
Vec3 surface_point(const Configuration& c, SurfaceKind kind, const std::array<double, 2>& p) {
  if (kind == SurfaceKind::kBilinear) return geometry::BilinearPatch(c.nodes).position(p[0], p[1]);
  return geometry::GregoryPatch(c.nodes, c.normals).position(p[0], p[1]);
}

TEST(Labeller, EveryNodeOrderGivesTheSameLabelAndThePointItNames) {
  std::mt19937_64 rng(51);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    int compared = 0;
    for (int k = 0; k < 60; ++k) {
      const Configuration world = random_world(rng);
      const Label base = label_configuration(world, kind);
      if (base.status != Status::kOk && base.status != Status::kOutside) continue;
      const double size = (world.nodes[1] - world.nodes[0]).norm();
      const Vec3 point = surface_point(world, kind, base.param);
      for (const SquareSymmetry& order : all_square_symmetries()) {
        const Configuration other_world = relabel(world, order);
        const Label other = label_configuration(other_world, kind);
        ASSERT_EQ(other.status, base.status);
        // The same label, moved by the relabelling: to_caller of the base's canonical coordinates.
        const auto expected = order.to_caller(base.param, kind);
        EXPECT_NEAR(other.param[0], expected[0], kOrderTol);
        EXPECT_NEAR(other.param[1], expected[1], kOrderTol);
        // ... which names the same world point on the same surface.
        EXPECT_LT((surface_point(other_world, kind, other.param) - point).norm(), kOrderTol * size * 10);
        // The gap is measured along the caller's own normal: a reversing order reverses its sign.
        EXPECT_NEAR(other.gap, order.orientation() * base.gap, kOrderTol * size);
        ++compared;
      }
    }
    EXPECT_GT(compared, 8 * 30) << to_string(kind);
  }
}

TEST(Labeller, GapSignFollowsTheCallersOrientation) {
  // A unit square in z = 0, counter-clockwise seen from +z; S above it at height 0.25.
  const Configuration up{
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, Vec3(0.7, 0.2, 0.25), {}};
  const Label l = label_configuration(up, SurfaceKind::kBilinear);
  ASSERT_EQ(l.status, Status::kOk);
  EXPECT_NEAR(l.param[0], 0.4, 1e-14);
  EXPECT_NEAR(l.param[1], -0.6, 1e-14);
  EXPECT_NEAR(l.gap, 0.25, 1e-14);
  // The same nodes in the order A, D, C, B: counter-clockwise seen from -z, so S is behind: gap -0.25, and
  // xi now runs along AD: (xi, eta) swapped.
  const Configuration down{{up.nodes[0], up.nodes[3], up.nodes[2], up.nodes[1]}, up.slave, {}};
  const Label m = label_configuration(down, SurfaceKind::kBilinear);
  ASSERT_EQ(m.status, Status::kOk);
  EXPECT_NEAR(m.param[0], -0.6, 1e-14);
  EXPECT_NEAR(m.param[1], 0.4, 1e-14);
  EXPECT_NEAR(m.gap, -0.25, 1e-14);
}

TEST(Labeller, FeaturesAreCanonicalWhateverTheCallersOrder) {
  // S nearest C and |AD| > |AB|: outside the paper's frame as given; the features are the canonical ones.
  const Configuration c{
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.1, 1.6, 0.1), Vec3(0, 1.5, 0)}, Vec3(0.9, 1.3, -0.2), {}};
  const Label l = label_configuration(c, SurfaceKind::kBilinear);
  ASSERT_EQ(l.status, Status::kOk);
  const auto n = geometry::normalise(c, SurfaceKind::kBilinear);
  ASSERT_TRUE(n.value);
  EXPECT_EQ(n.value->symmetry.rotation, 2);  // canonical A is the caller's C
  EXPECT_EQ(l.features, n.value->features);
  const geometry::DomainFilters
      paper;  // the bilinear study's filters: A nearest, |AD| <= |AB|, segment test at A, ...
  EXPECT_TRUE(paper.accepts(n.value->config, SurfaceKind::kBilinear, 1e-9));
}

}  // namespace
}  // namespace contactnn::dataset
