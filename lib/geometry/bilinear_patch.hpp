// The bilinear facet of a 4-node quadrilateral (paper Eqs 19-23; SPEC 1).
#pragma once

#include <array>
#include <span>

#include "geometry/surface_point.hpp"

namespace contactnn::geometry {

/// P(xi, eta) = sum_i N_i(xi, eta) P_i with N_1 = (1-xi)(1-eta)/4 at A = (-1,-1), N_2 at B = (1,-1),
/// N_3 at C = (1,1), N_4 at D = (-1,1). Defined (and evaluated) for any (xi, eta), not only [-1,1]^2.
class BilinearPatch {
 public:
  static constexpr SurfaceKind kKind = SurfaceKind::kBilinear;

  /// @param nodes  A, B, C, D, counter-clockwise seen from the side the normal points to.
  explicit BilinearPatch(const std::array<Vec3, 4>& nodes)
      : nodes_(nodes),
        // P = a0 + a1 xi + a2 eta + a3 xi eta: the same surface with the derivatives read off directly.
        a0_(0.25 * (nodes[0] + nodes[1] + nodes[2] + nodes[3])),
        a1_(0.25 * (-nodes[0] + nodes[1] + nodes[2] - nodes[3])),
        a2_(0.25 * (-nodes[0] - nodes[1] + nodes[2] + nodes[3])),
        a3_(0.25 * (nodes[0] - nodes[1] + nodes[2] - nodes[3])) {}

  [[nodiscard]] Vec3 position(double xi, double eta) const {
    return a0_ + xi * a1_ + eta * a2_ + (xi * eta) * a3_;
  }

  /// Position and derivatives; d_ss = d_tt = 0, d_st = (A - B + C - D)/4.
  [[nodiscard]] SurfacePoint evaluate(double xi, double eta) const {
    return SurfacePoint{position(xi, eta), a1_ + eta * a3_, a2_ + xi * a3_, Vec3::Zero(), a3_, Vec3::Zero()};
  }

  /// Length scale for relative tolerances: the longest edge or diagonal.
  [[nodiscard]] double characteristic_length() const;

  [[nodiscard]] const std::array<Vec3, 4>& nodes() const { return nodes_; }

 private:
  std::array<Vec3, 4> nodes_;
  Vec3 a0_, a1_, a2_, a3_;
};

/// Longest distance between any two of the four nodes (0 for a fully collapsed segment).
[[nodiscard]] double max_node_distance(const std::array<Vec3, 4>& nodes);
/// Longest distance between any two of a face's nodes (the length scale of the quadratic faces too).
[[nodiscard]] double max_node_distance(std::span<const Vec3> nodes);

}  // namespace contactnn::geometry
