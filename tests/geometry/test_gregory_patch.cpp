// Tests for lib/geometry/gregory_patch.* and lib/geometry/node_normals.* (SPEC 3).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/node_normals.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::geometry {
namespace {

// Flat patch vs bilinear facet: both are the same polynomial, only rounding separates them (SPEC 1 asks
// exact).
constexpr double kFlatTol = 1e-12;
// Interpolation of nodes: P00 = A etc. enter with Bernstein weight exactly 1, the others exactly 0.
constexpr double kCornerTol = 1e-12;
// Corner normal vs node normal: both are unit vectors computed through a few cross products.
constexpr double kCornerNormalTol = 1e-10;
// G1: unit normals of the two patches along a shared edge; SPEC-level requirement.
constexpr double kG1Tol = 1e-9;
// Central differences with step h = min(kFdStep, kFdStepPerDenominator * smallest |denominator of Eqs
// 28-31|): the rational terms vary on the scale of their denominator d, truncation ~ (h / d)^2 ~ 1e-8,
// rounding ~ eps |f| / h ~ 1e-9 for the smallest d used (0.004).
constexpr double kFdStep = 1e-5;
constexpr double kFdStepPerDenominator = 1e-4;
constexpr double kFdTol = 1e-7;
// Known answers are short sums of exactly representable or one-rounding values.
constexpr double kKnownTol = 1e-14;
// evaluate() vs a literal transcription of Eqs 27-31: same maths, different order of summation.
constexpr double kLiteralTol = 1e-12;
// Node normals tilt from the segment's corner normal by an angle whose tangent is below this (paper 6.3.1).
constexpr double kMaxTiltTangent = 0.2;

using Rng = std::mt19937_64;

double uniform(Rng& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

Eigen::Matrix3d random_rotation(Rng& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return q.toRotationMatrix();
}

/// A random rigid motion with scale: x -> scale R x + shift.
struct Placement {
  Eigen::Matrix3d rotation;
  Vec3 shift;
  double scale;
  [[nodiscard]] Vec3 apply(const Vec3& x) const { return scale * (rotation * x) + shift; }
};

Placement random_placement(Rng& rng) {
  return Placement{random_rotation(rng), Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)),
                   uniform(rng, 0.5, 2.0)};
}

/// Unit vector tilted from unit `n` by an angle whose tangent is uniform in [0, max_tangent), random azimuth.
Vec3 tilt(const Vec3& n, double max_tangent, Rng& rng) {
  const Vec3 any = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = n.cross(any).normalized();
  const Vec3 e2 = n.cross(e1);
  const double azimuth = uniform(rng, 0.0, 2.0 * M_PI);
  return (n + uniform(rng, 0.0, max_tangent) * (std::cos(azimuth) * e1 + std::sin(azimuth) * e2))
      .normalized();
}

/// A random flat convex quadrilateral (paper frame: A = 0, B = e_x, C and D in (-2, 2)^2), then placed.
/// Returns the nodes; `plane_normal` gets the unit normal of the side (B - A) x (D - A).
std::array<Vec3, 4> random_flat_convex_quad(Rng& rng, Vec3& plane_normal) {
  for (;;) {
    const std::array<Vec3, 4> local = {Vec3(0, 0, 0), Vec3(1, 0, 0),
                                       Vec3(uniform(rng, -2, 2), uniform(rng, -2, 2), 0.0),
                                       Vec3(uniform(rng, -2, 2), uniform(rng, 0.05, 2), 0.0)};
    if (!is_convex(local)) continue;
    const Placement place = random_placement(rng);
    std::array<Vec3, 4> nodes{};
    for (int i = 0; i < 4; ++i) nodes[i] = place.apply(local[i]);
    plane_normal = place.rotation * Vec3::UnitZ();
    return nodes;
  }
}

/// The paper's Gregory setting (Section 6.3.1): A = 0, B = e_x, D in the xy-plane, C warped by z in (-0.3,
/// 0.3), convex, every interior angle in [60, 120] degrees; then placed randomly.
std::array<Vec3, 4> random_warped_quad(Rng& rng) {
  for (;;) {
    const std::array<Vec3, 4> local = {
        Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -0.3, 0.3)),
        Vec3(uniform(rng, -2, 2), uniform(rng, 0.05, 2), 0.0)};
    if (!is_convex(local)) continue;
    bool angles_ok = true;
    for (const double angle : interior_angles_degrees(local))
      angles_ok = angles_ok && angle >= 60 && angle <= 120;
    if (!angles_ok) continue;
    const Placement place = random_placement(rng);
    std::array<Vec3, 4> nodes{};
    for (int i = 0; i < 4; ++i) nodes[i] = place.apply(local[i]);
    return nodes;
  }
}

