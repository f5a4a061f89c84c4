// One node-segment configuration: the master segment ABCD, the slave node S and (Gregory only) the
// four node normals, in world coordinates or in the normalised frame.
#pragma once

#include <array>

#include "geometry/surface_point.hpp"

namespace contactnn::geometry {

struct Configuration {
  std::array<Vec3, 4> nodes;    ///< A, B, C, D (SPEC 1 order)
  Vec3 slave;                   ///< S
  std::array<Vec3, 4> normals;  ///< node normals at A, B, C, D (any positive length); unused for bilinear

  /// True when every coordinate (and, with `with_normals`, every normal component) is finite.
  [[nodiscard]] bool is_finite(bool with_normals) const;
};

}  // namespace contactnn::geometry
