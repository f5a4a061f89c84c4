// The 8-node serendipity quadrilateral (quad8, SPEC 9): the face of a C3D20/C3D20R or a quadrilateral face of
// a C3D15, interpolated by its own quadratic shape functions (Zienkiewicz & Taylor, The Finite Element
// Method, vol. 1, 6th ed., Section 6.4, serendipity family).
#pragma once

#include <array>

#include "geometry/surface_point.hpp"

namespace contactnn::geometry {

/// P(xi, eta) = sum_i N_i(xi, eta) X_i over the 8 nodes in SPEC 9's order: corners A (-1,-1), B (1,-1),
/// C (1,1), D (-1,1), counter-clockwise seen from the side the normal P_xi x P_eta points to, then the
/// mid-side nodes of edges A-B (0,-1), B-C (1,0), C-D (0,1), D-A (-1,0). Shape functions: corner (s, t): (1 +
/// s xi)(1 + t eta)(s xi + t eta - 1)/4; mid-side (0, t): (1 - xi^2)(1 + t eta)/2; (s, 0): (1 + s xi)(1 -
/// eta^2)/2. Each edge is the quadratic curve through its two corners and its mid-side node, reached at the
/// edge's middle parameter. Defined (and evaluated) for any (xi, eta); the face is [-1, 1]^2.
///
/// Models geometry::Surface with kKind = kBilinear: that kind's parameter domain [-1, 1]^2 and names (xi,
/// eta) are the quad8's too (SPEC 9). The surface is not the bilinear facet of its corners unless every
/// mid-side node is its edge's midpoint.
class SerendipityQuad {
 public:
  static constexpr SurfaceKind kKind = SurfaceKind::kBilinear;

  /// @param nodes  A, B, C, D, then the mid-side nodes of A-B, B-C, C-D, D-A (world coordinates).
  explicit SerendipityQuad(const std::array<Vec3, 8>& nodes);

  [[nodiscard]] Vec3 position(double xi, double eta) const;
  /// Position with first and second derivatives in (xi, eta).
  [[nodiscard]] SurfacePoint evaluate(double xi, double eta) const;

  /// Length scale for relative tolerances: the longest distance between two of the 8 nodes.
  [[nodiscard]] double characteristic_length() const;

  [[nodiscard]] const std::array<Vec3, 8>& nodes() const { return nodes_; }
  /// A, B, C, D.
  [[nodiscard]] std::array<Vec3, 4> corners() const { return {nodes_[0], nodes_[1], nodes_[2], nodes_[3]}; }

  /// The 9 control points of the same surface as a biquadratic Bezier patch over [-1, 1]^2 (the serendipity
  /// space lies in the biquadratic one): the surface lies in their convex hull, so a sphere holding them
  /// holds the face. Row-major, xi fastest: (-1,-1), (0,-1), (1,-1), (-1,0), ... as Bezier indices.
  [[nodiscard]] std::array<Vec3, 9> bezier_control_points() const;

 private:
  std::array<Vec3, 8> nodes_;
  // P = c[0] + c[1] xi + c[2] eta + c[3] xi^2 + c[4] xi eta + c[5] eta^2 + c[6] xi^2 eta + c[7] xi eta^2.
  std::array<Vec3, 8> c_;
};

}  // namespace contactnn::geometry
