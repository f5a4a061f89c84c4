// projection::closest_point_on_serendipity_quad and closest_point_on_quadratic_triangle (SPEC 9's quad8 and
// tri6 labels), and closest_point_on_triangle (tri3), against an independent oracle written here: the faces
// by their textbook shape functions, dense sampling of the interior and of each edge, every sampled local
// minimum refined by Newton on the gradient of |S - P|^2 whose derivatives are central differences of
// positions (exact for these faces, quadratic in each parameter), the nearest candidate wins. No code of
// lib/projection is used.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "projection/closest_point_on_quadratic_face.hpp"

namespace contactnn::projection {
namespace {

using geometry::QuadraticTriangle;
using geometry::SerendipityQuad;

// The bound: labels agree with the oracle to 1e-10 of the face size.
constexpr double kLabelTol = 1e-10;
// Two oracle candidates whose distances differ by less than this (relative) are a tie: the point is then not
// compared (either is right), only the distance.
constexpr double kTieGap = 1e-8;
// Results of exact rewritings of the same face (relabelled nodes) agree to rounding.
constexpr double kRelabelTol = 1e-12;

/// A face as the oracle sees it: its nodes (SPEC 9's order) and the textbook shape functions.
struct OracleFace {
  bool triangle = false;
  std::vector<Vec3> x;

