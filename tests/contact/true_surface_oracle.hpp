// An independent closest point of a whole surface, for the tests of the surface search: each face by shape
// functions written here (bilinear and 8-node serendipity quadrilaterals on [-1, 1]^2, flat and 6-node
// triangles on r, s >= 0, r + s <= 1), its distance sampled on a grid and refined by a compass search from
// every grid point that is a local minimum near the best. Nothing of lib/geometry or lib/projection is used,
// so the search is never checked against its own code.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace contactnn::testing {

using OracleVec3 = Eigen::Vector3d;

/// One face of the true surface: its points over its parameter domain.
struct TrueFace {
  bool triangle = false;  ///< domain r, s >= 0, r + s <= 1; else [-1, 1]^2
  std::function<OracleVec3(double, double)> position;
  int tag = -1;  ///< the caller's (e.g. which face of the deck it is)
};

/// A quadrilateral through corners a, b, c, d (in order round it): the bilinear map.
inline TrueFace true_quad4(const std::array<OracleVec3, 4>& x, int tag = -1) {
  return {false,
          [x](double u, double v) -> OracleVec3 {
            return 0.25 * ((1 - u) * (1 - v) * x[0] + (1 + u) * (1 - v) * x[1] + (1 + u) * (1 + v) * x[2] +
                           (1 - u) * (1 + v) * x[3]);
          },
          tag};
}

/// The 8-node serendipity quadrilateral: corners in order round it, then the mid-side nodes of the edges
/// 1-2, 2-3, 3-4, 4-1.
inline TrueFace true_quad8(const std::array<OracleVec3, 8>& x, int tag = -1) {
  return {false,
          [x](double u, double v) -> OracleVec3 {
            static constexpr double kU[4] = {-1, 1, 1, -1}, kV[4] = {-1, -1, 1, 1};
            OracleVec3 p = OracleVec3::Zero();
            for (int i = 0; i < 4; ++i) {
              p += 0.25 * (1 + u * kU[i]) * (1 + v * kV[i]) * (u * kU[i] + v * kV[i] - 1) *
                   x[static_cast<std::size_t>(i)];
            }
            p += 0.5 * (1 - u * u) * (1 - v) * x[4] + 0.5 * (1 + u) * (1 - v * v) * x[5] +
                 0.5 * (1 - u * u) * (1 + v) * x[6] + 0.5 * (1 - u) * (1 - v * v) * x[7];
            return p;
          },
          tag};
}

inline TrueFace true_tri3(const std::array<OracleVec3, 3>& x, int tag = -1) {
  return {true, [x](double r, double s) -> OracleVec3 { return (1 - r - s) * x[0] + r * x[1] + s * x[2]; },
          tag};
}

/// The 6-node triangle: corners, then the mid-side nodes of the edges 1-2, 2-3, 3-1.
inline TrueFace true_tri6(const std::array<OracleVec3, 6>& x, int tag = -1) {
  return {true,
          [x](double r, double s) -> OracleVec3 {
            const double l1 = 1 - r - s, l2 = r, l3 = s;
            return l1 * (2 * l1 - 1) * x[0] + l2 * (2 * l2 - 1) * x[1] + l3 * (2 * l3 - 1) * x[2] +
                   4 * l1 * l2 * x[3] + 4 * l2 * l3 * x[4] + 4 * l3 * l1 * x[5];
          },
          tag};
}

struct OraclePoint {
  double distance = std::numeric_limits<double>::infinity();
  OracleVec3 point = OracleVec3::Zero();
  int face = -1;  ///< index into the faces
};

