#include "contact/shape_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/segment_checks.hpp"

namespace contactnn::contact {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}

Spread spread_of(std::vector<double> values) {
  Spread s;
  s.count = static_cast<long>(values.size());
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  s.min = values.front();
  s.max = values.back();
  s.median = n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return s;
}

double aspect_ratio(const std::array<Vec3, 4>& nodes) {
  double longest = 0.0;
  double shortest = kInfinity;
  for (std::size_t i = 0; i < 4; ++i) {
    const double edge = (nodes[(i + 1) % 4] - nodes[i]).norm();
    longest = std::max(longest, edge);
    shortest = std::min(shortest, edge);
  }
  return shortest > 0.0 ? longest / shortest : kInfinity;
}

double warp(const std::array<Vec3, 4>& nodes) {
  const Vec3 normal = (nodes[1] - nodes[0]).cross(nodes[2] - nodes[0]);
  const double length = normal.norm();
  double shortest = kInfinity;
  for (std::size_t i = 0; i < 4; ++i) shortest = std::min(shortest, (nodes[(i + 1) % 4] - nodes[i]).norm());
  if (!(length > 0.0) || !(shortest > 0.0)) return kInfinity;
  return std::abs((nodes[3] - nodes[0]).dot(normal)) / length / shortest;
}

double segment_size(const std::array<Vec3, 4>& nodes) {
  return std::sqrt(0.5 * (nodes[2] - nodes[0]).cross(nodes[3] - nodes[1]).norm());
}

double normal_tilt_tangent(const Vec3& node, const Vec3& next, const Vec3& prev, const Vec3& normal) {
  const Vec3 corner = (next - node).cross(prev - node);
  if (!(corner.norm() > 0.0) || !(normal.norm() > 0.0)) return -1.0;
  const double cosine_part = corner.dot(normal);
  if (!(cosine_part > 0.0)) return kInfinity;
  return corner.cross(normal).norm() / cosine_part;
}

ShapeStatistics shape_statistics(std::span<const NodeSegmentPair> pairs, SurfaceKind surface) {
  std::vector<double> angles, aspects, warps, offsets, tilts;
  for (const NodeSegmentPair& p : pairs) {
    // Faces other than quad4 (the surface search's triangles and quadratic faces) have no SPEC 7
    // configuration.
    if (p.status != PairStatus::kFound || p.nodes[0] < 0) continue;
    const auto& nodes = p.config.nodes;
    for (double a : geometry::interior_angles_degrees(nodes)) angles.push_back(a);
    aspects.push_back(aspect_ratio(nodes));
    warps.push_back(warp(nodes));
    if (p.label.status == Status::kOk || p.label.status == Status::kOutside) {
      const double size = segment_size(nodes);
      if (size > 0.0) offsets.push_back(p.label.gap / size);
    }
    if (surface == SurfaceKind::kGregory) {
      for (std::size_t i = 0; i < 4; ++i) {
        const double t =
            normal_tilt_tangent(nodes[i], nodes[(i + 1) % 4], nodes[(i + 3) % 4], p.config.normals[i]);
        if (t >= 0.0) tilts.push_back(t);
      }
    }
  }
  ShapeStatistics s;
  s.interior_angle_degrees = spread_of(std::move(angles));
  s.aspect_ratio = spread_of(std::move(aspects));
  s.warp = spread_of(std::move(warps));
  s.normal_offset = spread_of(std::move(offsets));
  s.normal_tilt_tangent = spread_of(std::move(tilts));
  return s;
}

}  // namespace contactnn::contact
