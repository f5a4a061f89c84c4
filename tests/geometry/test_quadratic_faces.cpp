// geometry::SerendipityQuad and geometry::QuadraticTriangle (SPEC 9's quad8 and tri6) against the shape
// functions written out in the textbook form (Zienkiewicz & Taylor, vol. 1, 6.4 and 6.6), central
// differences for the derivatives, and the Bezier hull that the surface search's bounding spheres rely on.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"

namespace contactnn::geometry {
namespace {

// Node coordinates are O(1): sums of a few O(1) products agree to a few roundings.
constexpr double kRounding = 1e-13;
// Central differences of a polynomial of degree <= 2 in the differenced variable are exact but for the
// rounding of P(x + h) - P(x - h), about 1e-16 / h relative; second differences about 1e-16 / h^2.
constexpr double kStep = 1e-3;
constexpr double kFirstDifferenceTol = 1e-11;
constexpr double kSecondDifferenceTol = 1e-8;

template <std::size_t N>
std::array<Vec3, N> random_nodes(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::array<Vec3, N> x;
  for (auto& p : x) p = Vec3(u(rng), u(rng), u(rng));
  return x;
}

/// The serendipity shape functions as the textbook writes them, at (xi, eta).
std::array<double, 8> quad8_shape(double xi, double eta) {
  const double s[4] = {-1, 1, 1, -1}, t[4] = {-1, -1, 1, 1};
  std::array<double, 8> n{};
  for (int i = 0; i < 4; ++i) {
    n[static_cast<std::size_t>(i)] = 0.25 * (1 + s[i] * xi) * (1 + t[i] * eta) * (s[i] * xi + t[i] * eta - 1);
  }
  n[4] = 0.5 * (1 - xi * xi) * (1 - eta);
  n[5] = 0.5 * (1 + xi) * (1 - eta * eta);
  n[6] = 0.5 * (1 - xi * xi) * (1 + eta);
  n[7] = 0.5 * (1 - xi) * (1 - eta * eta);
  return n;
}

/// The quadratic triangle's shape functions in area coordinates, at (r, s).
std::array<double, 6> tri6_shape(double r, double s) {
  const double l[3] = {1 - r - s, r, s};
  return {l[0] * (2 * l[0] - 1), l[1] * (2 * l[1] - 1), l[2] * (2 * l[2] - 1),
          4 * l[0] * l[1],       4 * l[1] * l[2],       4 * l[2] * l[0]};
}

template <std::size_t N>
Vec3 combine(const std::array<double, N>& shape, const std::array<Vec3, N>& x) {
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < N; ++i) p += shape[i] * x[i];
  return p;
}

/// Checks evaluate()'s derivatives against central differences of position().
template <class Face>
void expect_derivatives_match_differences(const Face& face, double a, double b) {
  const SurfacePoint p = face.evaluate(a, b);
  const double h = kStep;
  const auto pos = [&](double x, double y) { return face.position(x, y); };
  const Vec3 ds = (pos(a + h, b) - pos(a - h, b)) / (2 * h);
  const Vec3 dt = (pos(a, b + h) - pos(a, b - h)) / (2 * h);
  const Vec3 dss = (pos(a + h, b) - 2 * pos(a, b) + pos(a - h, b)) / (h * h);
  const Vec3 dtt = (pos(a, b + h) - 2 * pos(a, b) + pos(a, b - h)) / (h * h);
  const Vec3 dst =
      (pos(a + h, b + h) - pos(a + h, b - h) - pos(a - h, b + h) + pos(a - h, b - h)) / (4 * h * h);
  EXPECT_LE((p.position - pos(a, b)).norm(), kRounding);
  EXPECT_LE((p.d_s - ds).norm(), kFirstDifferenceTol);
  EXPECT_LE((p.d_t - dt).norm(), kFirstDifferenceTol);
  EXPECT_LE((p.d_ss - dss).norm(), kSecondDifferenceTol);
  EXPECT_LE((p.d_tt - dtt).norm(), kSecondDifferenceTol);
  EXPECT_LE((p.d_st - dst).norm(), kSecondDifferenceTol);
}

/// Faces of N random nodes: each node at its parameters `at`, and at random parameters in [lo, hi]^2 the
/// textbook interpolant (`shape`: the N shape functions) with derivatives that match finite differences.
template <class Face, std::size_t N, class Shape>
void expect_textbook_interpolant(std::uint64_t seed, double lo, double hi, const double (&at)[N][2],
                                 const Shape& shape) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  for (int trial = 0; trial < 50; ++trial) {
    const auto x = random_nodes<N>(rng);
    const Face face(x);
    for (std::size_t i = 0; i < N; ++i)
      EXPECT_LE((face.position(at[i][0], at[i][1]) - x[i]).norm(), kRounding) << i;
    for (int k = 0; k < 20; ++k) {
      const double s = u(rng), t = u(rng);
      EXPECT_LE((face.position(s, t) - combine(shape(s, t), x)).norm(), kRounding);
      expect_derivatives_match_differences(face, s, t);
    }
  }
}