namespace oracle_detail {

inline void clamp_to(bool triangle, double& a, double& b) {
  if (!triangle) {
    a = std::clamp(a, -1.0, 1.0);
    b = std::clamp(b, -1.0, 1.0);
    return;
  }
  a = std::max(a, 0.0);
  b = std::max(b, 0.0);
  if (a + b > 1.0) {
    const double excess = 0.5 * (a + b - 1.0);
    a = std::clamp(a - excess, 0.0, 1.0);
    b = std::clamp(b - excess, 0.0, 1.0);
    if (a + b > 1.0) b = 1.0 - a;
  }
}

/// Compass search on |S - x(a, b)| over the face's domain from (a, b), first step `step`.
inline double refine(const TrueFace& face, const OracleVec3& s, double a, double b, double step,
                     OracleVec3& point) {
  double best = (s - face.position(a, b)).norm();
  static constexpr double kDirections[8][2] = {{1, 0},  {-1, 0}, {0, 1}, {0, -1},
                                               {1, -1}, {-1, 1}, {1, 1}, {-1, -1}};
  for (int iteration = 0; iteration < 4000 && step > 1e-14; ++iteration) {
    bool moved = false;
    for (const auto& d : kDirections) {
      double na = a + step * d[0], nb = b + step * d[1];
      clamp_to(face.triangle, na, nb);
      const double distance = (s - face.position(na, nb)).norm();
      if (distance < best) {
        best = distance;
        a = na;
        b = nb;
        moved = true;
      }
    }
    if (!moved) step *= 0.5;
  }
  point = face.position(a, b);
  return best;
}

}  // namespace oracle_detail

/// The closest point of face `face` to `s`, if it may be nearer than `bound` (else distance infinity).
inline OraclePoint closest_point_on_true_face(const TrueFace& face, const OracleVec3& s,
                                              double bound = std::numeric_limits<double>::infinity(),
                                              int n = 32) {
  // Samples on the (n + 1)^2 grid (a triangle: the points with i + j <= n); the largest distance between
  // neighbouring samples bounds how much nearer than its nearest sample a point of a cell can be.
  const double lo = face.triangle ? 0.0 : -1.0, h = (face.triangle ? 1.0 : 2.0) / n;
  const auto valid = [&](int i, int j) {
    return i >= 0 && j >= 0 && i <= n && j <= n && (!face.triangle || i + j <= n);
  };
  std::vector<double> d(static_cast<std::size_t>((n + 1) * (n + 1)), std::numeric_limits<double>::infinity());
  std::vector<OracleVec3> x(d.size());
  const auto at = [&](int i, int j) { return static_cast<std::size_t>(i * (n + 1) + j); };
  double nearest = std::numeric_limits<double>::infinity(), cell = 0.0;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      if (!valid(i, j)) continue;
      x[at(i, j)] = face.position(lo + i * h, lo + j * h);
      d[at(i, j)] = (s - x[at(i, j)]).norm();
      nearest = std::min(nearest, d[at(i, j)]);
      if (i > 0) cell = std::max(cell, (x[at(i, j)] - x[at(i - 1, j)]).norm());
      if (j > 0) cell = std::max(cell, (x[at(i, j)] - x[at(i, j - 1)]).norm());
      if (i > 0 && j + 1 <= n && valid(i - 1, j + 1))
        cell = std::max(cell, (x[at(i, j)] - x[at(i - 1, j + 1)]).norm());
    }
  }
  OraclePoint best;
  if (nearest - 2.0 * cell > bound) return best;
  // Refine from every sample that is a discrete local minimum within two cells of the nearest sample.
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      if (!valid(i, j) || d[at(i, j)] > nearest + 2.0 * cell) continue;
      bool minimum = true;
      for (int di = -1; di <= 1 && minimum; ++di) {
        for (int dj = -1; dj <= 1 && minimum; ++dj) {
          if ((di != 0 || dj != 0) && valid(i + di, j + dj) && d[at(i + di, j + dj)] < d[at(i, j)])
            minimum = false;
        }
      }
      if (!minimum) continue;
      OracleVec3 p;
      const double distance = oracle_detail::refine(face, s, lo + i * h, lo + j * h, h, p);
      if (distance < best.distance) {
        best.distance = distance;
        best.point = p;
      }
    }
  }
  return best;
}

/// The closest point of the whole surface to `s` (the first face of the nearest, for equal distances).
inline OraclePoint closest_point_on_true_surface(const std::vector<TrueFace>& faces, const OracleVec3& s,
                                                 int n = 32) {
  OraclePoint best;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    OraclePoint p = closest_point_on_true_face(faces[f], s, best.distance, n);
    if (p.distance < best.distance) {
      best = p;
      best.face = static_cast<int>(f);
    }
  }
  return best;
}

}  // namespace contactnn::testing