  [[nodiscard]] Vec3 at(double a, double b) const {
    if (triangle) {
      const double l[3] = {1 - a - b, a, b};
      return l[0] * (2 * l[0] - 1) * x[0] + l[1] * (2 * l[1] - 1) * x[1] + l[2] * (2 * l[2] - 1) * x[2] +
             4 * l[0] * l[1] * x[3] + 4 * l[1] * l[2] * x[4] + 4 * l[2] * l[0] * x[5];
    }
    const double s[4] = {-1, 1, 1, -1}, t[4] = {-1, -1, 1, 1};
    Vec3 p = Vec3::Zero();
    for (int i = 0; i < 4; ++i)
      p +=
          0.25 * (1 + s[i] * a) * (1 + t[i] * b) * (s[i] * a + t[i] * b - 1) * x[static_cast<std::size_t>(i)];
    p += 0.5 * (1 - a * a) * (1 - b) * x[4] + 0.5 * (1 + a) * (1 - b * b) * x[5] +
         0.5 * (1 - a * a) * (1 + b) * x[6] + 0.5 * (1 - a) * (1 - b * b) * x[7];
    return p;
  }
  [[nodiscard]] bool inside(double a, double b, double margin) const {
    return triangle ? a >= -margin && b >= -margin && a + b <= 1 + margin
                    : a >= -1 - margin && a <= 1 + margin && b >= -1 - margin && b <= 1 + margin;
  }
  [[nodiscard]] int edges() const { return triangle ? 3 : 4; }
  /// Edge e's point at t in [0, 1] (from its first corner to its second), in face parameters.
  [[nodiscard]] std::array<double, 2> edge_param(int e, double t) const {
    if (triangle) {
      const double p[3][2] = {{t, 0}, {1 - t, t}, {0, 1 - t}};
      return {p[e][0], p[e][1]};
    }
    const double p[4][2] = {{-1 + 2 * t, -1}, {1, -1 + 2 * t}, {1 - 2 * t, 1}, {-1, 1 - 2 * t}};
    return {p[e][0], p[e][1]};
  }
  [[nodiscard]] double size() const {
    double longest = 0;
    for (const auto& p : x) {
      for (const auto& q : x) longest = std::max(longest, (p - q).norm());
    }
    return longest;
  }
};

struct OraclePoint {
  std::array<double, 2> param{0, 0};
  Vec3 point = Vec3::Zero();
  double distance = std::numeric_limits<double>::infinity();
  Location location = Location::kFace;
  int feature = -1;
  double runner_up = std::numeric_limits<double>::infinity();  ///< nearest other candidate (a distinct point)
};

/// Keeps the nearest candidate and the nearest one at a distinct point.
void offer(OraclePoint& best, const OracleFace& face, const Vec3& s, std::array<double, 2> param,
           Location location, int feature) {
  const Vec3 p = face.at(param[0], param[1]);
  const double d = (s - p).norm();
  const bool same_point = (p - best.point).norm() <= 1e-7 * face.size();
  if (d < best.distance) {
    if (!same_point) best.runner_up = best.distance;
    best.param = param;
    best.point = p;
    best.distance = d;
    best.location = location;
    best.feature = feature;
  } else if (!same_point) {
    best.runner_up = std::min(best.runner_up, d);
  }
}

OraclePoint oracle_closest_point(const OracleFace& face, const Vec3& s) {
  OraclePoint best;
  const double h = 1e-3;  // positions are quadratic in each parameter: central differences are exact
  const auto f = [&](double a, double b) { return (s - face.at(a, b)).squaredNorm(); };
  const auto gradient = [&](double a, double b) {
    const Vec3 r = face.at(a, b) - s;
    return std::array<double, 2>{((face.at(a + h, b) - face.at(a - h, b)) / (2 * h)).dot(r),
                                 ((face.at(a, b + h) - face.at(a, b - h)) / (2 * h)).dot(r)};
  };
  // Interior: the grid's local minima, each refined by Newton on the gradient (Hessian by central
  // differences of the gradient: not exact, which only slows Newton, never moves its root).
  const int n = 80;
  const double lo = face.triangle ? 0.0 : -1.0, width = face.triangle ? 1.0 : 2.0;
  const auto grid = [&](int i) { return lo + width * i / n; };
  // (Boundary grid points too: an interior minimum within a grid cell of an edge has its grid minimum there.)
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double a = grid(i), b = grid(j);
      if (!face.inside(a, b, 1e-12)) continue;
      const double here = f(a, b);
      bool minimum = true;
      for (int di = -1; di <= 1 && minimum; ++di) {
        for (int dj = -1; dj <= 1; ++dj) {
          if ((di != 0 || dj != 0) && face.inside(grid(i + di), grid(j + dj), 1e-12) &&
              f(grid(i + di), grid(j + dj)) < here) {
            minimum = false;
            break;
          }
        }
      }
      if (!minimum) continue;
      std::array<double, 2> p{a, b};
      bool converged = false;
      double last_step = 1.0;
      for (int it = 0; it < 60; ++it) {
        const double e = 1e-6;
        const auto g = gradient(p[0], p[1]);
        const auto ga = gradient(p[0] + e, p[1]), gb = gradient(p[0], p[1] + e);
        const auto gA = gradient(p[0] - e, p[1]), gB = gradient(p[0], p[1] - e);
        const double h00 = (ga[0] - gA[0]) / (2 * e), h11 = (gb[1] - gB[1]) / (2 * e);
        const double h01 = 0.5 * ((ga[1] - gA[1]) / (2 * e) + (gb[0] - gB[0]) / (2 * e));
        const double det = h00 * h11 - h01 * h01;
        if (!(h00 > 0 && det > 0)) break;
        const double d0 = (h11 * g[0] - h01 * g[1]) / det, d1 = (h00 * g[1] - h01 * g[0]) / det;
        p = {std::clamp(p[0] - d0, lo - width, lo + 2 * width),
             std::clamp(p[1] - d1, lo - width, lo + 2 * width)};
        last_step = std::max(std::abs(d0), std::abs(d1));
      }
      converged =
          last_step < 1e-8;  // steps at rounding level (~1e-12 here) after 60 of (near-quadratic) convergence
      if (converged && face.inside(p[0], p[1], 1e-12)) offer(best, face, s, p, Location::kFace, -1);
    }
  }
  // Edges: 4001 samples each, the ends (vertices) included, sampled local minima refined by 1-D Newton.
  const int m = 4000;
  for (int e = 0; e < face.edges(); ++e) {
    const auto g = [&](double t) {
      const auto p = face.edge_param(e, t), q = face.edge_param(e, t + h), r = face.edge_param(e, t - h);
      return ((face.at(q[0], q[1]) - face.at(r[0], r[1])) / (2 * h)).dot(face.at(p[0], p[1]) - s);
    };
    const auto ft = [&](double t) {
      const auto p = face.edge_param(e, t);
      return f(p[0], p[1]);
    };
    for (int i = 0; i <= m; ++i) {
      const double t0 = static_cast<double>(i) / m;
      if ((i > 0 && ft(static_cast<double>(i - 1) / m) < ft(t0)) ||
          (i < m && ft(static_cast<double>(i + 1) / m) < ft(t0))) {
        continue;
      }
      double t = t0;
      {  // the ends too: a minimum just inside an edge has its sampled minimum at the end
        for (int it = 0; it < 100; ++it) {
          const double e1 = 1e-6, slope = (g(t + e1) - g(t - e1)) / (2 * e1);
          if (!(slope > 0)) break;
          const double next = std::clamp(t - g(t) / slope, 0.0, 1.0);
          const bool done = std::abs(next - t) < 1e-15;
          t = next;
          if (done) break;
        }
      }
      const bool vertex = t <= 0.0 || t >= 1.0;
      const int corner = t >= 1.0 ? (e + 1) % face.edges() : e;
      offer(best, face, s, face.edge_param(e, t), vertex ? Location::kVertex : Location::kEdge,
            vertex ? corner : e);
    }
  }
  return best;
}

