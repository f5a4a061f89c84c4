// Closest-point projection of a slave node onto a master segment by Newton's method on paper Eqs 7-8.
#pragma once

#include <array>

#include "core/conventions.hpp"
#include "geometry/surface_point.hpp"

namespace contactnn::projection {

using geometry::Vec3;

/// Settings of the reference (label) solver. Defaults are what gen-configs uses.
struct ProjectionOptions {
  int max_iterations = 50;   ///< per start; quadratic convergence needs < 10 on the paper's domain
  double tol_param = 1e-13;  ///< converged when the Newton step (max norm, parameter units) is below this
  /// Converged also when |P_s.(S-P)| and |P_t.(S-P)| are below tol_residual * L^2 (L the segment's longest
  /// node distance): the residual can sit at rounding level before the step does.
  double tol_residual = 1e-15;
  /// A solution within this distance of the parameter domain (in parameter units) counts as inside
  /// (status ok); its coordinates are reported as found, not clamped.
  double domain_margin = 1e-10;
  /// Iterates are kept inside the domain enlarged by this many domain widths on each side; 0 picks the
  /// surface's default: 4 for the bilinear facet (defined everywhere; a distorted quad's stationary point
  /// may lie far outside), 0.1 for the Gregory patch (SPEC 3: its denominators vanish on lines through
  /// the corners outside [0,1]^2; [-0.1, 1.1]^2 meets them only in short pieces next to the corners).
  /// A solution beyond the box is reported as no_convergence, not outside.
  double box_margin = 0.0;
  /// Starts per parameter direction: a starts_per_axis x starts_per_axis grid inside the domain.
  /// 1 means the segment centre only; 3 or more finds the nearer root on warped quads (SPEC 2).
  int starts_per_axis = 3;
  /// Warm start (an FE code's previous point on the same face): when set, the one start `start` replaces the
  /// grid. It finds the stationary point whose basin holds the start; the grid's nearest one only where the
  /// surface has a single stationary point near S (the tracking of lib/contact checks this against fresh
  /// searches on real histories).
  bool warm_start = false;
  std::array<double, 2> start{0.0, 0.0};
  /// closest_point_on_face: the caller has checked the face as that function would (its nodes finite, its
  /// characteristic length finite, geometry::is_degenerate_segment false, on the nodes relative to the
  /// first): the checks are skipped. lib/contact's surface search checks each face once per state of the
  /// master, where every slave node's projection repeated them (9% of a tracked increment at 1e6 slave
  /// nodes).
  bool face_checked = false;
};

/// Result of a projection. `param` and `gap` are finite whenever status is ok or outside; for the
/// other statuses they hold the start point and 0 (never NaN), and must not be used as a projection.
struct [[nodiscard]] ProjectionResult {
  std::array<double, 2> param{0.0, 0.0};  ///< (xi, eta) or (u, v)
  double gap = 0.0;           ///< n.(S - P), n the unit normal P_s x P_t at the solution; < 0: penetration
  double sqr_distance = 0.0;  ///< |S - P|^2
  int iterations = 0;         ///< Newton iterations of the start that produced the reported solution
  Status status = Status::kInvalid;
};

/// The reference projection (the dataset labels). Runs damped Newton from each start of a grid and
/// returns, among the converged stationary points that are local minima of |S - P|^2, the nearest one
/// inside the domain (enlarged by domain_margin); if none is inside, the nearest converged one outside
/// (status outside); if none converged, no_convergence.
///
/// Each iteration solves H dp = r with the exact Jacobian H_ij = P_i.P_j - P_ij.(S - P) of Eqs 7-8
/// (the P_st.(S - P) term included). Where H is not positive definite (near a centre of curvature or a
/// saddle) it takes the Gauss-Newton step with P_i.P_j instead, a descent direction for |S - P|^2; steps
/// are halved until |S - P|^2 decreases (Armijo) and iterates are clamped into the bounded box.
///
/// Statuses: invalid if S or a surface value is non-finite; degenerate if P_s x P_t vanishes (relative to
/// L^2) at the solution or at every start. Limits: a local method; a stationary point that none of the
/// starts' basins reaches is missed (never observed on the paper's domains with 3x3 starts; the tests
/// compare against a dense grid search).
template <geometry::Surface SurfaceT>
[[nodiscard]] ProjectionResult project_point(const SurfaceT& surface, const Vec3& slave,
                                             const ProjectionOptions& options = {});

/// Plain Newton as an explicit FE code runs it (the speed comparison of paper Sections 5.3.2 and 6.3.3):
/// exactly `iterations` undamped steps H dp = r from `start`, no line search, no convergence test, no
/// safeguard except that a singular H stops early. Returns the last iterate, which may be anywhere.
template <geometry::Surface SurfaceT>
[[nodiscard]] std::array<double, 2> newton_fixed_iterations(const SurfaceT& surface, const Vec3& slave,
                                                            int iterations, std::array<double, 2> start);

/// Plain undamped Newton from `start` until the step is below tol_param (or max_iterations): an FE code's
/// "Newton to convergence". status is ok/outside if it converged, no_convergence otherwise, degenerate on
/// a singular H, invalid on non-finite values. gap and sqr_distance are filled when converged.
template <geometry::Surface SurfaceT>
[[nodiscard]] ProjectionResult newton_until_converged(const SurfaceT& surface, const Vec3& slave,
                                                      std::array<double, 2> start, int max_iterations = 50,
                                                      double tol_param = 1e-10);

/// Centre of a surface's parameter domain: (0, 0) for bilinear, (0.5, 0.5) for Gregory.
[[nodiscard]] constexpr std::array<double, 2> domain_centre(SurfaceKind kind) {
  const ParamDomain d = param_domain(kind);
  return {0.5 * (d.lo + d.hi), 0.5 * (d.lo + d.hi)};
}

}  // namespace contactnn::projection
