// Shape statistics of a scene's node-segment pairs: how far its segments and slave positions are from the
// paper's domain (interior angles, aspect ratio, warp, normal offset of the slave, node-normal tilt).
#pragma once

#include <array>
#include <span>
#include <vector>

#include "contact/global_search.hpp"

namespace contactnn::contact {

/// Smallest / median / largest of some values. count == 0: there were none (the others are then 0 and
/// mean nothing). The median of an even count is the mean of the two middle values.
struct Spread {
  long count = 0;
  double min = 0.0;
  double median = 0.0;
  double max = 0.0;
};
[[nodiscard]] Spread spread_of(std::vector<double> values);

/// Longest / shortest of the four edges AB, BC, CD, DA (1 for a square; infinite if an edge has length 0).
[[nodiscard]] double aspect_ratio(const std::array<Vec3, 4>& nodes);

/// Warp: the distance of D from the plane through A, B and C, divided by the shortest edge (0 for a flat
/// segment; the paper's domain reaches z_C = 0.3 for |AB| = 1; infinite if A, B, C are collinear).
[[nodiscard]] double warp(const std::array<Vec3, 4>& nodes);

/// Segment size: the square root of the area |AC x BD| / 2 (the area of a flat quadrilateral; the mean
/// projected area of a warped one). The unit of normal offsets.
[[nodiscard]] double segment_size(const std::array<Vec3, 4>& nodes);

/// tan of the angle between a node normal and the segment's corner normal (next - X) x (prev - X) there,
/// as in the paper's Section 6 filter; +infinity at 90 degrees or more; NaN never: a zero normal or a
/// collapsed corner gives -1 (no tilt to report).
[[nodiscard]] double normal_tilt_tangent(const Vec3& node, const Vec3& next, const Vec3& prev,
                                         const Vec3& normal);

struct ShapeStatistics {
  Spread interior_angle_degrees;  ///< four per pair (geometry::interior_angles_degrees)
  Spread aspect_ratio;            ///< one per pair
  Spread warp;                    ///< one per pair
  Spread normal_offset;           ///< gap / segment_size, one per pair whose label has a gap (ok, outside);
                                  ///< negative: penetration
  Spread normal_tilt_tangent;     ///< Gregory only: four per pair, one per node (empty for bilinear)
};

/// Statistics over the pairs with status kFound (each pair counts its segment once, so a segment shared by
/// several slave nodes weighs as often as it is used).
[[nodiscard]] ShapeStatistics shape_statistics(std::span<const NodeSegmentPair> pairs, SurfaceKind surface);

}  // namespace contactnn::contact