/// A curved quad8 (triangle: tri6) of size about 2: the reference square's (triangle's) corners moved by up
/// to 0.2, its mid-side nodes off their edges' midpoints by up to 0.2 in the plane and `bulge` x 2 out of it
/// (a valid element: its mid-side nodes well away from the quarter points); then rotated, scaled by 10^[-1,
/// 2] and moved by up to 50 (the face stays at least 1/500 of its distance from the origin: 1e-10 of its size
/// is above the rounding of its coordinates).
OracleFace random_face(std::mt19937_64& rng, bool triangle, double bulge) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), log_scale(-1.0, 2.0), shift(-50.0, 50.0);
  std::normal_distribution<double> g;
  OracleFace face;
  face.triangle = triangle;
  const std::vector<Vec3> corners =
      triangle ? std::vector<Vec3>{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)}
               : std::vector<Vec3>{Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
  for (const Vec3& c : corners) face.x.push_back(c + 0.2 * Vec3(u(rng), u(rng), u(rng)));
  const std::size_t k = corners.size();
  for (std::size_t e = 0; e < k; ++e) {
    face.x.push_back(0.5 * (face.x[e] + face.x[(e + 1) % k]) +
                     Vec3(0.2 * u(rng), 0.2 * u(rng), 2.0 * bulge * u(rng)));
  }
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  const double scale = std::pow(10.0, log_scale(rng));
  const Vec3 t(shift(rng), shift(rng), shift(rng));
  for (Vec3& p : face.x) p = scale * (q * p) + t;
  return face;
}

/// A slave node around the face: its point at random parameters (beyond the face by up to 60% of it in each
/// direction, so that edges and vertices are nearest too), plus up to `offset` x the face size along the
/// normal.
Vec3 random_slave(std::mt19937_64& rng, const OracleFace& face, double offset = 0.4) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double lo = face.triangle ? -0.6 : -1.6, hi = face.triangle ? 1.6 : 1.6;
  std::uniform_real_distribution<double> p(lo, hi);
  const double a = p(rng), b = p(rng);
  const double h = 1e-4;
  const Vec3 n =
      (face.at(a + h, b) - face.at(a - h, b)).cross(face.at(a, b + h) - face.at(a, b - h)).normalized();
  return face.at(a, b) + offset * face.size() * u(rng) * n;
}

FaceClosestPoint label(const OracleFace& face, const Vec3& s, const ProjectionOptions& options = {}) {
  if (face.triangle) {
    std::array<Vec3, 6> x;
    std::copy(face.x.begin(), face.x.end(), x.begin());
    return closest_point_on_quadratic_triangle(QuadraticTriangle(x), s, options);
  }
  std::array<Vec3, 8> x;
  std::copy(face.x.begin(), face.x.end(), x.begin());
  return closest_point_on_serendipity_quad(SerendipityQuad(x), s, options);
}

