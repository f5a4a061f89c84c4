#include "geometry/segment_checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace contactnn::geometry {

bool passes_segment_test(const Vec3& m, const Vec3& next, const Vec3& prev, const Vec3& s,
                         double relative_tolerance) {
  const Vec3 c1 = next - m;
  const Vec3 c2 = prev - m;
  const Vec3 c1xc2 = c1.cross(c2);
  const double area = c1xc2.norm();
  if (!(area > 0.0)) return false;
  const Vec3 unit_normal = c1xc2 / area;                 // Eq 6
  const Vec3 t = s - m;
  const Vec3 r = t - t.dot(unit_normal) * unit_normal;  // Eq 5
  const Vec3 c1xr = c1.cross(r);
  const double lengths = c1.norm() * r.norm() * c2.norm();
  const double slack3 = relative_tolerance * lengths * c1.norm();
  const double slack4 = relative_tolerance * lengths * r.norm();
  return c1xr.dot(c1xc2) > -slack3 && c1xr.dot(r.cross(c2)) > -slack4;  // Eqs 3, 4
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
    if (next.dot(prev) > 0.0 && !(next.cross(prev).norm() > std::max(1e-12 * longest, noise) * longest)) return true;
  }
  return false;
}

}  // namespace contactnn::geometry