/// Node normals tilted from the segment's own corner normals, with random lengths (the patch normalises).
std::array<Vec3, 4> random_tilted_normals(const std::array<Vec3, 4>& nodes, Rng& rng) {
  std::array<Vec3, 4> normals{};
  for (int i = 0; i < 4; ++i) {
    const Vec3 corner = corner_normal(nodes[i], nodes[(i + 1) % 4], nodes[(i + 3) % 4]);
    normals[i] = uniform(rng, 0.1, 10.0) * tilt(corner, kMaxTiltTangent, rng);
  }
  return normals;
}

Vec3 unit_normal(const SurfacePoint& p) { return p.d_s.cross(p.d_t).normalized(); }

constexpr std::array<std::array<double, 2>, 4> kCornerUv = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};

/// The four signed denominators of Eqs 28-31 at (u, v).
std::array<double, 4> denominators(double u, double v) { return {u + v, 1 - u + v, u + 1 - v, 2 - u - v}; }

/// Eqs 27-31 transcribed literally from control_points(), with SPEC 3's guard: the reference for evaluate().
Vec3 literal_position(const GregoryPatch& patch, double u, double v) {
  const auto& cp = patch.control_points();
  auto bern = [](int i, double t) {
    const double binom[4] = {1, 3, 3, 1};
    return binom[i] * std::pow(t, i) * std::pow(1 - t, 3 - i);
  };
  auto blend = [&](double s, double t, int i, int j) -> Vec3 {
    const Vec3& p0 = cp[GregoryPatch::interior_index(i, j, 0)];
    const Vec3& p1 = cp[GregoryPatch::interior_index(i, j, 1)];
    if (std::abs(s + t) < GregoryPatch::kDenominatorGuard) return 0.5 * (p0 + p1);
    return (s * p0 + t * p1) / (s + t);
  };
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      Vec3 p = cp[GregoryPatch::control_index(i, j)];
      if (i == 1 && j == 1) p = blend(u, v, 1, 1);          // Eq 28
      if (i == 1 && j == 2) p = blend(u, 1 - v, 1, 2);      // Eq 29
      if (i == 2 && j == 1) p = blend(1 - u, v, 2, 1);      // Eq 30
      if (i == 2 && j == 2) p = blend(1 - u, 1 - v, 2, 2);  // Eq 31
      sum += bern(i, u) * bern(j, v) * p;
    }
  }
  return sum;
}

bool all_finite(const SurfacePoint& p) {
  return p.position.allFinite() && p.d_s.allFinite() && p.d_t.allFinite() && p.d_ss.allFinite() &&
         p.d_st.allFinite() && p.d_tt.allFinite();
}

// ---------------------------------------------------------------------------------------------------------

TEST(GregoryPatch, FlatSegmentWithPlaneNormalsIsTheBilinearFacet) {
  Rng rng(20070101);
  for (int trial = 0; trial < 200; ++trial) {
    Vec3 plane_normal;
    const std::array<Vec3, 4> nodes = random_flat_convex_quad(rng, plane_normal);
    std::array<Vec3, 4> normals{};
    for (auto& n : normals) n = uniform(rng, 0.1, 10.0) * plane_normal;  // any positive length
    const GregoryPatch gregory(nodes, normals);
    const BilinearPatch bilinear(nodes);
    const double tol = kFlatTol * gregory.characteristic_length();
    for (int k = 0; k < 24; ++k) {
      // The four corners first (guarded denominators), then random points.
      const double u = k < 4 ? kCornerUv[k][0] : uniform(rng, 0, 1);
      const double v = k < 4 ? kCornerUv[k][1] : uniform(rng, 0, 1);
      const SurfacePoint g = gregory.evaluate(u, v);
      const SurfacePoint b = bilinear.evaluate(2 * u - 1, 2 * v - 1);
      ASSERT_LT((g.position - b.position).norm(), tol) << "trial " << trial << " (u, v) = " << u << ", " << v;
      ASSERT_LT((gregory.position(u, v) - b.position).norm(), tol) << "trial " << trial;
      // d/du = 2 d/dxi, d/dv = 2 d/deta; second derivatives by the same chain rule.
      ASSERT_LT((g.d_s - 2 * b.d_s).norm(), tol) << "trial " << trial << " (u, v) = " << u << ", " << v;
      ASSERT_LT((g.d_t - 2 * b.d_t).norm(), tol) << "trial " << trial << " (u, v) = " << u << ", " << v;
      ASSERT_LT((g.d_st - 4 * b.d_st).norm(), 10 * tol)
          << "trial " << trial << " (u, v) = " << u << ", " << v;
      ASSERT_LT(g.d_ss.norm(), 10 * tol) << "trial " << trial << " (u, v) = " << u << ", " << v;
      ASSERT_LT(g.d_tt.norm(), 10 * tol) << "trial " << trial << " (u, v) = " << u << ", " << v;
    }
  }
}

