#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "geometry/segment_checks.hpp"

namespace contactnn::geometry {
namespace {

const std::array<Vec3, 4> kSquare = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};

TEST(SegmentChecks, SegmentTestAcceptsOnlyTheWedgeBetweenTheTwoEdgesAtTheNode) {
  const Vec3 a = kSquare[0], b = kSquare[1], d = kSquare[3];
  EXPECT_TRUE(passes_segment_test(a, b, d, Vec3(0.3, 0.2, 0.5)));     // inside the wedge, above
  EXPECT_TRUE(passes_segment_test(a, b, d, Vec3(0.3, 0.2, -0.5)));    // below: r is the in-plane part
  EXPECT_FALSE(passes_segment_test(a, b, d, Vec3(-0.3, 0.2, 0.0)));   // behind AD
  EXPECT_FALSE(passes_segment_test(a, b, d, Vec3(0.3, -0.2, 0.0)));   // behind AB
  EXPECT_FALSE(passes_segment_test(a, b, d, Vec3(0.3, 0.0, 0.0)));    // on AB: Eq 3 is strict
  EXPECT_FALSE(passes_segment_test(a, b, d, Vec3(-0.3, -0.3, 0.0)));  // opposite wedge
}

TEST(SegmentChecks, NearestNodeAllowsTiesAndRejectsCloserNodes) {
  EXPECT_TRUE(first_node_is_nearest(kSquare, Vec3(0.2, 0.3, 1)));
  EXPECT_TRUE(first_node_is_nearest(kSquare, Vec3(0.5, 0.3, 1)));  // tie with B
  EXPECT_FALSE(first_node_is_nearest(kSquare, Vec3(0.6, 0.3, 1)));
}

TEST(SegmentChecks, InteriorAnglesAndConvexity) {
  const auto square = interior_angles_degrees(kSquare);
  for (double angle : square) EXPECT_NEAR(angle, 90.0, 1e-12);
  EXPECT_TRUE(is_convex(kSquare));
  const std::array<Vec3, 4> dart = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.3, 0.3, 0),
                                    Vec3(0, 1, 0)};  // reflex at C
  EXPECT_FALSE(is_convex(dart));
  const std::array<Vec3, 4> clockwise = {kSquare[0], kSquare[3], kSquare[2], kSquare[1]};
  EXPECT_TRUE(is_convex(clockwise));  // convexity is judged against its own normal (B-A) x (D-A)
  const auto dart_angles = interior_angles_degrees(dart);
  EXPECT_NEAR(dart_angles[0], 90.0, 1e-12);
  // The angle between the edges at C is reported (< 180); the dart is caught by is_convex, not by angles.
  const double expected_c = std::acos(-0.42 / 0.58) * 180.0 / M_PI;  // CD = (-0.3, 0.7), CB = (0.7, -0.3)
  EXPECT_NEAR(dart_angles[2], expected_c, 1e-9);
}

TEST(SegmentChecks, DegenerateSegmentsAreRecognised) {
  EXPECT_FALSE(is_degenerate_segment(kSquare));
  EXPECT_TRUE(is_degenerate_segment({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}));  // B = C
  EXPECT_TRUE(
      is_degenerate_segment({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)}));  // collinear
  EXPECT_TRUE(
      is_degenerate_segment({Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)}));  // a point
  EXPECT_FALSE(
      is_degenerate_segment({Vec3(0, 0, 0), Vec3(1e3, 0, 0), Vec3(1e3, 1, 0), Vec3(0, 1, 0)}));  // 1e3:1
}

TEST(SegmentTest, StrictTestIsTheProductsOfEqs3And4) {
  // Tolerance 0 is Eqs 3-6 as printed (the products, written here independently) on random corners and
  // slave nodes.
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> x(-2, 2);
  int passed = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 m(x(rng), x(rng), x(rng)), next(x(rng), x(rng), x(rng)), prev(x(rng), x(rng), x(rng)),
        s(x(rng), x(rng), x(rng));
    const Vec3 c1 = next - m, c2 = prev - m, n = c1.cross(c2).normalized(), t = s - m;
    const Vec3 r = t - t.dot(n) * n;                                                             // Eqs 5-6
    const bool printed = c1.cross(r).dot(c1.cross(c2)) > 0 && c1.cross(r).dot(r.cross(c2)) > 0;  // Eqs 3-4
    const bool mine = passes_segment_test(m, next, prev, s, 0.0);
    ASSERT_EQ(mine, printed) << k;
    passed += mine;
  }
  EXPECT_GT(passed, 1000);
}

