// projection::closest_point_on_face: the closest point of a whole face, its edges and vertices included,
// against independent oracles (tests/projection/closest_point_oracle.hpp).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "projection/closest_point_on_face.hpp"
#include "projection/closest_point_oracle.hpp"

namespace contactnn::projection {
namespace {

using geometry::BilinearPatch;
using geometry::GregoryPatch;

// Points and distances of exact methods agree to rounding: 1e-12 of the face size.
constexpr double kExact = 1e-12;

std::array<Vec3, 4> unit_square() { return {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)}; }

TEST(ClosestPointOnFace, LocationsOnAFlatSquareWrittenOut) {
  const BilinearPatch square(unit_square());
  struct Case {
    Vec3 slave;
    Location location;
    int feature;
    std::array<double, 2> param;
    double distance;
  };
  const Case cases[] = {
      {Vec3(0.25, -0.5, 1.0), Location::kFace, -1, {0.25, -0.5}, 1.0},
      {Vec3(0.5, -3.0, 0.0), Location::kEdge, 0, {0.5, -1.0}, 2.0},
      {Vec3(4.0, 0.25, -3.0), Location::kEdge, 1, {1.0, 0.25}, std::sqrt(18.0)},
      {Vec3(-0.5, 2.0, 0.0), Location::kEdge, 2, {-0.5, 1.0}, 1.0},
      {Vec3(-2.0, 0.0, 0.0), Location::kEdge, 3, {-1.0, 0.0}, 1.0},
      {Vec3(-2.0, -2.0, 0.0), Location::kVertex, 0, {-1.0, -1.0}, std::sqrt(2.0)},
      {Vec3(3.0, -1.0, 0.0), Location::kVertex, 1, {1.0, -1.0}, 2.0},
      {Vec3(2.0, 2.0, 1.0), Location::kVertex, 2, {1.0, 1.0}, std::sqrt(3.0)},
      {Vec3(-1.0, 3.0, 0.0), Location::kVertex, 3, {-1.0, 1.0}, 2.0},
      // Exactly on an edge and on a vertex: found, at distance 0.
      {Vec3(0.3, -1.0, 0.0), Location::kEdge, 0, {0.3, -1.0}, 0.0},
      {Vec3(1.0, 1.0, 0.0), Location::kVertex, 2, {1.0, 1.0}, 0.0},
  };
  for (const Case& c : cases) {
    const FaceClosestPoint p = closest_point_on_face(square, c.slave);
    SCOPED_TRACE(::testing::Message() << "slave " << c.slave.transpose());
    ASSERT_EQ(p.status, Status::kOk);
    EXPECT_EQ(p.location, c.location);
    EXPECT_EQ(p.feature, c.feature);
    EXPECT_NEAR(p.param[0], c.param[0], kExact);
    EXPECT_NEAR(p.param[1], c.param[1], kExact);
    EXPECT_NEAR(p.distance, c.distance, kExact);
    EXPECT_NEAR(p.normal.z(), 1.0, kExact);
  }
}

/// A random convex planar quadrilateral: a square's corners moved by up to 0.3, rotated and moved anywhere.
std::array<Vec3, 4> random_planar_quad(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), angle(-3.1, 3.1), shift(-10.0, 10.0);
  std::array<Vec3, 4> q = unit_square();
  for (Vec3& x : q) x += Vec3(jitter(rng), jitter(rng), 0.0);
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(angle(rng), Vec3::UnitZ()) *
                             Eigen::AngleAxisd(angle(rng), Vec3(1, 2, 3).normalized()))
                                .toRotationMatrix();
  const Vec3 t(shift(rng), shift(rng), shift(rng));
  for (Vec3& x : q) x = r * x + t;
  return q;
}

TEST(ClosestPointOnFace, PlanarQuadEqualsTheTriangleOracleInsideOnEdgesAndAtVertices) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> around(-3.0, 3.0);
  int counts[3] = {0, 0, 0};
  for (int n = 0; n < 4000; ++n) {
    const std::array<Vec3, 4> q = random_planar_quad(rng);
    const Vec3 centre = 0.25 * (q[0] + q[1] + q[2] + q[3]);
    const Vec3 slave = centre + Vec3(around(rng), around(rng), around(rng));
    const FaceClosestPoint p = closest_point_on_face(BilinearPatch(q), slave);
    ASSERT_EQ(p.status, Status::kOk) << "slave " << slave.transpose() << " quad " << q[0].transpose() << " | "
                                     << q[1].transpose() << " | " << q[2].transpose() << " | "
                                     << q[3].transpose();
    const Vec3 oracle = testing::closest_point_on_planar_quad(slave, q);
    const double size = geometry::max_node_distance(q);
    ASSERT_LE((p.point - oracle).norm(), kExact * size) << "slave " << slave.transpose();
    EXPECT_NEAR(p.distance, (slave - oracle).norm(), kExact * size);
    ++counts[static_cast<int>(p.location)];
  }
  // The sample reaches every kind of location.
  EXPECT_GT(counts[0], 200);
  EXPECT_GT(counts[1], 200);
  EXPECT_GT(counts[2], 200);
}

