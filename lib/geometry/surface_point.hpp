// A surface point with the first and second parametric derivatives Newton projection needs.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <concepts>

#include "core/conventions.hpp"

namespace contactnn::geometry {

using Vec3 = Eigen::Vector3d;

/// Position P(s, t) and its derivatives in the surface's own parameters (s, t): (xi, eta) for the
/// bilinear facet, (u, v) for the Gregory patch. All in the units of the node coordinates.
struct SurfacePoint {
  Vec3 position;
  Vec3 d_s, d_t;          ///< dP/ds, dP/dt
  Vec3 d_ss, d_st, d_tt;  ///< second derivatives
};

/// What Newton projection needs of a surface: its kind (which fixes the parameter domain) and
/// position plus derivatives at a parameter point. BilinearPatch and GregoryPatch model it.
template <class S>
concept Surface = requires(const S& surface, double s, double t) {
  { S::kKind } -> std::convertible_to<SurfaceKind>;
  { surface.evaluate(s, t) } -> std::same_as<SurfacePoint>;
  { surface.position(s, t) } -> std::same_as<Vec3>;
  { surface.characteristic_length() } -> std::convertible_to<double>;
};

}  // namespace contactnn::geometry