/// Labels of `slaves` random slaves (up to `offset` x the face size off it) of each of `faces` random faces
/// against the oracle; returns how many were compared by location (not a tie, not within 1e-8 of a boundary).
int compare_with_oracle(bool triangle, double bulge, double offset, int faces, int slaves, unsigned seed,
                        int (&by_location)[3]) {
  std::mt19937_64 rng(seed);
  int compared = 0;
  for (int i = 0; i < faces; ++i) {
    const OracleFace face = random_face(rng, triangle, bulge);
    const double size = face.size();
    for (int j = 0; j < slaves; ++j) {
      const Vec3 s = random_slave(rng, face, offset);
      const OraclePoint want = oracle_closest_point(face, s);
      const FaceClosestPoint got = label(face, s);
      SCOPED_TRACE(::testing::Message() << (triangle ? "tri6" : "quad8") << " face " << i << " slave " << j);
      EXPECT_EQ(got.status, Status::kOk);
      if (got.status != Status::kOk) continue;
      EXPECT_NEAR(got.distance, want.distance, kLabelTol * size);
      EXPECT_LE((got.point - face.at(got.param[0], got.param[1])).norm(),
                kLabelTol * size);  // P is the face's
      EXPECT_TRUE(face.inside(got.param[0], got.param[1], 0.0)) << got.param[0] << ", " << got.param[1];
      if (want.runner_up - want.distance <= kTieGap * size) continue;
      EXPECT_LE((got.point - want.point).norm(), kLabelTol * size)
          << "oracle " << want.param[0] << ", " << want.param[1] << " label " << got.param[0] << ", "
          << got.param[1];
      // The location where it is unambiguous (the oracle's point not within 1e-8 of a bound it is not on).
      const double a = want.param[0], b = want.param[1], m = 1e-8;
      const bool near_bound =
          want.location == Location::kFace ? !face.inside(a, b, -m)
          : want.location == Location::kEdge
              ? (face.triangle ? std::min({a, b, 1 - a - b}) < m && std::max({a, b, 1 - a - b}) > 1 - m
                               : std::abs(std::abs(a) - 1) < m && std::abs(std::abs(b) - 1) < m)
              : false;
      if (near_bound) continue;
      EXPECT_EQ(got.location, want.location);
      EXPECT_EQ(got.feature, want.feature);
      ++by_location[static_cast<int>(want.location)];
      ++compared;
    }
  }
  return compared;
}

/// compare_with_oracle on curved faces of one type (tri6 when `triangle`, else quad8): over 200 points
/// compared, interior, edge and vertex points all among them.
void expect_agreement_at_every_location(bool triangle, unsigned seed) {
  int by_location[3] = {0, 0, 0};
  const int compared = compare_with_oracle(triangle, 0.1, 0.4, 12, 25, seed, by_location);
  EXPECT_GT(compared, 200);
  EXPECT_GT(by_location[0], 20);
  EXPECT_GT(by_location[1], 20);
  EXPECT_GT(by_location[2], 10);
}

TEST(ClosestPointOnQuadraticFace, Quad8LabelsAgreeWithTheIndependentOracle) {
  expect_agreement_at_every_location(false, 21);
}

TEST(ClosestPointOnQuadraticFace, Tri6LabelsAgreeWithTheIndependentOracle) {
  expect_agreement_at_every_location(true, 22);
}

TEST(ClosestPointOnQuadraticFace, Tri3LabelsAgreeWithTheOracleOnFlatTriangles) {
  // A tri6 with every mid-side node at its edge's midpoint is the flat triangle of its corners: the oracle's
  // answer for it is tri3's exact closest point.
  std::mt19937_64 rng(23);
  for (int i = 0; i < 10; ++i) {
    OracleFace face = random_face(rng, true, 0.0);
    for (std::size_t e = 0; e < 3; ++e) face.x[3 + e] = 0.5 * (face.x[e] + face.x[(e + 1) % 3]);
    for (int j = 0; j < 25; ++j) {
      const Vec3 s = random_slave(rng, face);
      const OraclePoint want = oracle_closest_point(face, s);
      const FaceClosestPoint got = closest_point_on_triangle({face.x[0], face.x[1], face.x[2]}, s);
      ASSERT_EQ(got.status, Status::kOk);
      EXPECT_NEAR(got.distance, want.distance, kLabelTol * face.size());
      EXPECT_LE((got.point - want.point).norm(), kLabelTol * face.size());
      const FaceClosestPoint quadratic = label(face, s);
      EXPECT_LE((quadratic.point - got.point).norm(), kLabelTol * face.size());
      EXPECT_EQ(quadratic.location, got.location);
    }
  }
}