/// A warped quadrilateral: the unit square's corners moved by up to `warp` in every direction.
std::array<Vec3, 4> random_warped_quad(std::mt19937_64& rng, double warp) {
  std::uniform_real_distribution<double> jitter(-warp, warp);
  std::array<Vec3, 4> q = unit_square();
  for (Vec3& x : q) x += Vec3(jitter(rng), jitter(rng), jitter(rng));
  return q;
}

TEST(ClosestPointOnFace, NoSampleOfAWarpedFacetIsNearer) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> around(-2.5, 2.5);
  constexpr int kGrid = 161;
  for (int n = 0; n < 300; ++n) {
    const std::array<Vec3, 4> q = random_warped_quad(rng, 0.4);
    const BilinearPatch facet(q);
    const Vec3 slave(around(rng), around(rng), around(rng));
    const FaceClosestPoint p = closest_point_on_face(facet, slave);
    ASSERT_EQ(p.status, Status::kOk);
    const double sampled = testing::sampled_distance(facet, slave, -1.0, 1.0, kGrid);
    // Never beaten by a sample; and a sample within the grid's spacing of the answer is as near to rounding.
    EXPECT_LE(p.distance, sampled + kExact) << "slave " << slave.transpose();
    EXPECT_GE(p.distance, sampled - 0.02) << "slave " << slave.transpose();
    EXPECT_NEAR(p.distance, (slave - facet.position(p.param[0], p.param[1])).norm(), kExact);
  }
}

/// A Gregory patch on a warped quad with node normals tilted from the corner normals by up to `tilt`.
GregoryPatch random_patch(std::mt19937_64& rng, double warp, double tilt) {
  const std::array<Vec3, 4> q = random_warped_quad(rng, warp);
  std::uniform_real_distribution<double> jitter(-tilt, tilt);
  std::array<Vec3, 4> normals;
  for (int i = 0; i < 4; ++i) {
    const Vec3& x = q[static_cast<std::size_t>(i)];
    const Vec3 corner =
        (q[static_cast<std::size_t>((i + 1) % 4)] - x).cross(q[static_cast<std::size_t>((i + 3) % 4)] - x);
    normals[static_cast<std::size_t>(i)] =
        (corner.normalized() + Vec3(jitter(rng), jitter(rng), jitter(rng))).normalized();
  }
  return GregoryPatch(q, normals);
}

/// A cubic Bezier curve's point by de Casteljau's algorithm (independent of the patch's own evaluation).
Vec3 bezier(const std::array<Vec3, 4>& b, double t) {
  std::array<Vec3, 4> x = b;
  for (int level = 3; level > 0; --level) {
    for (int i = 0; i < level; ++i)
      x[static_cast<std::size_t>(i)] =
          (1 - t) * x[static_cast<std::size_t>(i)] + t * x[static_cast<std::size_t>(i + 1)];
  }
  return x[0];
}

TEST(ClosestPointOnFace, GregoryEdgesAreTheirBezierCurvesAndNoCurvePointIsNearer) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> around(-2.5, 2.5);
  for (int n = 0; n < 200; ++n) {
    const GregoryPatch patch = random_patch(rng, 0.3, 0.2);
    const auto& c = patch.control_points();
    const auto at = [&](int i, int j) {
      return c[static_cast<std::size_t>(GregoryPatch::control_index(i, j))];
    };
    // Edge 0 is v = 0 (P00..P30), 1 is u = 1 (P30..P33), 2 is v = 1 (P03..P33), 3 is u = 0 (P00..P03).
    const std::array<std::array<Vec3, 4>, 4> curves = {{{at(0, 0), at(1, 0), at(2, 0), at(3, 0)},
                                                        {at(3, 0), at(3, 1), at(3, 2), at(3, 3)},
                                                        {at(0, 3), at(1, 3), at(2, 3), at(3, 3)},
                                                        {at(0, 0), at(0, 1), at(0, 2), at(0, 3)}}};
    const Vec3 slave(around(rng), around(rng), around(rng));
    for (int e = 0; e < 4; ++e) {
      const EdgePoint p = closest_point_on_edge(patch, e, slave);
      const double t = (e == 0 || e == 2) ? p.param[0] : p.param[1];
      const Vec3 on_curve = bezier(curves[static_cast<std::size_t>(e)], t);
      EXPECT_LE((patch.position(p.param[0], p.param[1]) - on_curve).norm(), kExact);
      double sampled = std::numeric_limits<double>::infinity();
      for (int k = 0; k <= 20000; ++k) {
        sampled =
            std::min(sampled, (slave - bezier(curves[static_cast<std::size_t>(e)], k / 20000.0)).norm());
      }
      EXPECT_LE(p.distance, sampled + kExact) << "edge " << e << " slave " << slave.transpose();
      EXPECT_GE(p.distance, sampled - 1e-3);
    }
  }
}

