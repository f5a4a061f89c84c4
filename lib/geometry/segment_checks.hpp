// Geometric predicates on a segment and a slave node: the filters of the paper's Sections 5.1 and 6.3.1.
#pragma once

#include <array>

#include "geometry/surface_point.hpp"

namespace contactnn::geometry {

/// The segment test of paper Eqs 3-6 at master node `m` with c1 = next - m (counter-clockwise
/// neighbour) and c2 = prev - m (clockwise neighbour): the projection r of t = s - m onto the plane
/// normal to c1 x c2 lies strictly inside the angle between c1 and c2:
///   (c1 x r) . (c1 x c2) > 0   (Eq 3)   and   (c1 x r) . (r x c2) > 0   (Eq 4),
/// i.e. r = alpha c1 + beta c2 with alpha, beta > 0. False for a collapsed corner (c1 x c2 = 0).
/// `relative_tolerance` > 0 admits what the rounding of real coordinates puts on the boundary: S on the
/// corner (|r| <= tolerance x the shorter edge), and S outside the angle by up to about tolerance radians
/// (alpha |c1| > -tolerance |r| and beta |c2| > -tolerance |r|). Relaxing alpha and beta rather than the
/// products keeps S on the backward extension of an edge outside. 0: the strict test.
/// The segment test's tolerance for pairs of real meshes, which put slave nodes on master nodes and over
/// master edges up to the rounding of the deck's printed coordinates: the global search's default, the
/// scene sampler's, and the domain check's (a pair the global search makes is never out of domain for it).
inline constexpr double kSegmentTestTolerance = 1e-6;

[[nodiscard]] bool passes_segment_test(const Vec3& m, const Vec3& next, const Vec3& prev, const Vec3& s,
                                       double relative_tolerance = 0.0);

/// True when node 0 (A) is a nearest node of the segment to `s` (ties count as nearest; with
/// `relative_tolerance`, |SA|^2 <= (1 + tolerance) |SX|^2 for every other node X).
[[nodiscard]] bool first_node_is_nearest(const std::array<Vec3, 4>& nodes, const Vec3& s,
                                         double relative_tolerance = 0.0);

/// Interior angles at A, B, C, D in degrees, measured between the two edges at each node (3D angles).
[[nodiscard]] std::array<double, 4> interior_angles_degrees(const std::array<Vec3, 4>& nodes);

/// True when the quadrilateral, projected onto the plane normal to (B - A) x (D - A), is strictly
/// convex and counter-clockwise: the corner cross products (next - X) x (prev - X) all point to the
/// side of that normal (with `relative_tolerance`: > -tolerance |next - X| |prev - X| |normal|, so a
/// corner of 180 degrees up to rounding passes).
[[nodiscard]] bool is_convex(const std::array<Vec3, 4>& nodes, double relative_tolerance = 0.0);

}  // namespace contactnn::geometry

namespace contactnn::geometry {

/// True when the segment cannot carry a projection: two nodes closer than 1e-10 of the longest node
/// distance (coincident), the area |AC x BD|/2 below 1e-12 of its square (collinear or collapsed), or a
/// corner of zero angle (its two edges along one ray: the segment folds onto itself; |next x prev| below
/// 1e-12 of the longest distance squared). A straight angle (180 degrees, a triangle) is not degenerate.
/// `coordinate_noise` (>= 0, in the nodes' units) is the rounding each node coordinate already carries,
/// e.g. eps * max|x| of world coordinates far from the origin: a node distance below 16 * noise or an area
/// below 16 * noise * longest cannot be told from zero, so it counts as zero too.
[[nodiscard]] bool is_degenerate_segment(const std::array<Vec3, 4>& nodes, double coordinate_noise = 0.0);

}  // namespace contactnn::geometry
