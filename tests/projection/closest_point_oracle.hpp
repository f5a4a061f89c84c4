// Independent closest-point oracles for the tests of projection::closest_point_on_face and the surface
// search: the exact closest point of a triangle (Ericson, Real-Time Collision Detection, 5.1.5: Voronoi
// regions of the vertices, then the edges, then the face; no iteration), and a dense sampling of any
// parametric surface.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "geometry/surface_point.hpp"

namespace contactnn::testing {

using geometry::Vec3;

/// The point of triangle abc nearest p.
inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// The point of the planar convex quadrilateral abcd (its bilinear facet is the quadrilateral itself) nearest
/// p: the nearer of the triangles abc and acd.
inline Vec3 closest_point_on_planar_quad(const Vec3& p, const std::array<Vec3, 4>& q) {
  const Vec3 x = closest_point_on_triangle(p, q[0], q[1], q[2]);
  const Vec3 y = closest_point_on_triangle(p, q[0], q[2], q[3]);
  return (p - x).squaredNorm() <= (p - y).squaredNorm() ? x : y;
}

/// The smallest |p - P(s, t)| over an n x n grid of the closed domain [lo, hi]^2 (n >= 2).
template <class SurfaceT>
double sampled_distance(const SurfaceT& surface, const Vec3& p, double lo, double hi, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double s = lo + (hi - lo) * i / (n - 1.0), t = lo + (hi - lo) * j / (n - 1.0);
      best = std::min(best, (p - surface.position(s, t)).norm());
    }
  }
  return best;
}

}  // namespace contactnn::testing