TEST(SegmentTest, ToleranceAdmitsTheEdgePlaneAndTheCornerButNotTheBackwardExtensionOfAnEdge) {
  const Vec3 m(0, 0, 0), next(1, 0, 0), prev(0, 1, 0);
  const double tol = 1e-6;
  // On the plane of edge m-next (y = 0), above the segment: fails strictly, passes with the tolerance.
  EXPECT_FALSE(passes_segment_test(m, next, prev, Vec3(0.5, 0, 0.3), 0.0));
  EXPECT_TRUE(passes_segment_test(m, next, prev, Vec3(0.5, 0, 0.3), tol));
  EXPECT_TRUE(passes_segment_test(m, next, prev, Vec3(0.5, -1e-9, 0.3), tol));
  EXPECT_FALSE(passes_segment_test(m, next, prev, Vec3(0.5, -1e-3, 0.3), tol));
  // Straight above the corner: r = 0.
  EXPECT_TRUE(passes_segment_test(m, next, prev, Vec3(0, 0, -0.2), tol));
  EXPECT_TRUE(passes_segment_test(m, next, prev, Vec3(1e-9, -1e-9, 0.2), tol));
  // On the line of edge m-next but behind m: c1 x r = 0 as on the edge, and still outside the corner.
  EXPECT_FALSE(passes_segment_test(m, next, prev, Vec3(-0.5, 0, 0.1), tol));
  EXPECT_FALSE(passes_segment_test(m, next, prev, Vec3(0, -0.5, 0.1), tol));
  // A collapsed corner passes nothing.
  EXPECT_FALSE(passes_segment_test(m, next, 2.0 * next, Vec3(0.5, 0.5, 0.1), tol));
}

TEST(SegmentTest, GivesTheSameAnswerAtScalesFrom1eMinus300To1e300) {
  // The test is scale-free: the same random corners and slave nodes (strict and with the global search's
  // tolerance), and a slave node on an edge's plane and over the corner, give the answer of scale 1 at every
  // scale. Its products are fourth powers of the corner's size: they left the double range near 1e+-77, where
  // every slave node of a scaled deck failed the test (gen-configs --scene --search nearest_node:
  // no_segment).
  std::mt19937_64 rng(67);
  std::uniform_real_distribution<double> x(-2, 2);
  std::vector<std::array<Vec3, 4>> cases;
  for (int k = 0; k < 2000; ++k)
    cases.push_back({Vec3(x(rng), x(rng), x(rng)), Vec3(x(rng), x(rng), x(rng)), Vec3(x(rng), x(rng), x(rng)),
                     Vec3(x(rng), x(rng), x(rng))});
  cases.push_back({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.5, 0, 0.3)});    // on the edge's plane
  cases.push_back({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -0.2)});     // over the corner
  cases.push_back({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.2, 0.5)});  // inside
  for (const double tol : {0.0, kSegmentTestTolerance}) {
    int passed = 0;
    for (const auto& c : cases) {
      const bool reference = passes_segment_test(c[0], c[1], c[2], c[3], tol);
      passed += reference ? 1 : 0;
      for (const double scale : {1e-300, 1e-200, 1e-100, 1e-77, 1e-40, 1e40, 1e77, 1e100, 1e200, 1e300}) {
        ASSERT_EQ(passes_segment_test(scale * c[0], scale * c[1], scale * c[2], scale * c[3], tol), reference)
            << "scale " << scale << " tolerance " << tol;
      }
    }
    EXPECT_GT(passed, 200) << tol;
  }
}

}  // namespace
}  // namespace contactnn::geometry
