#include "geometry/node_normals.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "core/error.hpp"

namespace contactnn::geometry {

namespace {
// A corner whose cross product is this small relative to its edges has no direction worth averaging.
constexpr double kMinCornerSine = 1e-12;
// Unit corner normals summing to less than this (per corner) point in opposite directions: no normal.
constexpr double kMinSumPerCorner = 1e-12;
}  // namespace

Vec3 corner_normal(const Vec3& node, const Vec3& next, const Vec3& prev) {
  const Vec3 to_next = next - node;
  const Vec3 to_prev = prev - node;
  const Vec3 cross = to_next.cross(to_prev);
  const double length = cross.norm();
  CONTACTNN_REQUIRE(std::isfinite(length) && length > kMinCornerSine * to_next.norm() * to_prev.norm(),
                    "corner_normal: degenerate corner at ("
                        << node.transpose() << "): |(next - X) x (prev - X)| = " << length
                        << ", |next - X| = " << to_next.norm() << ", |prev - X| = " << to_prev.norm());
  return cross / length;
}

Vec3 node_normal(std::span<const Vec3> positions, std::span<const std::array<int, 4>> segments, int node) {
  const auto node_count = static_cast<long>(positions.size());
  CONTACTNN_REQUIRE(node >= 0 && node < node_count,
                    "node_normal: node index " << node << " outside [0, " << node_count << ")");
  Vec3 sum = Vec3::Zero();
  int corners = 0;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const std::array<int, 4>& segment = segments[s];
    for (int k = 0; k < 4; ++k) {
      CONTACTNN_REQUIRE(segment[k] >= 0 && segment[k] < node_count,
                        "node_normal: segment " << s << " has node index " << segment[k] << " outside [0, "
                                                << node_count << ")");
    }
    for (int k = 0; k < 4; ++k) {
      if (segment[k] != node) continue;
      sum += corner_normal(positions[node], positions[segment[(k + 1) % 4]], positions[segment[(k + 3) % 4]]);
      ++corners;
    }
  }
  CONTACTNN_REQUIRE(corners > 0, "node_normal: node " << node << " is a corner of none of the "
                                                      << segments.size() << " segments");
  const double length = sum.norm();
  CONTACTNN_REQUIRE(length > kMinSumPerCorner * corners, "node_normal: the "
                                                             << corners << " corner normals at node " << node
                                                             << " cancel (|sum| = " << length << ")");
  return sum / length;
}

}  // namespace contactnn::geometry