TEST(ClosestPointOnFace, NoSampleOfAGregoryPatchIsNearer) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> around(-2.5, 2.5);
  int boundary = 0;
  for (int n = 0; n < 250; ++n) {
    const GregoryPatch patch = random_patch(rng, 0.3, 0.2);
    const Vec3 slave(around(rng), around(rng), around(rng));
    const FaceClosestPoint p = closest_point_on_face(patch, slave);
    ASSERT_EQ(p.status, Status::kOk);
    const double sampled = testing::sampled_distance(patch, slave, 0.0, 1.0, 121);
    EXPECT_LE(p.distance, sampled + kExact) << "slave " << slave.transpose();
    EXPECT_GE(p.distance, sampled - 0.03);
    boundary += p.location != Location::kFace;
  }
  EXPECT_GT(boundary, 50);
}

TEST(ClosestPointOnFace, FlatGregoryPatchGivesTheBilinearFacetsPoint) {
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> around(-3.0, 3.0);
  for (int n = 0; n < 300; ++n) {
    std::array<Vec3, 4> q = unit_square();
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (Vec3& x : q) x += Vec3(jitter(rng), jitter(rng), 0.0);
    const std::array<Vec3, 4> up = {Vec3::UnitZ(), Vec3::UnitZ(), Vec3::UnitZ(), Vec3::UnitZ()};
    const Vec3 slave(around(rng), around(rng), around(rng));
    const FaceClosestPoint b = closest_point_on_face(BilinearPatch(q), slave);
    const FaceClosestPoint g = closest_point_on_face(GregoryPatch(q, up), slave);
    ASSERT_EQ(b.status, Status::kOk);
    ASSERT_EQ(g.status, Status::kOk);
    EXPECT_LE((b.point - g.point).norm(), 1e-10) << "slave " << slave.transpose();
    EXPECT_EQ(b.location, g.location);
    EXPECT_EQ(b.feature, g.feature);
    EXPECT_NEAR(g.param[0], 0.5 * (b.param[0] + 1.0), 1e-10);
    EXPECT_NEAR(g.param[1], 0.5 * (b.param[1] + 1.0), 1e-10);
  }
}

TEST(ClosestPointOnTriangle, EqualsEricsonsRegionsInsideOnEdgesAndAtVertices) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> x(-2.0, 2.0);
  int counts[3] = {0, 0, 0};
  for (int n = 0; n < 5000; ++n) {
    const std::array<Vec3, 3> t = {Vec3(x(rng), x(rng), x(rng)), Vec3(x(rng), x(rng), x(rng)),
                                   Vec3(x(rng), x(rng), x(rng))};
    const Vec3 slave(2 * x(rng), 2 * x(rng), 2 * x(rng));
    const FaceClosestPoint p = closest_point_on_triangle(t, slave);
    if (p.status == Status::kDegenerate) continue;
    ASSERT_EQ(p.status, Status::kOk);
    const Vec3 oracle = testing::closest_point_on_triangle(slave, t[0], t[1], t[2]);
    const double size = std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    ASSERT_LE((p.point - oracle).norm(), 1e-11 * size) << slave.transpose();
    EXPECT_LE((t[0] + p.param[0] * (t[1] - t[0]) + p.param[1] * (t[2] - t[0]) - p.point).norm(),
              1e-12 * size);
    ++counts[static_cast<int>(p.location)];
  }
  EXPECT_GT(counts[0], 200);
  EXPECT_GT(counts[1], 200);
  EXPECT_GT(counts[2], 200);
  // Written out: the triangle (0,0,0), (2,0,0), (0,2,0).
  const std::array<Vec3, 3> t = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)};
  const FaceClosestPoint face = closest_point_on_triangle(t, Vec3(0.5, 0.5, -1.0));
  EXPECT_EQ(face.location, Location::kFace);
  EXPECT_NEAR(face.param[0], 0.25, kExact);
  EXPECT_NEAR(face.distance, 1.0, kExact);
  const FaceClosestPoint hypotenuse = closest_point_on_triangle(t, Vec3(2.0, 2.0, 0.0));
  EXPECT_EQ(hypotenuse.location, Location::kEdge);
  EXPECT_EQ(hypotenuse.feature, 1);
  EXPECT_NEAR(hypotenuse.distance, std::sqrt(2.0), kExact);
  const FaceClosestPoint corner = closest_point_on_triangle(t, Vec3(-1.0, -1.0, 1.0));
  EXPECT_EQ(corner.location, Location::kVertex);
  EXPECT_EQ(corner.feature, 0);
  EXPECT_EQ(closest_point_on_triangle({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)}, Vec3(0, 1, 0)).status,
            Status::kDegenerate);
}

TEST(ClosestPointOnFace, NonFiniteSlaveIsInvalidAndACollapsedFaceDegenerate) {
  const BilinearPatch square(unit_square());
  EXPECT_EQ(closest_point_on_face(square, Vec3(std::nan(""), 0, 0)).status, Status::kInvalid);
  EXPECT_EQ(closest_point_on_face(square, Vec3(std::numeric_limits<double>::infinity(), 0, 0)).status,
            Status::kInvalid);
  const BilinearPatch point({Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)});
  EXPECT_EQ(closest_point_on_face(point, Vec3(0, 0, 2)).status, Status::kDegenerate);
}

}  // namespace
}  // namespace contactnn::projection
