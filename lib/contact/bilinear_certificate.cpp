#include "contact/bilinear_certificate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace contactnn::contact {

namespace {

/// The certificate holds where max_k |a3.(S - X_k)| is below this fraction of lambda_floor: the Hessian's
/// smallest eigenvalue is then at least (1 - kMargin) lambda_floor everywhere on the square.
constexpr double kMargin = 0.9;
/// Newton's iterations before the run is given up (a strongly convex, nearly quadratic f converges in a few).
constexpr int kMaxIterations = 16;
/// (s, t) of the corners A, B, C, D.
constexpr std::array<std::array<double, 2>, 4> kCorners = {
    {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}};

}  // namespace

double eigenvalue_floor(double nu, double trace) {
  if (!(nu > 0.0) || !(trace > 0.0) || !std::isfinite(nu) || !std::isfinite(trace)) return 0.0;
  const double det = nu * nu;
  const double floor = 2.0 * det / (trace + std::sqrt(std::max(trace * trace - 4.0 * det, 0.0)));
  return std::isfinite(floor) ? floor : 0.0;
}

BilinearCertificate BilinearCertificate::prepare(const std::array<Vec3, 4>& nodes) {
  BilinearCertificate c;
  c.origin = nodes[0];
  if (!c.origin.allFinite()) return c;
  std::array<Vec3, 4> x;
  for (std::size_t k = 0; k < 4; ++k) x[k] = nodes[k] - c.origin;
  for (const Vec3& v : x) {
    if (!v.allFinite()) return c;
  }
  c.patch = geometry::BilinearPatch(x);
  c.length = c.patch.characteristic_length();
  const Vec3 a1 = 0.25 * (-x[0] + x[1] + x[2] - x[3]);
  const Vec3 a2 = 0.25 * (-x[0] - x[1] + x[2] + x[3]);
  const Vec3 a3 = 0.25 * (x[0] - x[1] + x[2] - x[3]);
  c.twist = a3;
  for (std::size_t k = 0; k < 4; ++k) c.twist_at_corner[k] = a3.dot(x[k]);
  const Vec3 centre_normal = a1.cross(a2);
  const double norm = centre_normal.norm();
  if (!(norm > 0.0) || !std::isfinite(norm) || !(c.length > 0.0) || !std::isfinite(c.length)) return c;
  const Vec3 n = centre_normal / norm;
  double nu = std::numeric_limits<double>::infinity();
  for (const auto& [s, t] : kCorners) nu = std::min(nu, (a1 + t * a3).cross(a2 + s * a3).dot(n));
  const double trace = std::max((a1 - a3).squaredNorm(), (a1 + a3).squaredNorm()) +
                       std::max((a2 - a3).squaredNorm(), (a2 + a3).squaredNorm());
  c.lambda_floor = eigenvalue_floor(nu, trace);
  return c;
}

bool BilinearCertificate::convex_for(const Vec3& relative) const {
  const double at_slave = twist.dot(relative);
  double largest = 0.0;
  for (const double corner : twist_at_corner) largest = std::max(largest, std::abs(at_slave - corner));
  return largest < kMargin * lambda_floor;
}

std::optional<projection::FaceClosestPoint> BilinearCertificate::closest_point(
    const Vec3& slave, const projection::ProjectionOptions& options,
    const std::array<double, 2>* start) const {
  projection::FaceClosestPoint out;
  if (!closest_point(slave, options, start, out)) return std::nullopt;
  return out;
}