TEST(GregoryPatch, InterpolatesCornersAndNodeNormals) {
  Rng rng(26);
  for (int trial = 0; trial < 300; ++trial) {
    const std::array<Vec3, 4> nodes = random_warped_quad(rng);
    const std::array<Vec3, 4> normals = random_tilted_normals(nodes, rng);
    const GregoryPatch patch(nodes, normals);
    const double tol = kCornerTol * patch.characteristic_length();
    for (int corner = 0; corner < 4; ++corner) {
      const double u = kCornerUv[corner][0], v = kCornerUv[corner][1];
      const SurfacePoint p = patch.evaluate(u, v);
      ASSERT_TRUE(all_finite(p)) << "trial " << trial << " corner " << corner;
      EXPECT_LT((p.position - nodes[corner]).norm(), tol) << "trial " << trial << " corner " << corner;
      EXPECT_LT((patch.position(u, v) - nodes[corner]).norm(), tol)
          << "trial " << trial << " corner " << corner;
      const Vec3 n_node = normals[corner].normalized();
      EXPECT_LT((unit_normal(p) - n_node).norm(), kCornerNormalTol)
          << "trial " << trial << " corner " << corner;
      // And the normal tends to it from inside (the corner value is not an artefact of the guard).
      const double du = (u == 0 ? 1 : -1) * 1e-7, dv = (v == 0 ? 1 : -1) * 2e-7;
      EXPECT_LT((unit_normal(patch.evaluate(u + du, v + dv)) - n_node).norm(), 1e-5)
          << "trial " << trial << " corner " << corner;
    }
  }
}