TEST(SerendipityQuad, IsTheTextbookInterpolantThroughItsEightNodes) {
  const double at[8][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  expect_textbook_interpolant<SerendipityQuad>(11, -1.3, 1.3, at, quad8_shape);
}

TEST(QuadraticTriangle, IsTheTextbookInterpolantThroughItsSixNodes) {
  const double at[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
  expect_textbook_interpolant<QuadraticTriangle>(12, -0.3, 1.3, at, tri6_shape);
}

TEST(QuadraticFaces, MidpointMidSideNodesGiveTheLinearFace) {
  // With every mid-side node at its edge's midpoint the quad8 is the bilinear facet of its corners and the
  // tri6 the flat triangle.
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    auto q = random_nodes<8>(rng);
    for (std::size_t e = 0; e < 4; ++e) q[4 + e] = 0.5 * (q[e] + q[(e + 1) % 4]);
    auto t = random_nodes<6>(rng);
    for (std::size_t e = 0; e < 3; ++e) t[3 + e] = 0.5 * (t[e] + t[(e + 1) % 3]);
    const SerendipityQuad quad(q);
    const QuadraticTriangle tri(t);
    const double xi = u(rng), eta = u(rng), r = 0.5 * (u(rng) + 1), s = 0.5 * (u(rng) + 1) * (1 - r);
    const Vec3 bilinear = 0.25 * ((1 - xi) * (1 - eta) * q[0] + (1 + xi) * (1 - eta) * q[1] +
                                  (1 + xi) * (1 + eta) * q[2] + (1 - xi) * (1 + eta) * q[3]);
    EXPECT_LE((quad.position(xi, eta) - bilinear).norm(), kRounding);
    EXPECT_LE((tri.position(r, s) - (t[0] + r * (t[1] - t[0]) + s * (t[2] - t[0]))).norm(), kRounding);
    EXPECT_LE(quad.evaluate(xi, eta).d_ss.norm() + quad.evaluate(xi, eta).d_tt.norm(), kRounding);
  }
}

TEST(QuadraticFaces, BezierControlPointsReproduceTheSurface) {
  // The Bernstein forms evaluated from the control points are the same surfaces: so the faces lie in their
  // convex hulls (what the surface search's bounding spheres assume).
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto b2 = [](double t) { return std::array<double, 3>{(1 - t) * (1 - t), 2 * t * (1 - t), t * t}; };
  for (int trial = 0; trial < 30; ++trial) {
    const SerendipityQuad quad(random_nodes<8>(rng));
    const auto c = quad.bezier_control_points();
    const QuadraticTriangle tri(random_nodes<6>(rng));
    const auto d = tri.bezier_control_points();
    for (int k = 0; k < 20; ++k) {
      const double a = u(rng), b = u(rng);  // Bezier parameters of the quad: xi = 2a - 1, eta = 2b - 1
      const auto ba = b2(a), bb = b2(b);
      Vec3 p = Vec3::Zero();
      for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) p += ba[i] * bb[j] * c[3 * j + i];
      }
      EXPECT_LE((p - quad.position(2 * a - 1, 2 * b - 1)).norm(), kRounding);
      const double r = a, s = b * (1 - a), l = 1 - r - s;
      const Vec3 q =
          l * l * d[0] + r * r * d[1] + s * s * d[2] + 2 * l * r * d[3] + 2 * r * s * d[4] + 2 * s * l * d[5];
      EXPECT_LE((q - tri.position(r, s)).norm(), kRounding);
    }
  }
}

TEST(QuadraticFaces, CharacteristicLengthIsTheLongestNodeDistance) {
  std::array<Vec3, 8> q;
  for (auto& p : q) p = Vec3::Zero();
  q[6] = Vec3(0, 3, 4);  // mid-side node C-D: 5 from every other node
  EXPECT_DOUBLE_EQ(SerendipityQuad(q).characteristic_length(), 5.0);
  std::array<Vec3, 6> t;
  for (auto& p : t) p = Vec3::Zero();
  t[1] = Vec3(1, 0, 0);
  t[4] = Vec3(1, 2, 2);  // 3 from A
  EXPECT_DOUBLE_EQ(QuadraticTriangle(t).characteristic_length(), 3.0);
}

}  // namespace
}  // namespace contactnn::geometry