bool BilinearCertificate::closest_point(const Vec3& slave, const projection::ProjectionOptions& options,
                                        const std::array<double, 2>* start,
                                        projection::FaceClosestPoint& out) const {
  const Vec3 relative = slave - origin;
  if (!(lambda_floor > 0.0) || !relative.allFinite() || !convex_for(relative)) return false;

  // 1. One Newton run on grad f = 0 (undamped: f is strictly convex on the square and nearly quadratic).
  std::array<double, 2> p = start != nullptr ? *start : std::array<double, 2>{0.0, 0.0};
  const double residual_floor = options.tol_residual * length * length;
  const double margin = options.domain_margin;
  // Step 2 (below), as projection::closest_point_on_face: the interior point (clamped), then the edges, the
  // nearest wins. f grows by at least mu |q - p|^2 / 2 from the interior minimum p to any q (mu = (1 -
  // kMargin) x lambda_floor), so every edge point's squared distance exceeds p's by mu delta^2 at least,
  // delta the parameter distance from p to the boundary. Where that is 1e8 times the rounding of the squared
  // distances (1e-16 of |S - P|^2 + length^2), the edges cannot win and are not computed.
  const auto edges_farther_from = [&](const std::array<double, 2>& q, double squared) {
    const double delta = 1.0 - std::max(std::abs(q[0]), std::abs(q[1]));
    return delta > 0.0 && (1.0 - kMargin) * lambda_floor * delta * delta > 1e-8 * (squared + length * length);
  };
  // The answer p where the run ends inside the square (delta > 0: nothing to clamp) and the edges cannot
  // win, reported into `out` from the evaluation `sp` there: the report nearest_of_interior_and_edges would
  // make, without evaluating the patch again (every field written; none of them where the edges may win:
  // they are then computed below).
  const auto interior_answer = [&](const geometry::SurfacePoint& sp, double squared, int its) {
    if (!(std::abs(p[0]) <= 1.0 + margin && std::abs(p[1]) <= 1.0 + margin && edges_farther_from(p, squared)))
      return false;
    out.param = p;
    projection::locate_on_quad(param_domain(SurfaceKind::kBilinear), out);
    projection::report_at(sp, relative, out);
    out.iterations = its;
    out.by_method = false;
    out.point += origin;
    return true;
  };
  bool converged = false;
  int iterations = 0;
  for (int it = 1; it <= kMaxIterations; ++it) {
    const geometry::SurfacePoint sp = patch.evaluate(p[0], p[1]);
    const Vec3 r = relative - sp.position;
    const double r0 = sp.d_s.dot(r), r1 = sp.d_t.dot(r);
    if (std::abs(r0) <= residual_floor && std::abs(r1) <= residual_floor) {
      converged = true;
      iterations = it - 1;
      if (interior_answer(sp, r.squaredNorm(), iterations)) return out.status == Status::kOk;
      break;
    }
    const double h00 = sp.d_s.squaredNorm(), h11 = sp.d_t.squaredNorm();
    const double h01 = sp.d_s.dot(sp.d_t) - twist.dot(r);
    const double det = h00 * h11 - h01 * h01;
    if (!(det > 0.0)) break;  // beyond the square, where nothing is certified
    const double d0 = (h11 * r0 - h01 * r1) / det, d1 = (h00 * r1 - h01 * r0) / det;
    p = {p[0] + d0, p[1] + d1};
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || std::max(std::abs(p[0]), std::abs(p[1])) > 4.0) break;
    if (std::max(std::abs(d0), std::abs(d1)) <= options.tol_param) {
      converged = true;
      iterations = it;
      // The run ends at p: one evaluation there decides the edges and makes the report.
      const geometry::SurfacePoint at = patch.evaluate(p[0], p[1]);
      if (interior_answer(at, (relative - at.position).squaredNorm(), iterations))
        return out.status == Status::kOk;
      break;
    }
  }
  // Both exits of a converged run above have answered wherever the edges cannot win (interior_answer, from
  // an evaluation at p): here they may, and are computed.
  const bool interior = converged && std::abs(p[0]) <= 1.0 + margin && std::abs(p[1]) <= 1.0 + margin;
  bool from_interior = false;
  out = projection::nearest_of_interior_and_edges(patch, relative, interior ? &p : nullptr, iterations,
                                                  &from_interior, false);
  if (out.status != Status::kOk) return false;

  // 3. The certificate of a boundary answer: no descent into the square (Karush-Kuhn-Tucker). Otherwise the
  //    square's interior holds a nearer point that the run did not reach: the reference decides.
  if (!from_interior) {
    const geometry::SurfacePoint at = patch.evaluate(out.param[0], out.param[1]);
    const Vec3 r = relative - at.position;
    const double g[2] = {-at.d_s.dot(r), -at.d_t.dot(r)};
    const double tol = 1e-12 * (1.0 - kMargin) * lambda_floor;
    for (std::size_t k = 0; k < 2; ++k) {
      if (out.param[k] == 1.0 && g[k] > tol) return false;
      if (out.param[k] == -1.0 && g[k] < -tol) return false;
    }
  }
  out.point += origin;
  return true;
}

}  // namespace contactnn::contact
