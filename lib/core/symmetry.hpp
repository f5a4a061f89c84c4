// The symmetries of the square that bring any node order of a segment to the paper's canonical one
// (SPEC 4, "Canonical configuration"), and how local coordinates move under them.
//
// The caller's nodes N0..N3 (its A, B, C, D) sit at the bilinear corners p0 = (-1,-1), p1 = (1,-1),
// p2 = (1,1), p3 = (-1,1). A symmetry relabels them: canonical node i is caller node caller_node(i).
//  - rotation r (0..3): canonical node i = caller node (i + r) mod 4, so canonical A is caller node r;
//  - mirror: after the rotation, the order A, D, C, B (the paper's |AD| <= |AB| step). With a reflection of
//    space it keeps the front side of the segment (SPEC 4); the projection's gap sign is handled by the
//    frame.
// A point's coordinates follow: caller (xi, eta) = rot^r(m(s, t)), with rot(x, y) = (-y, x) (the map
// p_i -> p_{i+1}) and m the swap (x, y) -> (y, x) when mirrored (the map p_i -> p_{(4-i) mod 4}).
#pragma once

#include <array>

#include "core/conventions.hpp"

namespace contactnn {

/// One of the 8 symmetries of the square acting on a segment's node order (SPEC 4).
struct SquareSymmetry {
  int rotation = 0;     ///< 0..3: canonical node 0 (A) is caller node `rotation`
  bool mirror = false;  ///< after the rotation, the node order A, D, C, B

  /// Index in the caller's order of canonical node `canonical` (0..3).
  [[nodiscard]] constexpr int caller_node(int canonical) const {
    const int rotated = mirror ? (4 - canonical) % 4 : canonical;
    return (rotated + rotation) % 4;
  }

  /// Canonical local coordinates -> the caller's, in `kind`'s own parameters ((xi, eta) or (u, v)). Exact for
  /// (xi, eta) (sign changes and swaps); for (u, v) the reflections about 1/2 (u -> 1 - u) round in the last
  /// bit.
  [[nodiscard]] constexpr std::array<double, 2> to_caller(std::array<double, 2> p, SurfaceKind kind) const {
    const double c = kind == SurfaceKind::kBilinear ? 0.0 : 0.5;  // centre of the parameter domain
    double x = p[0] - c, y = p[1] - c;
    if (mirror) {
      const double t = x;
      x = y;
      y = t;
    }
    for (int k = 0; k < rotation; ++k) {
      const double t = x;
      x = -y;
      y = t;
    }
    return {x + c, y + c};
  }

  /// The caller's local coordinates -> canonical ones (the inverse of to_caller).
  [[nodiscard]] constexpr std::array<double, 2> to_canonical(std::array<double, 2> p,
                                                             SurfaceKind kind) const {
    const double c = kind == SurfaceKind::kBilinear ? 0.0 : 0.5;
    double x = p[0] - c, y = p[1] - c;
    for (int k = 0; k < rotation; ++k) {
      const double t = x;
      x = y;
      y = -t;
    }
    if (mirror) {
      const double t = x;
      x = y;
      y = t;
    }
    return {x + c, y + c};
  }

  /// +1 when the relabelling keeps the orientation of the parametrisation (P_s x P_t), -1 when it reverses
  /// it (the mirror).
  [[nodiscard]] constexpr double orientation() const { return mirror ? -1.0 : 1.0; }

  friend constexpr bool operator==(const SquareSymmetry&, const SquareSymmetry&) = default;
};

/// All 8 symmetries, identity first (for tests and for callers that enumerate node orders).
[[nodiscard]] constexpr std::array<SquareSymmetry, 8> all_square_symmetries() {
  return {SquareSymmetry{0, false}, SquareSymmetry{1, false}, SquareSymmetry{2, false},
          SquareSymmetry{3, false}, SquareSymmetry{0, true},  SquareSymmetry{1, true},
          SquareSymmetry{2, true},  SquareSymmetry{3, true}};
}

}  // namespace contactnn
