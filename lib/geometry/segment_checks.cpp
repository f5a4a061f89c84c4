#include "geometry/segment_checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace contactnn::geometry {

namespace {

/// The largest power of two at most x for a positive normal x (its exponent bits alone); 1 for 0, subnormals,
/// infinities and NaN.
double power_of_two_below(double x) {
  int exponent = 0;
  (void)std::frexp(x, &exponent);
  return x > 0.0 && x <= std::numeric_limits<double>::max() && x >= std::numeric_limits<double>::min()
             ? std::ldexp(1.0, exponent - 1)
             : 1.0;
}

}  // namespace

bool passes_segment_test(const Vec3& m, const Vec3& next, const Vec3& prev, const Vec3& s,
                         double relative_tolerance) {
  // In units of the corner's size, a power of two (exact: the same decisions wherever nothing under- or
  // overflowed): |c1 x c2|^2 is a fourth power of the size and left the double range beyond sizes of 1e+-77,
  // so that a deck scaled by 1e-100 or 1e100 had no segment for any slave node (the local search holds to
  // 1e+-300). A slave node more than about 1e300 corner sizes away fails the test.
  const Vec3 e1 = next - m;
  const Vec3 e2 = prev - m;
  const double unit = power_of_two_below(std::max(e1.cwiseAbs().maxCoeff(), e2.cwiseAbs().maxCoeff()));
  const Vec3 c1 = e1 / unit;
  const Vec3 c2 = e2 / unit;
  const Vec3 c1xc2 = c1.cross(c2);
  const double area_squared = c1xc2.squaredNorm();
  if (!(area_squared > 0.0)) return false;
  const Vec3 t = (s - m) / unit;
  const Vec3 r = t - (t.dot(c1xc2) / area_squared) * c1xc2;  // Eqs 5-6
  // r = alpha c1 + beta c2 in the corner's plane: c1 x r = beta (c1 x c2) and r x c2 = alpha (c1 x c2), so
  // Eq 3 says beta > 0 and Eq 4 says alpha beta > 0.
  const double alpha = r.cross(c2).dot(c1xc2) / area_squared;
  const double beta = c1.cross(r).dot(c1xc2) / area_squared;
  if (!(relative_tolerance > 0.0)) return alpha > 0.0 && beta > 0.0;
  const double r_length = r.norm();
  const double c1_length = c1.norm();
  const double c2_length = c2.norm();
  if (r_length <= relative_tolerance * std::min(c1_length, c2_length)) return true;  // S on the corner
  // Relaxing alpha and beta, not the products of Eqs 3-4, keeps S on the backward extension of an edge
  // (c1 x r = 0 with alpha < 0) outside.
  return alpha * c1_length > -relative_tolerance * r_length &&
         beta * c2_length > -relative_tolerance * r_length;
}

bool first_node_is_nearest(const std::array<Vec3, 4>& nodes, const Vec3& s, double relative_tolerance) {
  const double to_a = (s - nodes[0]).squaredNorm() / (1.0 + relative_tolerance);
  return to_a <= (s - nodes[1]).squaredNorm() && to_a <= (s - nodes[2]).squaredNorm() &&
         to_a <= (s - nodes[3]).squaredNorm();
}

std::array<double, 4> interior_angles_degrees(const std::array<Vec3, 4>& nodes) {
  std::array<double, 4> angles{};
  for (int i = 0; i < 4; ++i) {
    const Vec3 to_next = nodes[(i + 1) % 4] - nodes[i];
    const Vec3 to_prev = nodes[(i + 3) % 4] - nodes[i];
    // atan2 of |cross| and dot is accurate near 0 and 180 degrees, where acos of the cosine is not.
    angles[i] = std::atan2(to_next.cross(to_prev).norm(), to_next.dot(to_prev)) * 180.0 / std::numbers::pi;
  }
  return angles;
}

bool is_convex(const std::array<Vec3, 4>& nodes, double relative_tolerance) {
  const Vec3 reference = (nodes[1] - nodes[0]).cross(nodes[3] - nodes[0]);
  for (int i = 0; i < 4; ++i) {
    const Vec3 to_next = nodes[(i + 1) % 4] - nodes[i];
    const Vec3 to_prev = nodes[(i + 3) % 4] - nodes[i];
    // The slack scales with the edges, not with the corner's cross product, which vanishes at 180 degrees.
    const double slack = relative_tolerance * to_next.norm() * to_prev.norm() * reference.norm();
    if (!(to_next.cross(to_prev).dot(reference) > -slack)) return false;
  }
  return true;
}

}  // namespace contactnn::geometry

namespace contactnn::geometry {

bool is_degenerate_segment(const std::array<Vec3, 4>& nodes, double coordinate_noise) {
  // The extreme squared distances, then two square roots instead of six: sqrt is correctly rounded and
  // monotone, so sqrt(max d^2) and sqrt(min d^2) are bit for bit the max and min of the six norms (this
  // test runs on every network query, inside geometry::normalise).
  double longest_squared = 0.0;
  double shortest_squared = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      const double squared = (nodes[i] - nodes[j]).squaredNorm();
      longest_squared = std::max(longest_squared, squared);
      shortest_squared = std::min(shortest_squared, squared);
    }
  }
  const double longest = std::sqrt(longest_squared);
  const double shortest = std::sqrt(shortest_squared);
  const double noise = 16.0 * coordinate_noise;
  if (!(longest > 0.0) || !(shortest > std::max(1e-10 * longest, noise))) return true;
  const double twice_area = (nodes[2] - nodes[0]).cross(nodes[3] - nodes[1]).norm();
  if (!(0.5 * twice_area > std::max(1e-12 * longest, noise) * longest)) return true;
  // A corner of zero angle (its two edges along one ray: the segment folds back onto itself). A straight
  // angle (a triangle with a node on an edge) is usable.
  for (int i = 0; i < 4; ++i) {
    const Vec3 next = nodes[(i + 1) % 4] - nodes[i];
    const Vec3 prev = nodes[(i + 3) % 4] - nodes[i];
    if (next.dot(prev) > 0.0 && !(next.cross(prev).norm() > std::max(1e-12 * longest, noise) * longest))
      return true;
  }
  return false;
}

}  // namespace contactnn::geometry