TEST(GregoryPatch, NeighbouringPatchesShareTheTangentPlaneAlongTheirEdge) {
  Rng rng(1983);
  int edges_checked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    // A warped 3 x 3 grid of nodes: 4 segments, 4 interior edges. Each segment's corner list starts at a
    // random corner, so shared edges meet with every combination of (u, v) sides and directions.
    std::vector<Vec3> positions;
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        positions.emplace_back(i + uniform(rng, -0.2, 0.2), j + uniform(rng, -0.2, 0.2),
                               uniform(rng, -0.3, 0.3));
      }
    }
    const Placement place = random_placement(rng);
    for (auto& x : positions) x = place.apply(x);
    std::vector<std::array<int, 4>> segments;
    for (int qj = 0; qj < 2; ++qj) {
      for (int qi = 0; qi < 2; ++qi) {
        const std::array<int, 4> ccw = {qi + 3 * qj, qi + 1 + 3 * qj, qi + 1 + 3 * (qj + 1),
                                        qi + 3 * (qj + 1)};
        const int shift = static_cast<int>(rng() % 4);
        segments.push_back({ccw[shift], ccw[(shift + 1) % 4], ccw[(shift + 2) % 4], ccw[(shift + 3) % 4]});
      }
    }
    // Shared node normals: Eq 26, then tilted (the edge shares its two node normals whatever they are).
    std::vector<Vec3> node_normals;
    for (int n = 0; n < 9; ++n)
      node_normals.push_back(tilt(node_normal(positions, segments, n), kMaxTiltTangent, rng));
    std::vector<GregoryPatch> patches;
    for (const auto& s : segments) {
      patches.emplace_back(
          std::array<Vec3, 4>{positions[s[0]], positions[s[1]], positions[s[2]], positions[s[3]]},
          std::array<Vec3, 4>{node_normals[s[0]], node_normals[s[1]], node_normals[s[2]],
                              node_normals[s[3]]});
    }
    for (int p1 = 0; p1 < 4; ++p1) {
      for (int p2 = p1 + 1; p2 < 4; ++p2) {
        for (int k1 = 0; k1 < 4; ++k1) {
          for (int k2 = 0; k2 < 4; ++k2) {
            // Edge k1 -> k1+1 of patch 1 is edge k2+1 -> k2 of patch 2 (opposite direction: both
            // counter-clockwise).
            if (segments[p1][k1] != segments[p2][(k2 + 1) % 4] ||
                segments[p1][(k1 + 1) % 4] != segments[p2][k2])
              continue;
            ++edges_checked;
            for (int step = 0; step <= 100; ++step) {
              const double t = step / 100.0;  // fraction from node segments[p1][k1] to segments[p1][k1+1]
              const auto& a1 = kCornerUv[k1];
              const auto& b1 = kCornerUv[(k1 + 1) % 4];
              const auto& a2 = kCornerUv[(k2 + 1) % 4];
              const auto& b2 = kCornerUv[k2];
              const SurfacePoint s1 =
                  patches[p1].evaluate((1 - t) * a1[0] + t * b1[0], (1 - t) * a1[1] + t * b1[1]);
              const SurfacePoint s2 =
                  patches[p2].evaluate((1 - t) * a2[0] + t * b2[0], (1 - t) * a2[1] + t * b2[1]);
              ASSERT_LT((s1.position - s2.position).norm(), kCornerTol * patches[p1].characteristic_length())
                  << "trial " << trial << " patches " << p1 << "," << p2 << " t " << t;
              const Vec3 n1 = unit_normal(s1), n2 = unit_normal(s2);
              ASSERT_LT(n1.cross(n2).norm(), kG1Tol)
                  << "trial " << trial << " patches " << p1 << "," << p2 << " t " << t;
              ASSERT_GT(n1.dot(n2), 0.0) << "trial " << trial << " patches " << p1 << "," << p2 << " t " << t;
            }
          }
        }
      }
    }
  }
  EXPECT_EQ(edges_checked, 60 * 4);
}

TEST(GregoryPatch, DerivativesMatchCentralDifferences) {
  Rng rng(31);
  double worst = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    const std::array<Vec3, 4> nodes = random_warped_quad(rng);
    const GregoryPatch patch(nodes, random_tilted_normals(nodes, rng));
    const double scale = patch.characteristic_length();
    std::vector<std::array<double, 2>> points;
    for (int k = 0; k < 10; ++k) points.push_back({uniform(rng, 0.02, 0.98), uniform(rng, 0.02, 0.98)});
    for (const auto& corner : kCornerUv) {  // near each corner, inside, but many steps h away from it
      for (int k = 0; k < 3; ++k) {
        const double du = uniform(rng, 0.002, 0.02), dv = uniform(rng, 0.002, 0.02);
        points.push_back({corner[0] == 0 ? du : 1 - du, corner[1] == 0 ? dv : 1 - dv});
      }
    }
    while (points.size() < 32) {  // just outside [0,1]^2, away from the lines where a denominator vanishes
      const double u = uniform(rng, -0.15, 1.15), v = uniform(rng, -0.15, 1.15);
      if (u >= 0 && u <= 1 && v >= 0 && v <= 1) continue;
      bool far = true;
      for (const double d : denominators(u, v)) far = far && std::abs(d) > 0.2;
      if (far) points.push_back({u, v});
    }
    for (const auto& [u, v] : points) {
      double smallest_denominator = std::numeric_limits<double>::infinity();
      for (const double d : denominators(u, v))
        smallest_denominator = std::min(smallest_denominator, std::abs(d));
      const double h = std::min(kFdStep, kFdStepPerDenominator * smallest_denominator);
      const SurfacePoint p = patch.evaluate(u, v);
      const SurfacePoint pu_plus = patch.evaluate(u + h, v), pu_minus = patch.evaluate(u - h, v);
      const SurfacePoint pv_plus = patch.evaluate(u, v + h), pv_minus = patch.evaluate(u, v - h);
      const std::array<std::pair<Vec3, Vec3>, 6> pairs = {{
          {p.d_s, (pu_plus.position - pu_minus.position) / (2 * h)},
          {p.d_t, (pv_plus.position - pv_minus.position) / (2 * h)},
          {p.d_ss, (pu_plus.d_s - pu_minus.d_s) / (2 * h)},
          {p.d_st, (pv_plus.d_s - pv_minus.d_s) / (2 * h)},
          {p.d_st, (pu_plus.d_t - pu_minus.d_t) / (2 * h)},
          {p.d_tt, (pv_plus.d_t - pv_minus.d_t) / (2 * h)},
      }};
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        const double error = (pairs[k].first - pairs[k].second).norm() / (scale + pairs[k].first.norm());
        worst = std::max(worst, error);
        ASSERT_LT(error, kFdTol) << "trial " << trial << " (u, v) = " << u << ", " << v << " derivative " << k
                                 << ": analytic " << pairs[k].first.transpose() << " vs FD "
                                 << pairs[k].second.transpose();
      }
      EXPECT_LT((patch.position(u, v) - p.position).norm(), kLiteralTol * scale);
    }
  }
  std::ostringstream worst_text;
  worst_text << worst;
  RecordProperty("worst_relative_fd_error", worst_text.str());
}

