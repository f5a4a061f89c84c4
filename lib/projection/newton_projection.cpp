#include "projection/newton_projection.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"

namespace contactnn::projection {

namespace {

using geometry::SurfacePoint;

/// Residual r_i = P_i.(S - P) of Eqs 7-8 and the exact Jacobian H_ij = P_i.P_j - P_ij.(S - P)
/// (so that Newton's update is H dp = r); `gram` is the Gauss-Newton part P_i.P_j alone.
struct NewtonSystem {
  double r0, r1;
  double h00, h01, h11;
  double g00, g01, g11;
};

NewtonSystem newton_system(const SurfacePoint& p, const Vec3& slave) {
  const Vec3 d = slave - p.position;
  NewtonSystem s{};
  s.r0 = p.d_s.dot(d);
  s.r1 = p.d_t.dot(d);
  s.g00 = p.d_s.dot(p.d_s);
  s.g01 = p.d_s.dot(p.d_t);
  s.g11 = p.d_t.dot(p.d_t);
  s.h00 = s.g00 - p.d_ss.dot(d);
  s.h01 = s.g01 - p.d_st.dot(d);
  s.h11 = s.g11 - p.d_tt.dot(d);
  return s;
}

/// Solves the symmetric 2x2 system [a b; b c] x = (r0, r1) by Cramer's rule; false if singular.
bool solve2(double a, double b, double c, double r0, double r1, double det_floor, std::array<double, 2>& x) {
  const double det = a * c - b * b;
  if (!(std::abs(det) > det_floor)) return false;
  x = {(c * r0 - b * r1) / det, (a * r1 - b * r0) / det};
  return std::isfinite(x[0]) && std::isfinite(x[1]);
}

double clamp_to(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

/// Outcome of one damped Newton run.
struct RunResult {
  std::array<double, 2> param;
  int iterations;
  bool converged;
  bool degenerate;
  bool invalid;
};

template <class SurfaceT>
RunResult damped_newton(const SurfaceT& surface, const Vec3& slave, std::array<double, 2> p,
                        const ProjectionOptions& options, double length) {
  const ParamDomain domain = param_domain(SurfaceT::kKind);
  const double width = domain.hi - domain.lo;
  const double margin =
      options.box_margin > 0.0 ? options.box_margin : (SurfaceT::kKind == SurfaceKind::kBilinear ? 4.0 : 0.1);
  const double box_lo = domain.lo - margin * width;
  const double box_hi = domain.hi + margin * width;
  const double l2 = length * length;
  const double det_floor = 1e-24 * l2 * l2;  // |P_s x P_t|^2 ~ L^4: a singular Gram matrix at this level
  const double residual_floor = options.tol_residual * l2;
  const double max_step = 0.5 * width;  // a step longer than half the domain is not trusted as is

  for (int it = 1; it <= options.max_iterations; ++it) {
    const SurfacePoint point = surface.evaluate(p[0], p[1]);
    if (!point.position.allFinite() || !point.d_s.allFinite() || !point.d_t.allFinite()) {
      return {p, it, false, false, true};
    }
    const NewtonSystem s = newton_system(point, slave);
    if (std::abs(s.r0) <= residual_floor && std::abs(s.r1) <= residual_floor)
      return {p, it - 1, true, false, false};

    std::array<double, 2> step{};
    const bool positive_definite = s.h00 > 0.0 && s.h00 * s.h11 - s.h01 * s.h01 > det_floor;
    if (!positive_definite || !solve2(s.h00, s.h01, s.h11, s.r0, s.r1, det_floor, step)) {
      // Not a minimum's basin (or singular): the Gauss-Newton step goes downhill on |S - P|^2.
      if (!solve2(s.g00, s.g01, s.g11, s.r0, s.r1, det_floor, step)) return {p, it, false, true, false};
    }
    const double step_length = std::max(std::abs(step[0]), std::abs(step[1]));
    if (step_length > max_step) {
      step[0] *= max_step / step_length;
      step[1] *= max_step / step_length;
    }

    // Armijo backtracking on f = |S - P|^2 / 2, whose gradient is -r: skipped once steps are tiny,
    // where f differences are below rounding and quadratic convergence needs the full step.
    const double f0 = 0.5 * (slave - point.position).squaredNorm();
    const double slope = -(s.r0 * step[0] + s.r1 * step[1]);  // directional derivative, < 0 downhill
    double alpha = 1.0;
    std::array<double, 2> next{};
    for (int halvings = 0;; ++halvings) {
      next = {clamp_to(p[0] + alpha * step[0], box_lo, box_hi),
              clamp_to(p[1] + alpha * step[1], box_lo, box_hi)};
      if (step_length * alpha < 1e-6 || halvings >= 30) break;
      const double f1 = 0.5 * (slave - surface.position(next[0], next[1])).squaredNorm();
      if (f1 <= f0 + 1e-4 * alpha * slope) break;
      alpha *= 0.5;
    }
    const double moved = std::max(std::abs(next[0] - p[0]), std::abs(next[1] - p[1]));
    p = next;
    if (step_length <= options.tol_param) return {p, it, true, false, false};
    // Not moving although the Newton step is not small: pinned against the box (the minimum lies beyond
    // it) or no descent possible. Not a stationary point; stop instead of spinning.
    if (moved <= options.tol_param) return {p, it, false, false, false};
  }
  return {p, options.max_iterations, false, false, false};
}

/// Fills gap and sqr_distance at result.param; false where the normal vanishes (degenerate) or a value is
/// not finite. `is_minimum` (optional) receives whether the exact Hessian of |S - P|^2 / 2 there is positive
/// semi-definite to rounding: a local minimum, not a saddle or a maximum, which Newton on Eqs 7-8 converges
/// to just as well.
template <class SurfaceT>
bool fill_solution(const SurfaceT& surface, const Vec3& slave, ProjectionResult& result, double length,
                   bool* is_minimum = nullptr) {
  const SurfacePoint point = surface.evaluate(result.param[0], result.param[1]);
  const Vec3 normal = point.d_s.cross(point.d_t);
  const double normal_length = normal.norm();
  if (!(normal_length > 1e-12 * length * length)) return false;
  const Vec3 d = slave - point.position;
  result.gap = normal.dot(d) / normal_length;
  result.sqr_distance = d.squaredNorm();
  if (is_minimum != nullptr) {
    const NewtonSystem s = newton_system(point, slave);
    const double tol = 1e-10 * length * length;
    *is_minimum = s.h00 >= -tol && s.h11 >= -tol && s.h00 * s.h11 - s.h01 * s.h01 >= -tol * tol;
  }
  return std::isfinite(result.gap) && std::isfinite(result.sqr_distance);
}

bool inside(const std::array<double, 2>& p, ParamDomain domain, double margin) {
  return p[0] >= domain.lo - margin && p[0] <= domain.hi + margin && p[1] >= domain.lo - margin &&
         p[1] <= domain.hi + margin;
}

}  // namespace

template <geometry::Surface SurfaceT>
ProjectionResult project_point(const SurfaceT& surface, const Vec3& slave, const ProjectionOptions& options) {
  const ParamDomain domain = param_domain(SurfaceT::kKind);
  ProjectionResult best;
  best.param = domain_centre(SurfaceT::kKind);
  if (!slave.allFinite()) return best;  // invalid
  const double length = surface.characteristic_length();
  if (!std::isfinite(length)) return best;
  if (!(length > 0.0)) {
    best.status = Status::kDegenerate;
    return best;
  }

  const int n = options.warm_start ? 1 : std::max(options.starts_per_axis, 1);
  bool have_inside = false;
  bool have_outside = false;
  bool any_degenerate = false;
  bool any_invalid = false;
  int max_iterations_seen = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      // Starts at the centres of an n x n grid of cells: n = 1 is the domain centre.
      const double width = domain.hi - domain.lo;
      const std::array<double, 2> start =
          options.warm_start
              ? options.start
              : std::array<double, 2>{domain.lo + width * (i + 0.5) / n, domain.lo + width * (j + 0.5) / n};
      const RunResult run = damped_newton(surface, slave, start, options, length);
      max_iterations_seen = std::max(max_iterations_seen, run.iterations);
      any_invalid = any_invalid || run.invalid;
      if (run.degenerate) any_degenerate = true;
      if (!run.converged) continue;
      ProjectionResult candidate;
      candidate.param = run.param;
      candidate.iterations = run.iterations;
      bool is_minimum = false;
      if (!fill_solution(surface, slave, candidate, length, &is_minimum)) {
        any_degenerate = true;
        continue;
      }
      if (!is_minimum) continue;  // a saddle: never the label
      const bool candidate_inside = inside(run.param, domain, options.domain_margin);
      candidate.status = candidate_inside ? Status::kOk : Status::kOutside;
      // Inside beats outside; among equals the nearer wins; ties keep the earlier start (determinism).
      const bool better = (candidate_inside && !have_inside) ||
                          (candidate_inside == have_inside &&
                           (!(have_inside || have_outside) || candidate.sqr_distance < best.sqr_distance));
      if (better) {
        best = candidate;
        have_inside = have_inside || candidate_inside;
        have_outside = have_outside || !candidate_inside;
      }
    }
  }
  if (have_inside || have_outside) return best;
  best = ProjectionResult{};
  best.param = domain_centre(SurfaceT::kKind);
  best.iterations = max_iterations_seen;
  best.status = any_invalid      ? Status::kInvalid
                : any_degenerate ? Status::kDegenerate
                                 : Status::kNoConvergence;
  return best;
}

