// The 6-node quadratic triangle (tri6, SPEC 9): a face of a C3D10 or a triangular face of a C3D15,
// interpolated by its own quadratic shape functions (Zienkiewicz & Taylor, The Finite Element Method, vol. 1,
// 6th ed., Section 6.6).
#pragma once

#include <array>

#include "geometry/surface_point.hpp"

namespace contactnn::geometry {

/// P(r, s) = sum_i N_i(r, s) X_i over the 6 nodes in SPEC 9's order: corners A (0,0), B (1,0), C (0,1),
/// counter-clockwise seen from the side the normal P_r x P_s points to, then the mid-side nodes of edges A-B
/// (1/2,0), B-C (1/2,1/2), C-A (0,1/2). With L_A = 1 - r - s, L_B = r, L_C = s: corner N = L (2L - 1),
/// mid-side N = 4 L_i L_j. Each edge is the quadratic curve through its two corners and its mid-side node,
/// reached at the edge's middle parameter. Defined (and evaluated) for any (r, s); the face is the triangle
/// r >= 0, s >= 0, r + s <= 1.
///
/// Models geometry::Surface. Its kKind (kGregory) stands only for the parameter box [0, 1]^2 of that kind,
/// which holds the triangle: code that takes the whole box as the face (project_point, closest_point_on_face)
/// does not apply; projection::closest_point_on_quadratic_triangle is the triangle's closest point.
class QuadraticTriangle {
 public:
  static constexpr SurfaceKind kKind = SurfaceKind::kGregory;

  /// @param nodes  A, B, C, then the mid-side nodes of A-B, B-C, C-A (world coordinates).
  explicit QuadraticTriangle(const std::array<Vec3, 6>& nodes);

  [[nodiscard]] Vec3 position(double r, double s) const;
  /// Position with first and second derivatives in (r, s).
  [[nodiscard]] SurfacePoint evaluate(double r, double s) const;

  /// Length scale for relative tolerances: the longest distance between two of the 6 nodes.
  [[nodiscard]] double characteristic_length() const;

  [[nodiscard]] const std::array<Vec3, 6>& nodes() const { return nodes_; }
  /// A, B, C.
  [[nodiscard]] std::array<Vec3, 3> corners() const { return {nodes_[0], nodes_[1], nodes_[2]}; }

  /// The 6 control points of the same surface as a quadratic Bezier triangle: A, B, C, then for each edge
  /// 2 M - (X + Y)/2 (M its mid-side node, X and Y its corners). The surface lies in their convex hull.
  [[nodiscard]] std::array<Vec3, 6> bezier_control_points() const;

 private:
  std::array<Vec3, 6> nodes_;
  // P = c[0] + c[1] r + c[2] s + c[3] r^2 + c[4] r s + c[5] s^2.
  std::array<Vec3, 6> c_;
};

}  // namespace contactnn::geometry