TEST(GregoryPatch, MatchesLiteralEquations27To31) {
  Rng rng(27);
  for (int trial = 0; trial < 50; ++trial) {
    const std::array<Vec3, 4> nodes = random_warped_quad(rng);
    const GregoryPatch patch(nodes, random_tilted_normals(nodes, rng));
    const double tol = kLiteralTol * patch.characteristic_length();
    for (int k = 0; k < 40; ++k) {
      const double u = uniform(rng, -0.5, 1.5), v = uniform(rng, -0.5, 1.5);
      bool far = true;
      for (const double d : denominators(u, v)) far = far && std::abs(d) > 0.05;
      if (!far) continue;
      const Vec3 expected = literal_position(patch, u, v);
      ASSERT_LT((patch.evaluate(u, v).position - expected).norm(), tol * (1 + expected.norm()))
          << "trial " << trial << " (u, v) = " << u << ", " << v;
      ASSERT_LT((patch.position(u, v) - expected).norm(), tol * (1 + expected.norm()))
          << "trial " << trial << " (u, v) = " << u << ", " << v;
    }
  }
}

TEST(GregoryPatch, GuardedDenominatorsGiveFiniteValuesAndTheMeanPoint) {
  Rng rng(14);
  const std::array<Vec3, 4> nodes = random_warped_quad(rng);
  const GregoryPatch patch(nodes, random_tilted_normals(nodes, rng));
  const auto& cp = patch.control_points();
  // Exactly on each zero line of Eqs 28-31 (corners inside the domain; lines through them outside), and
  // within the guard of one (|u + v| = 4e-15 after rounding).
  const std::vector<std::array<double, 2>> points = {
      {0, 0},      {1, 0},       {1, 1},      {0, 1},     {0.3, -0.3},  {-0.4, 0.4}, {0.25, 1.25},
      {-0.5, 0.5}, {1.25, 0.25}, {0.5, -0.5}, {1.5, 0.5}, {0.75, 1.25}, {2.0, 0.0},  {0.5, -0.5 + 4e-15}};
  for (const auto& [u, v] : points) {
    const SurfacePoint p = patch.evaluate(u, v);
    ASSERT_TRUE(all_finite(p)) << "(u, v) = " << u << ", " << v;
    ASSERT_TRUE(patch.position(u, v).allFinite()) << "(u, v) = " << u << ", " << v;
    // The guarded point is the mean of its two points: compare with the literal Eqs 27-31 with that rule.
    EXPECT_LT((p.position - literal_position(patch, u, v)).norm(), kLiteralTol * (1 + p.position.norm()))
        << "(u, v) = " << u << ", " << v;
  }
  // At the corners the first derivatives are the continuous limits 3 (P10 - P00), 3 (P01 - P00), etc.
  using G = GregoryPatch;
  const SurfacePoint at_a = patch.evaluate(0, 0);
  EXPECT_LT((at_a.d_s - 3 * (cp[G::control_index(1, 0)] - cp[G::control_index(0, 0)])).norm(),
            kKnownTol * 10);
  EXPECT_LT((at_a.d_t - 3 * (cp[G::control_index(0, 1)] - cp[G::control_index(0, 0)])).norm(),
            kKnownTol * 10);
  const SurfacePoint at_c = patch.evaluate(1, 1);
  EXPECT_LT((at_c.d_s - 3 * (cp[G::control_index(3, 3)] - cp[G::control_index(2, 3)])).norm(),
            kKnownTol * 10);
  EXPECT_LT((at_c.d_t - 3 * (cp[G::control_index(3, 3)] - cp[G::control_index(3, 2)])).norm(),
            kKnownTol * 10);
}