TEST(ClosestPointOnQuadraticFace, StronglyCurvedFacesStillAgreeWithTheOracle) {
  // Mid-side nodes up to 0.6 out of the plane on edges of length 2: arcs of up to about 120 degrees; slave
  // nodes within 0.1 of the face size of it, as contacts are (nearer the centres of curvature, on the concave
  // side, several minima come within rounding of each other and neither search promises the global one).
  int by_location[3] = {0, 0, 0};
  EXPECT_GT(compare_with_oracle(false, 0.3, 0.1, 6, 20, 24, by_location), 50);
  EXPECT_GT(compare_with_oracle(true, 0.3, 0.1, 6, 20, 25, by_location), 50);
}

TEST(ClosestPointOnQuadraticFace, EveryNodeOrderOfAFaceGivesTheSamePoint) {
  // The 8 orders of a quad8 (4 cyclic relabellings, each mirrored: A, D, C, B with the mid-sides of A-D, D-C,
  // C-B, B-A) and the 6 of a tri6 describe the same surface: the same point and distance; the mirror's normal
  // is the opposite one.
  std::mt19937_64 rng(26);
  for (const bool triangle : {false, true}) {
    for (int i = 0; i < 6; ++i) {
      const OracleFace face = random_face(rng, triangle, 0.1);
      const std::size_t k = triangle ? 3 : 4;
      for (int j = 0; j < 20; ++j) {
        const Vec3 s = random_slave(rng, face);
        const FaceClosestPoint own = label(face, s);
        for (std::size_t shift = 0; shift < k; ++shift) {
          for (const bool mirror : {false, true}) {
            OracleFace other = face;
            for (std::size_t c = 0; c < k; ++c) {
              // Corner c of the new order and the mid-side node of its edge to corner c + 1.
              const std::size_t from = mirror ? (shift + k - c) % k : (shift + c) % k;
              other.x[c] = face.x[from];
              other.x[k + c] = mirror ? face.x[k + (from + k - 1) % k] : face.x[k + from];
            }
            const FaceClosestPoint p = label(other, s);
            SCOPED_TRACE(::testing::Message()
                         << (triangle ? "tri6" : "quad8") << " shift " << shift << " mirror " << mirror);
            ASSERT_EQ(p.status, Status::kOk);
            EXPECT_LE((p.point - own.point).norm(), kRelabelTol * face.size() + 1e-9 * own.distance);
            EXPECT_NEAR(p.distance, own.distance, kRelabelTol * face.size());
            EXPECT_EQ(p.location, own.location);
            if (own.location == Location::kFace) {
              EXPECT_LE((p.normal - (mirror ? -1.0 : 1.0) * own.normal).norm(), 1e-9);
            }
          }
        }
      }
    }
  }
}

