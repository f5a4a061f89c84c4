// Node normals of a quadrilateral mesh (paper Eq 26; SPEC 3, last bullet).
#pragma once

#include <array>
#include <span>

#include "geometry/surface_point.hpp"

namespace contactnn::geometry {

/// Unit corner normal of a segment at node X: unit((next - X) x (prev - X)), with `next` the
/// counter-clockwise neighbour of X in the segment and `prev` the clockwise one.
/// Throws InvalidArgument when the corner is degenerate: |(next - X) x (prev - X)| is at most
/// 1e-12 |next - X| |prev - X| (coincident nodes or collinear edges) or a coordinate is not finite.
[[nodiscard]] Vec3 corner_normal(const Vec3& node, const Vec3& next, const Vec3& prev);

/// Node normal of paper Eq 26 at one node of a quadrilateral mesh: the normalised sum of the unit corner
/// normals (corner_normal) of every segment that has `node` as a corner. (Eq 26 as printed sums the
/// un-normalised c1 x c2; SPEC 3 normalises each corner first, so large segments do not dominate.)
/// @param positions  #nodes node coordinates
/// @param segments   #segments quadrilaterals, each 4 indices into `positions`, counter-clockwise (SPEC 1)
/// @param node       index into `positions` of the node whose normal is wanted
/// @return the unit node normal
/// Throws InvalidArgument when `node` or a segment's index is out of range, when no segment has `node` as a
/// corner, when one of its corners there is degenerate (see corner_normal), or when the corner normals
/// cancel (sum shorter than 1e-12 times their count).
[[nodiscard]] Vec3 node_normal(std::span<const Vec3> positions, std::span<const std::array<int, 4>> segments,
                               int node);

}  // namespace contactnn::geometry