// Unit square A = 0, B = e_x, C = (1,1,0), D = e_y; n_A = (3, 0, 4) (unit (0.6, 0, 0.8)), the others (0, 0,
// 2). With c = 0.8, s = 0.6 written out by hand from SPEC 3:
//   E(A->B) = (1/3)(c^2, 0, -s c) = (0.64/3, 0, -0.16); E(A->D) = (0, 1/3, 0); all other edge points are
//   thirds. Edge A->B: a0 = a3 = e_y, b0 = b3 = (0, 1/3, 0), k0 = k1 = 1/3, h0 = h1 = 0 -> b1 = b2 = (0, 1/3,
//   0):
//     P110 = (0.64/3, 1/3, -0.16), P210 = (2/3, 1/3, 0).
//   Edge D->A: a0 = e_x, a3 = unit(n_A x -e_y) = (c, 0, -s), b0 = (1/3, 0, 0), b3 = E(A->B) - A,
//     k0 = 1/3, k1 = a3.b3 = c/3, h0 = h1 = 0;
//     b1 = [(1+c)/3 e_x + (1/3)(c, 0, -s)]/3 = ((1+2c)/9, 0, -s/9)  -> P121 = (2.6/9, 2/3, -0.6/9);
//     b2 = [(1+c)/3 (c, 0, -s) + (c/3) e_x]/3 = ((2c+c^2)/9, 0, -(1+c)s/9) -> P111 = (2.24/9, 1/3, -0.12).
//   Edges B->C, C->D (flat, normals e_z): P211 = (2/3,1/3,0), P221 = P220 = (2/3,2/3,0), P120 = (1/3,2/3,0).
//   P(0.5, 0.5): Bernstein (1,3,3,1)/8; only P10, P11 = (P110+P111)/2, P12 = (P120+P121)/2 leave the flat
//   grid,
//     with weights 3/64, 9/64, 9/64: x = 0.5 + (3(-0.12) + 9(-0.92/9) + 9(-0.2/9))/64 = 0.476875,
//     y = 0.5, z = (3(-0.16) + 9(-0.14) + 9(-1/30))/64 = -0.031875.
//   Corner normal at A: 3(P10 - A) x 3(P01 - A) = (0.64, 0, -0.48) x (0, 1, 0) = (0.48, 0, 0.64) = 0.8 n_A.
TEST(GregoryPatch, KnownAnswerUnitSquareWithTiltedNormalAtA) {
  const std::array<Vec3, 4> nodes = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> normals = {Vec3(3, 0, 4), Vec3(0, 0, 2), Vec3(0, 0, 2), Vec3(0, 0, 2)};
  const GregoryPatch patch(nodes, normals);
  using G = GregoryPatch;
  const auto& cp = patch.control_points();
  const double third = 1.0 / 3.0, two_thirds = 2.0 / 3.0;
  struct Expected {
    int index;
    Vec3 point;
  };
  const std::vector<Expected> expected = {
      {G::control_index(0, 0), Vec3(0, 0, 0)},
      {G::control_index(1, 0), Vec3(0.64 / 3, 0, -0.16)},
      {G::control_index(2, 0), Vec3(two_thirds, 0, 0)},
      {G::control_index(3, 0), Vec3(1, 0, 0)},
      {G::control_index(3, 1), Vec3(1, third, 0)},
      {G::control_index(3, 2), Vec3(1, two_thirds, 0)},
      {G::control_index(3, 3), Vec3(1, 1, 0)},
      {G::control_index(2, 3), Vec3(two_thirds, 1, 0)},
      {G::control_index(1, 3), Vec3(third, 1, 0)},
      {G::control_index(0, 3), Vec3(0, 1, 0)},
      {G::control_index(0, 2), Vec3(0, two_thirds, 0)},
      {G::control_index(0, 1), Vec3(0, third, 0)},
      {G::interior_index(1, 1, 0), Vec3(0.64 / 3, third, -0.16)},
      {G::interior_index(2, 1, 0), Vec3(two_thirds, third, 0)},
      {G::interior_index(2, 1, 1), Vec3(two_thirds, third, 0)},
      {G::interior_index(2, 2, 1), Vec3(two_thirds, two_thirds, 0)},
      {G::interior_index(2, 2, 0), Vec3(two_thirds, two_thirds, 0)},
      {G::interior_index(1, 2, 0), Vec3(third, two_thirds, 0)},
      {G::interior_index(1, 2, 1), Vec3(2.6 / 9, two_thirds, -0.6 / 9)},
      {G::interior_index(1, 1, 1), Vec3(2.24 / 9, third, -0.12)},
  };
  ASSERT_EQ(expected.size(), 20u);
  for (const auto& [index, point] : expected) {
    EXPECT_LT((cp[index] - point).norm(), kKnownTol)
        << "control point " << index << ": " << cp[index].transpose() << " expected " << point.transpose();
  }
  // The documented numeric order of control_points().
  EXPECT_EQ(G::control_index(3, 3), 15);
  EXPECT_EQ(G::control_index(0, 3), 12);
  EXPECT_EQ(G::interior_index(1, 1, 0), 5);
  EXPECT_EQ(G::interior_index(2, 2, 0), 10);
  EXPECT_EQ(G::interior_index(1, 1, 1), 16);
  EXPECT_EQ(G::interior_index(2, 2, 1), 19);

  EXPECT_LT((patch.position(0.5, 0.5) - Vec3(0.476875, 0.5, -0.031875)).norm(), kKnownTol);
  EXPECT_LT((patch.evaluate(0.5, 0.5).position - Vec3(0.476875, 0.5, -0.031875)).norm(), kKnownTol);
  const SurfacePoint at_a = patch.evaluate(0, 0);
  EXPECT_LT((at_a.d_s.cross(at_a.d_t) - Vec3(0.48, 0, 0.64)).norm(), kKnownTol);
  EXPECT_LT((patch.normals()[0] - Vec3(0.6, 0, 0.8)).norm(), kKnownTol);
  EXPECT_DOUBLE_EQ(patch.characteristic_length(), std::sqrt(2.0));
}

