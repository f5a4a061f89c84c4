// The closest point of a bilinear facet to a slave node in one Newton run, certified to be the facet's
// closest point, with the reference (lib/projection's grid of starts) only where no certificate holds.
//
// The facet P(s, t) = a0 + a1 s + a2 t + a3 s t on [-1, 1]^2 and f = |S - P|^2 / 2 have
//   grad f = -(P_s.r, P_t.r),   Hess f = J^T J - (a3.r) [[0, 1], [1, 0]],   r = S - P, J = [P_s P_t],
// since P_ss = P_tt = 0 and P_st = a3. For any direction w, w^T H w >= (lambda_min(J^T J) - |a3.r|) |w|^2.
// Both terms are bounded over the whole square by numbers computed once per face and state:
//  - a3.r = a3.S - a3.P(s, t) is bilinear in (s, t): its largest magnitude on the square is at a corner,
//    max_k |a3.(S - X_k)| (four dot products per slave node);
//  - lambda_min = (tr - sqrt(tr^2 - 4 det)) / 2 with det = |P_s x P_t|^2 and tr = |P_s|^2 + |P_t|^2 grows
//  with
//    det and falls with tr, so bounds of both bound it. P_s x P_t = a1 x a2 + s a1 x a3 +
//    t a3 x a2 is affine in (s, t), so its component along the centre normal n is smallest at a corner:
//    |P_s x P_t| >= min_k (P_s x P_t)_k . n; |P_s|^2 = |a1 + a3 t|^2 and |P_t|^2 = |a2 + a3 s|^2 are convex,
//    so largest at t = +-1 and s = +-1.
// Where max_k |a3.(S - X_k)| < kMargin x lambda_floor, f is strictly convex on the square: its minimum over
// the closed square is unique, an interior stationary point is that minimum, and a boundary point that meets
// the Karush-Kuhn-Tucker conditions is that minimum. One Newton run (from the centre, or from an FE code's
// previous point) and the four straight edges then give the reference's answer, without its grid of nine
// starts. A run that does not end on a certified point returns nothing, and the caller takes the reference.
#pragma once

#include <array>
#include <optional>

#include "geometry/bilinear_patch.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::contact {

using geometry::Vec3;

/// A lower bound of lambda_min(J^T J) over a face from bounds of |P_s x P_t| >= nu > 0 and of
/// |P_s|^2 + |P_t|^2 <= trace (lambda_min = (tr - sqrt(tr^2 - 4 det)) / 2 grows with det and falls with tr;
/// written without the cancellation); 0 where the bounds give nothing. Both certificates' (this one's and
/// curved_certificate.hpp's).
[[nodiscard]] double eigenvalue_floor(double nu, double trace);

/// A quad4 face on its bilinear facet, prepared once per state of the master: the facet relative to its first
/// node (as projection::closest_point_on_face builds it) and the certificate's bounds.
struct BilinearCertificate {
  Vec3 origin = Vec3::Zero();  ///< the face's first node; everything below is relative to it
  geometry::BilinearPatch patch{{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}};
  Vec3 twist = Vec3::Zero();                ///< a3 = P_st
  std::array<double, 4> twist_at_corner{};  ///< a3.X_k (relative corners)
  double lambda_floor = 0.0;  ///< lower bound of lambda_min(J^T J) over the square; 0: no certificate
  double length = 0.0;        ///< characteristic length (the reference's tolerances are relative to it)

  /// The bounds for the facet with corners `nodes` (world or working units); lambda_floor 0 where the facet
  /// is folded, degenerate or not finite (then every slave takes the reference).
  static BilinearCertificate prepare(const std::array<Vec3, 4>& nodes);

  /// True when f is certified strictly convex on the square for `relative` (S minus origin).
  [[nodiscard]] bool convex_for(const Vec3& relative) const;

  /// The closest point of the facet to `slave` (world or working units, as the nodes), as
  /// projection::closest_point_on_face would report it (point in the caller's coordinates, location,
  /// normal, distance), when the certificate holds and the Newton run ends on a certified point; nothing
  /// otherwise. `start`: the first iterate (the centre when null). `tol_param`, `tol_residual`,
  /// `domain_margin`: the reference's (projection::ProjectionOptions).
  [[nodiscard]] std::optional<projection::FaceClosestPoint> closest_point(
      const Vec3& slave, const projection::ProjectionOptions& options,
      const std::array<double, 2>* start = nullptr) const;
  /// The same into `out` (true), written field by field where the caller keeps it (an answer built aside and
  /// copied was read back across its own stores: a store-forwarding stall per slave node); false: nothing
  /// certified (`out` then holds no answer).
  bool closest_point(const Vec3& slave, const projection::ProjectionOptions& options,
                     const std::array<double, 2>* start, projection::FaceClosestPoint& out) const;
};

}  // namespace contactnn::contact
