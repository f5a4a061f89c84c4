// Tests for lib/contact/global_search.* and shape_statistics.*: the segment test and its tolerance, the
// choice among candidate segments, node order, and the statistics' definitions, on hand-made meshes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "contact/global_search.hpp"
#include "contact/shape_statistics.hpp"
#include "core/error.hpp"
#include "geometry/segment_checks.hpp"
#include "mesh/grid_surface.hpp"
#include "mesh/surface_mesh.hpp"
#include "test_support.hpp"

namespace contactnn::contact {
namespace {

// Labels at a corner or on an edge of a flat grid: exact up to Newton's convergence (tol_param 1e-13).
constexpr double kParamTol = 1e-10;
// Statistics of hand-computed shapes: a few roundings.
constexpr double kShapeTol = 1e-12;

/// An nx x ny grid of unit squares on z = height(x, y), counter-clockwise seen from +z (outward = up);
/// node (i, j) has index and id i + (nx + 1) j (+1 for the id).
mesh::SurfaceMesh grid(int nx, int ny, double (*height)(double, double) = nullptr) {
  return testing::grid_surface(
      nx, ny, [&](double i, double j) { return geometry::Vec3(i, j, height ? height(i, j) : 0.0); });
}

NodeSegmentPair search_one(const mesh::SurfaceMesh& s, const Vec3& slave,
                           SurfaceKind kind = SurfaceKind::kBilinear) {
  SearchOptions options;
  options.surface = kind;
  const std::vector<Vec3> normals = mesh::node_normals(s);
  const std::vector<long> ids = {99};
  const std::vector<Vec3> positions = {slave};
  return global_search(s, normals, ids, positions, options)[0];
}

TEST(GlobalSearch, SlaveAboveASegmentGetsItWithANearestNodeFirstAndCounterClockwiseOrder) {
  const mesh::SurfaceMesh s = grid(3, 3);
  const NodeSegmentPair p = search_one(s, Vec3(1.3, 2.2, 0.05));
  ASSERT_EQ(p.status, PairStatus::kFound);
  // Nearest node (1, 2); the segment [1,2] x [2,3]; order A = (1,2), (2,2), (2,3), (1,3).
  EXPECT_EQ(s.node_ids[static_cast<std::size_t>(p.nodes[0])], 1 + 1 + 4 * 2);
  EXPECT_EQ(p.config.nodes[0], Vec3(1, 2, 0));
  EXPECT_EQ(p.config.nodes[1], Vec3(2, 2, 0));
  EXPECT_EQ(p.config.nodes[2], Vec3(2, 3, 0));
  EXPECT_EQ(p.config.nodes[3], Vec3(1, 3, 0));
  EXPECT_EQ(p.candidates, 1);
  ASSERT_EQ(p.label.status, Status::kOk);
  EXPECT_NEAR(p.label.param[0], -0.4, kParamTol);  // xi = 2 (x - 1) - 1
  EXPECT_NEAR(p.label.param[1], -0.6, kParamTol);
  EXPECT_NEAR(p.label.gap, 0.05, kParamTol);
}

TEST(GlobalSearch, SlaveOnAMasterNodeGetsOneOfItsSegmentsWithTheLabelAtTheCorner) {
  const mesh::SurfaceMesh s = grid(2, 2);
  const NodeSegmentPair p = search_one(s, Vec3(1, 1, 0));  // the middle node, exactly (a matching mesh)
  ASSERT_EQ(p.status, PairStatus::kFound);
  EXPECT_EQ(p.candidates, 4);
  EXPECT_EQ(p.config.nodes[0], Vec3(1, 1, 0));
  ASSERT_EQ(p.label.status, Status::kOk);
  EXPECT_NEAR(p.label.param[0], -1.0, kParamTol);
  EXPECT_NEAR(p.label.param[1], -1.0, kParamTol);
  EXPECT_EQ(p.segment, 0);  // all four at distance 0: the first segment in the surface's order
}

TEST(GlobalSearch, SlaveOnASharedEdgePlaneGetsTheSegmentItsProjectionIsIn) {
  // S on the plane x = 1 between segments 0 ([0,1]) and 1 ([1,2]), nearest node (1, 0).
  const mesh::SurfaceMesh s = grid(2, 1);
  const NodeSegmentPair p = search_one(s, Vec3(1, 0.3, 0.1));
  ASSERT_EQ(p.status, PairStatus::kFound);
  EXPECT_EQ(p.candidates, 2);
  EXPECT_EQ(p.label.status, Status::kOk);
  EXPECT_EQ(p.segment, 0);  // both contain the projection at equal distance: the lower index
  // Moved by 1e-3 into segment 1: only segment 1 passes.
  const NodeSegmentPair q = search_one(s, Vec3(1.001, 0.3, 0.1));
  EXPECT_EQ(q.segment, 1);
  EXPECT_EQ(q.candidates, 1);
}

double ridge(double x, double) { return -0.3 * std::abs(x - 1.0); }

TEST(GlobalSearch, SlaveInTheDeadZoneOfAConvexRidgeHasNoSegment) {
  // Two segments meeting at a convex ridge x = 1; S straight above the ridge node fails the segment test
  // of both (paper Section 2's search has this gap; SPEC 7 reports no_segment).
  const mesh::SurfaceMesh s = grid(2, 1, ridge);
  const NodeSegmentPair p = search_one(s, Vec3(1, 0.0, 0.2));
  EXPECT_EQ(p.status, PairStatus::kNoSegment);
  EXPECT_EQ(p.candidates, 0);
  // Beside the ridge, over one side: found.
  EXPECT_EQ(search_one(s, Vec3(1.4, 0.4, 0.0)).status, PairStatus::kFound);
}

double valley(double x, double) { return 0.3 * std::abs(x - 1.0); }

TEST(GlobalSearch, ConcaveValleyOffersBothSidesAndThePairIsTheOneWithTheProjectionInside) {
  const mesh::SurfaceMesh s = grid(2, 1, valley);
  const NodeSegmentPair p = search_one(s, Vec3(1.02, 0.2, 0.3), SurfaceKind::kGregory);
  ASSERT_EQ(p.status, PairStatus::kFound);
  EXPECT_EQ(p.candidates, 2);
  EXPECT_EQ(p.label.status, Status::kOk);
  // Gregory normals: the unit node normals of Eq 26, so the valley node's normal is +z.
  EXPECT_LT((p.config.normals[0] - Vec3::UnitZ()).norm(), kShapeTol);
}

TEST(GlobalSearch, GregorySearchWithoutNormalsIsRefused) {
  const mesh::SurfaceMesh s = grid(1, 1);
  SearchOptions options;
  options.surface = SurfaceKind::kGregory;
  const std::vector<long> ids = {1};
  const std::vector<Vec3> positions = {Vec3(0.5, 0.5, 0.1)};
  EXPECT_THROW((void)global_search(s, {}, ids, positions, options), InvalidArgument);
}

TEST(ShapeStatistics, DefinitionsOnHandComputedShapes) {
  // A 4 x 1 rectangle with D lifted by 0.5: edges |AB| = 4, |BC| = 1, |CD| = sqrt(16.25), |DA| = sqrt(1.25).
  const std::array<Vec3, 4> rect = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(4, 1, 0), Vec3(0, 1, 0.5)};
  EXPECT_NEAR(aspect_ratio(rect), std::sqrt(16.25), kShapeTol);
  // D is 0.5 above the plane z = 0 of A, B, C; the shortest edge is |BC| = 1.
  EXPECT_NEAR(warp(rect), 0.5, kShapeTol);
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0)};
  EXPECT_NEAR(segment_size(square), 2.0, kShapeTol);
  EXPECT_EQ(warp(square), 0.0);
  // A normal tilted by 0.1 rad from the corner normal +z.
  const Vec3 tilted(std::sin(0.1), 0, std::cos(0.1));
  EXPECT_NEAR(normal_tilt_tangent(square[0], square[1], square[3], tilted), std::tan(0.1), kShapeTol);
  EXPECT_EQ(normal_tilt_tangent(square[0], square[1], square[3], Vec3(1, 0, -0.1)),
            std::numeric_limits<double>::infinity());
  EXPECT_EQ(normal_tilt_tangent(square[0], square[1], square[3], Vec3::Zero()), -1.0);
  const Spread odd = spread_of({3, 1, 2});
  EXPECT_EQ(odd.count, 3);
  EXPECT_EQ(odd.min, 1);
  EXPECT_EQ(odd.median, 2);
  EXPECT_EQ(odd.max, 3);
  EXPECT_EQ(spread_of({4, 1, 2, 3}).median, 2.5);
  EXPECT_EQ(spread_of({}).count, 0);
}

TEST(ShapeStatistics, OverFoundPairsOnly) {
  const mesh::SurfaceMesh s = grid(2, 1, ridge);
  SearchOptions options;
  const std::vector<long> ids = {1, 2};
  const std::vector<Vec3> positions = {Vec3(1, 0.0, 0.2), Vec3(0.4, 0.5, 0.1)};  // dead zone, then found
  const auto pairs = global_search(s, mesh::node_normals(s), ids, positions, options);
  const ShapeStatistics st = shape_statistics(pairs, SurfaceKind::kBilinear);
  EXPECT_EQ(st.aspect_ratio.count, 1);
  EXPECT_EQ(st.interior_angle_degrees.count, 4);
  EXPECT_NEAR(st.interior_angle_degrees.median, 90.0, kShapeTol);
  EXPECT_EQ(st.normal_tilt_tangent.count, 0);  // bilinear: none
  ASSERT_EQ(st.normal_offset.count, 1);
  EXPECT_GT(st.normal_offset.min, 0.0);
}

}  // namespace
}  // namespace contactnn::contact