TEST(GregoryPatch, RejectsInputsThatDefineNoPatch) {
  const std::array<Vec3, 4> nodes = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> up = {Vec3::UnitZ(), Vec3::UnitZ(), Vec3::UnitZ(), Vec3::UnitZ()};
  EXPECT_EQ(GregoryPatch::diagnose(nodes, up), GregoryDefect::kNone);

  auto nan_node = nodes;
  nan_node[2].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(GregoryPatch::diagnose(nan_node, up), GregoryDefect::kNonFinite);
  auto inf_normal = up;
  inf_normal[1].x() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(GregoryPatch::diagnose(nodes, inf_normal), GregoryDefect::kNonFinite);

  auto zero_normal = up;
  zero_normal[3] = Vec3::Zero();
  EXPECT_EQ(GregoryPatch::diagnose(nodes, zero_normal), GregoryDefect::kZeroNormal);
  EXPECT_THROW(GregoryPatch(nodes, zero_normal), InvalidArgument);

  auto along_edge = up;
  along_edge[0] = Vec3(-2, 0, 0);  // n_A parallel to AB: E(A->B) = A
  EXPECT_EQ(GregoryPatch::diagnose(nodes, along_edge), GregoryDefect::kDegenerateEdge);
  EXPECT_THROW(GregoryPatch(nodes, along_edge), InvalidArgument);

  auto coincident = nodes;
  coincident[3] = coincident[0];
  EXPECT_EQ(GregoryPatch::diagnose(coincident, up), GregoryDefect::kDegenerateEdge);

  // Tiny and huge normals are fine: only their direction counts.
  std::array<Vec3, 4> extreme = {1e-300 * Vec3::UnitZ(), 1e300 * Vec3(0, 1, 1e3), Vec3::UnitZ(),
                                 Vec3::UnitZ()};
  EXPECT_EQ(GregoryPatch::diagnose(nodes, extreme), GregoryDefect::kNone);
  EXPECT_LT((GregoryPatch(nodes, extreme).normals()[0] - Vec3::UnitZ()).norm(), kKnownTol);
  // Down to the smallest subnormal: any component not zero is a direction.
  extreme[0] = std::numeric_limits<double>::denorm_min() * Vec3(0, 0, 3);
  EXPECT_EQ(GregoryPatch::diagnose(nodes, extreme), GregoryDefect::kNone);
  EXPECT_LT((GregoryPatch(nodes, extreme).normals()[0] - Vec3::UnitZ()).norm(), kKnownTol);
  // The normals the diagnosis hands back are the patch's own, bit for bit.
  std::array<Vec3, 4> unit;
  ASSERT_EQ(GregoryPatch::diagnose(nodes, extreme, &unit), GregoryDefect::kNone);
  const GregoryPatch patch(nodes, extreme);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(unit[i], patch.normals()[i]) << i;
  EXPECT_EQ(GregoryPatch::control_points_of(nodes, unit), patch.control_points());
}