TEST(ClosestPointOnQuadraticFace, AParabolicCylinderWrittenOut) {
  // P = (xi, eta, xi^2 / 2) is exactly a quad8 (z = x^2 / 2 over [-1, 1]^2: mid-side nodes on the parabola).
  const std::array<Vec3, 8> x = {Vec3(-1, -1, 0.5), Vec3(1, -1, 0.5), Vec3(1, 1, 0.5), Vec3(-1, 1, 0.5),
                                 Vec3(0, -1, 0),    Vec3(1, 0, 0.5),  Vec3(0, 1, 0),   Vec3(-1, 0, 0.5)};
  const SerendipityQuad face(x);
  const FaceClosestPoint above = closest_point_on_serendipity_quad(face, Vec3(0.3, 0.25, 2.0));
  // d/dx [(x - 0.3)^2 + (x^2/2 - 2)^2] = 2(x - 0.3) + 2x (x^2/2 - 2) = 0  <=>  x^3 / 2 - x - 0.3 = 0: on [-1,
  // 1], the one root (near -0.3) is a maximum of f = (x - 0.3)^2 + (x^2/2 - 2)^2, smallest at the end x = 1
  // (f(1) = 0.49 + 2.25 = 2.74 < f(-1) = 3.94): edge B-C, eta = 0.25.
  EXPECT_EQ(above.location, Location::kEdge);
  EXPECT_EQ(above.feature, 1);
  EXPECT_NEAR(above.point.x(), 1.0, 1e-15);
  EXPECT_NEAR(above.point.y(), 0.25, 1e-12);
  EXPECT_NEAR(above.distance, std::sqrt(2.74), 1e-12);
  // Below the vertex of the parabola: the interior point (0.3 -> x with x - 0.3 + x (x^2/2 + 1) = 0).
  const FaceClosestPoint below = closest_point_on_serendipity_quad(face, Vec3(0.3, -0.5, -1.0));
  double t = 0.1;
  for (int it = 0; it < 50; ++it) t -= (t - 0.3 + t * (t * t / 2 + 1)) / (1 + 1.5 * t * t + 1);
  EXPECT_EQ(below.location, Location::kFace);
  EXPECT_NEAR(below.point.x(), t, 1e-12);
  EXPECT_NEAR(below.point.z(), t * t / 2, 1e-12);
  EXPECT_NEAR(below.param[0], t, 1e-12);
  EXPECT_NEAR(below.param[1], -0.5, 1e-12);
  EXPECT_NEAR(below.normal.dot(Vec3(-t, 0, 1).normalized()), 1.0, 1e-12);  // P_xi x P_eta: up
}

TEST(ClosestPointOnQuadraticFace, WarmStartAtTheAnswerGivesIt) {
  std::mt19937_64 rng(27);
  for (const bool triangle : {false, true}) {
    const OracleFace face = random_face(rng, triangle, 0.1);
    for (int j = 0; j < 30; ++j) {
      const Vec3 s = random_slave(rng, face);
      const FaceClosestPoint fresh = label(face, s);
      ProjectionOptions warm;
      warm.warm_start = true;
      warm.start = fresh.param;
      const FaceClosestPoint again = label(face, s, warm);
      EXPECT_LE((again.point - fresh.point).norm(), kRelabelTol * face.size());
    }
  }
}

TEST(ClosestPointOnQuadraticFace, StatusesOfBadInput) {
  std::array<Vec3, 8> q = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0),
                           Vec3(0, -1, 0),  Vec3(1, 0, 0),  Vec3(0, 1, 0), Vec3(-1, 0, 0)};
  EXPECT_EQ(closest_point_on_serendipity_quad(SerendipityQuad(q), Vec3(0, 0, std::nan(""))).status,
            Status::kInvalid);
  auto bad = q;
  bad[5].y() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(closest_point_on_serendipity_quad(SerendipityQuad(bad), Vec3(0, 0, 1)).status, Status::kInvalid);
  auto collapsed = q;
  collapsed[2] = collapsed[1];
  collapsed[3] = collapsed[0];
  EXPECT_EQ(closest_point_on_serendipity_quad(SerendipityQuad(collapsed), Vec3(0, 0, 1)).status,
            Status::kDegenerate);
  std::array<Vec3, 6> t = {Vec3(0, 0, 0),   Vec3(1, 0, 0),     Vec3(2, 0, 0),
                           Vec3(0.5, 0, 0), Vec3(1.5, 0.1, 0), Vec3(1, 0.1, 0)};
  EXPECT_EQ(closest_point_on_quadratic_triangle(QuadraticTriangle(t), Vec3(0, 0, 1)).status,
            Status::kDegenerate);
  t[2] = Vec3(0, 1, 0);
  t[0].z() = std::nan("");
  EXPECT_EQ(closest_point_on_quadratic_triangle(QuadraticTriangle(t), Vec3(0, 0, 1)).status,
            Status::kInvalid);
}

}  // namespace
}  // namespace contactnn::projection