template <geometry::Surface SurfaceT>
std::array<double, 2> newton_fixed_iterations(const SurfaceT& surface, const Vec3& slave, int iterations,
                                              std::array<double, 2> p) {
  for (int it = 0; it < iterations; ++it) {
    const NewtonSystem s = newton_system(surface.evaluate(p[0], p[1]), slave);
    const double det = s.h00 * s.h11 - s.h01 * s.h01;
    if (det == 0.0) break;
    p[0] += (s.h11 * s.r0 - s.h01 * s.r1) / det;
    p[1] += (s.h00 * s.r1 - s.h01 * s.r0) / det;
  }
  return p;
}

template <geometry::Surface SurfaceT>
ProjectionResult newton_until_converged(const SurfaceT& surface, const Vec3& slave, std::array<double, 2> p,
                                        int max_iterations, double tol_param) {
  ProjectionResult result;
  result.param = p;
  if (!slave.allFinite()) return result;
  const double length = surface.characteristic_length();
  for (int it = 1; it <= max_iterations; ++it) {
    const NewtonSystem s = newton_system(surface.evaluate(p[0], p[1]), slave);
    const double det = s.h00 * s.h11 - s.h01 * s.h01;
    if (!std::isfinite(det)) return result;  // invalid
    if (det == 0.0) {
      result.status = Status::kDegenerate;
      result.iterations = it;
      return result;
    }
    const double d0 = (s.h11 * s.r0 - s.h01 * s.r1) / det;
    const double d1 = (s.h00 * s.r1 - s.h01 * s.r0) / det;
    p[0] += d0;
    p[1] += d1;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1])) {
      result.status = Status::kNoConvergence;
      result.iterations = it;
      return result;
    }
    if (std::max(std::abs(d0), std::abs(d1)) <= tol_param) {
      result.param = p;
      result.iterations = it;
      if (!fill_solution(surface, slave, result, length)) {
        result.status = Status::kDegenerate;
        return result;
      }
      result.status = inside(p, param_domain(SurfaceT::kKind), 1e-10) ? Status::kOk : Status::kOutside;
      return result;
    }
  }
  result.status = Status::kNoConvergence;
  result.iterations = max_iterations;
  return result;
}

#define CONTACTNN_INSTANTIATE_PROJECTION(SurfaceT)                                                           \
  template ProjectionResult project_point<SurfaceT>(const SurfaceT&, const Vec3&, const ProjectionOptions&); \
  template std::array<double, 2> newton_fixed_iterations<SurfaceT>(const SurfaceT&, const Vec3&, int,        \
                                                                   std::array<double, 2>);                   \
  template ProjectionResult newton_until_converged<SurfaceT>(const SurfaceT&, const Vec3&,                   \
                                                             std::array<double, 2>, int, double);
CONTACTNN_INSTANTIATE_PROJECTION(geometry::BilinearPatch)
CONTACTNN_INSTANTIATE_PROJECTION(geometry::GregoryPatch)
#undef CONTACTNN_INSTANTIATE_PROJECTION

}  // namespace contactnn::projection