TEST(GregoryPatch, ModelsTheSurfaceConcept) {
  static_assert(Surface<GregoryPatch>);
  static_assert(GregoryPatch::kKind == SurfaceKind::kGregory);
  SUCCEED();
}

// A roof: the right segment is twice as wide as the left. Corner normals at O = 0: right (R - O) x (Y - O) =
// (-2, 0, 2), left (Y - O) x (L - O) = (1, 0, 1). SPEC 3 sums unit corner normals: (0, 0, sqrt 2) -> e_z;
// the un-normalised sum of Eq 26 as printed would give unit(-1, 0, 3).
TEST(NodeNormal, SumsUnitCornerNormalsOfTheSegmentsSharingTheNode) {
  const std::vector<Vec3> positions = {Vec3(0, 0, 0), Vec3(0, 1, 0),  Vec3(2, 0, 2),
                                       Vec3(2, 1, 2), Vec3(-1, 0, 1), Vec3(-1, 1, 1)};
  const std::vector<std::array<int, 4>> segments = {{0, 2, 3, 1}, {4, 0, 1, 5}};
  EXPECT_LT((node_normal(positions, segments, 0) - Vec3::UnitZ()).norm(), kKnownTol);
  EXPECT_LT((node_normal(positions, segments, 1) - Vec3::UnitZ()).norm(), kKnownTol);
  // A node of one segment only gets that segment's corner normal.
  EXPECT_LT((node_normal(positions, segments, 2) - Vec3(-1, 0, 1) / std::sqrt(2.0)).norm(), kKnownTol);
  EXPECT_LT((node_normal(positions, segments, 4) - Vec3(1, 0, 1) / std::sqrt(2.0)).norm(), kKnownTol);
  EXPECT_LT(
      (corner_normal(positions[0], positions[2], positions[1]) - Vec3(-1, 0, 1) / std::sqrt(2.0)).norm(),
      kKnownTol);
}

TEST(NodeNormal, FailsLoudlyOnBadMeshes) {
  const std::vector<Vec3> positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                                       Vec3(5, 5, 5)};
  const std::vector<std::array<int, 4>> segments = {{0, 1, 2, 3}};
  EXPECT_THROW((void)node_normal(positions, segments, 4), InvalidArgument);   // in no segment
  EXPECT_THROW((void)node_normal(positions, segments, 5), InvalidArgument);   // out of range
  EXPECT_THROW((void)node_normal(positions, segments, -1), InvalidArgument);  // out of range
  const std::vector<std::array<int, 4>> bad_index = {{0, 1, 2, 7}};
  EXPECT_THROW((void)node_normal(positions, bad_index, 0), InvalidArgument);
  EXPECT_THROW((void)corner_normal(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)),
               InvalidArgument);  // collinear
  // Two corners facing each other cancel.
  const std::vector<std::array<int, 4>> folded = {{0, 1, 2, 3}, {0, 3, 2, 1}};
  EXPECT_THROW((void)node_normal(positions, folded, 0), InvalidArgument);
}

}  // namespace
}  // namespace contactnn::geometry
