#include "contact/quadratic_certificate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "contact/bilinear_certificate.hpp"
#include "geometry/segment_checks.hpp"
#include "projection/closest_point_on_quadratic_face.hpp"

namespace contactnn::contact {

namespace {

/// The certificate holds where the bound of |M|_2 is below this fraction of lambda_floor: the Hessian's
/// smallest eigenvalue is then at least (1 - kMargin) lambda_floor everywhere on the face.
constexpr double kMargin = 0.9;
/// Newton's iterations before the run is given up (a strongly convex f converges in a few).
constexpr int kMaxIterations = 16;

template <std::size_t N>
bool all_finite(const std::array<Vec3, N>& x) {
  return std::all_of(x.begin(), x.end(), [](const Vec3& v) { return v.allFinite(); });
}

/// lo_k, hi_k: the range of Q.v_k over the control points `q`.
template <std::size_t N>
void ranges(QuadraticCertificate& c, const std::array<Vec3, N>& q, std::size_t count) {
  for (std::size_t k = 0; k < count; ++k) {
    c.lo[k] = std::numeric_limits<double>::infinity();
    c.hi[k] = -std::numeric_limits<double>::infinity();
    for (const Vec3& x : q) {
      const double v = x.dot(c.curvature[k]);
      c.lo[k] = std::min(c.lo[k], v);
      c.hi[k] = std::max(c.hi[k], v);
    }
  }
}

/// The largest S.v_k - Q.v_k over the control points (an upper bound of r.v), for k in [from, to).
double upper(const QuadraticCertificate& c, const Vec3& relative, std::size_t from, std::size_t to) {
  double m = -std::numeric_limits<double>::infinity();
  for (std::size_t k = from; k < to; ++k) m = std::max(m, relative.dot(c.curvature[k]) - c.lo[k]);
  return m;
}

/// The largest |S.v_k - Q.v_k| over the control points (a bound of |r.v|), for k in [from, to).
double largest(const QuadraticCertificate& c, const Vec3& relative, std::size_t from, std::size_t to) {
  double m = 0.0;
  for (std::size_t k = from; k < to; ++k) {
    const double at = relative.dot(c.curvature[k]);
    m = std::max({m, std::abs(at - c.lo[k]), std::abs(at - c.hi[k])});
  }
  return m;
}

/// Each edge's sphere: about the mean of its Bezier control points X, 2 M - (X + Y) / 2, Y, through the
/// farthest (a little larger, for rounding).
void edge_spheres(QuadraticCertificate& c, std::span<const Vec3> x, std::size_t corners) {
  for (std::size_t e = 0; e < corners; ++e) {
    const Vec3& a = x[e];
    const Vec3& b = x[(e + 1) % corners];
    const Vec3 m = 2.0 * x[corners + e] - 0.5 * (a + b);
    c.edge_centre[e] = (a + b + m) / 3.0;
    c.edge_radius[e] = (1.0 + 1e-12) * std::max({(a - c.edge_centre[e]).norm(), (b - c.edge_centre[e]).norm(),
                                                 (m - c.edge_centre[e]).norm()});
  }
}

constexpr double kBinomial[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};

/// The t in [0, 1] of the nearest point to `slave` of the curve C(t) = c0 + c1 t + c2 t^2 through the edge's
/// corners X, Y and mid-side node M (the reference's edge curve), where f = |C - S|^2 / 2 is strictly convex
/// in t (the certificate holds on the face, and an edge is a segment of its parameters): f' = C'.(C - S)
/// increases, so its root (or the end where it has none) is the edge's one minimum, found by Newton kept in
/// a shrinking bracket (bisection where a step leaves it), to rounding.
double convex_edge_minimum(const Vec3& x, const Vec3& m, const Vec3& y, const Vec3& slave) {
  const Vec3 c0 = x - slave, c1 = -3.0 * x + 4.0 * m - y, c2 = 2.0 * x - 4.0 * m + 2.0 * y;
  const auto slope = [&](double t) { return (c1 + (2.0 * t) * c2).dot(c0 + t * (c1 + t * c2)); };
  const double s0 = slope(0.0), s1 = slope(1.0);
  if (!(s0 < 0.0)) return 0.0;
  if (!(s1 > 0.0)) return 1.0;
  // The root of f' between, from the secant's (f' is nearly linear on a mildly curved edge).
  double a = 0.0, b = 1.0, t = s0 / (s0 - s1);
  for (int it = 0; it < 100; ++it) {
    const Vec3 d1 = c1 + (2.0 * t) * c2;
    const Vec3 r = c0 + t * (c1 + t * c2);
    const double g = d1.dot(r);
    if (g == 0.0 || !std::isfinite(g)) break;
    if (g < 0.0) {
      a = t;
    } else {
      b = t;
    }
    const double h = d1.squaredNorm() + 2.0 * c2.dot(r);
    const double step = h > 0.0 ? -g / h : std::numeric_limits<double>::infinity();
    if (std::abs(step) <= 4.0 * std::numeric_limits<double>::epsilon()) {
      t = std::clamp(t + step, 0.0, 1.0);  // converged: the last step, to rounding
      break;
    }
    double next = t + step;
    if (!(next > a && next < b)) next = 0.5 * (a + b);  // a step out of the bracket: bisection
    if (next == t) break;
    t = next;
  }
  return t;
}

/// The Newton run, the edges and the certificate of a boundary answer, for either face (Face: the face
/// relative to its first node).
template <class Face>
std::optional<projection::FaceClosestPoint> certified(const QuadraticCertificate& c, const Face& face,
                                                      const Vec3& relative,
                                                      const projection::ProjectionOptions& options,
                                                      const std::array<double, 2>* start) {
  const bool triangle = c.triangle;
  // 1. One Newton run on grad f = 0 (undamped: f is strictly convex on the face).
  std::array<double, 2> p = start != nullptr ? *start
                            : triangle       ? std::array<double, 2>{1.0 / 3.0, 1.0 / 3.0}
                                             : std::array<double, 2>{0.0, 0.0};
  const double residual_floor = options.tol_residual * c.length * c.length;
  bool converged = false;
  int iterations = 0;
  double squared = 0.0;  // |S - P|^2 at the last iterate evaluated (the converged point's, to rounding)
  for (int it = 1; it <= kMaxIterations; ++it) {
    const geometry::SurfacePoint sp = face.evaluate(p[0], p[1]);
    const Vec3 r = relative - sp.position;
    squared = r.squaredNorm();
    const double r0 = sp.d_s.dot(r), r1 = sp.d_t.dot(r);
    if (std::abs(r0) <= residual_floor && std::abs(r1) <= residual_floor) {
      converged = true;
      iterations = it - 1;
      break;
    }
    const double h00 = sp.d_s.squaredNorm() - sp.d_ss.dot(r), h11 = sp.d_t.squaredNorm() - sp.d_tt.dot(r);
    const double h01 = sp.d_s.dot(sp.d_t) - sp.d_st.dot(r);
    const double det = h00 * h11 - h01 * h01;
    if (!(det > 0.0) || !(h00 > 0.0)) break;  // beyond the face, where nothing is certified
    const double inverse = 1.0 / det;
    const double d0 = (h11 * r0 - h01 * r1) * inverse, d1 = (h00 * r1 - h01 * r0) * inverse;
    p = {p[0] + d0, p[1] + d1};
    // Beyond the face by far, or (from the second step, the run converging) by ten times the last step: the
    // stationary point lies outside and the face's minimum on its boundary, where the edges decide. Were it
    // inside after all, the boundary point fails step 3's test and the reference decides.
    const double step = std::max(std::abs(d0), std::abs(d1));
    const double outside = triangle ? std::max({-p[0], -p[1], p[0] + p[1] - 1.0})
                                    : std::max(std::abs(p[0]), std::abs(p[1])) - 1.0;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || outside > 0.5 || (it > 1 && outside > 10.0 * step)) {
      break;
    }
    if (step <= options.tol_param) {
      converged = true;
      iterations = it;
      break;
    }
  }
  const double margin = options.domain_margin;
  const bool interior =
      converged && (triangle ? p[0] >= -margin && p[1] >= -margin && p[0] + p[1] <= 1.0 + margin
                             : std::abs(p[0]) <= 1.0 + margin && std::abs(p[1]) <= 1.0 + margin);

  // 2. As the reference: the interior point (moved onto the face), then the edges, the nearest wins. f grows
  //    by at least mu |q - p|^2 / 2 from the interior minimum p to any q of the face (mu = (1 - kMargin) x
  //    lambda_floor), so every edge point's squared distance exceeds p's by mu delta^2 at least, delta the
  //    parameter distance from p to the boundary. Where that is 1e8 times the rounding of the squared
  //    distances, the edges cannot win and are not computed.
  bool edges_farther = false;
  if (interior) {
    const double delta = triangle ? std::min({p[0], p[1], (1.0 - p[0] - p[1]) / std::sqrt(2.0)})
                                  : 1.0 - std::max(std::abs(p[0]), std::abs(p[1]));
    edges_farther = delta > 0.0 &&
                    (1.0 - kMargin) * c.lambda_floor * delta * delta > 1e-8 * (squared + c.length * c.length);
  }
  // 3. The certificate of a boundary point q: no descent into the face from it (Karush-Kuhn-Tucker; the edge
  //    search leaves it stationary along its edge). f being convex, q is then the face's minimum.
  const auto minimum_at = [&](const std::array<double, 2>& q) {
    const geometry::SurfacePoint sp = face.evaluate(q[0], q[1]);
    const Vec3 r = relative - sp.position;
    const double g[2] = {-sp.d_s.dot(r), -sp.d_t.dot(r)};
    const double tol = 1e-12 * (1.0 - kMargin) * c.lambda_floor;
    if (triangle) {
      // The directions to the triangle's vertices span the cone into the face from any point of its
      // boundary (along the point's own edge the slope is the edge search's rounding).
      static constexpr std::array<std::array<double, 2>, 3> kVertex = {{{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}}};
      for (const auto& v : kVertex) {
        if (g[0] * (v[0] - q[0]) + g[1] * (v[1] - q[1]) < -tol) return false;
      }
      return true;
    }
    // The square: at a bound, no descent back into it (a corner: both bounds, its whole cone).
    for (std::size_t k = 0; k < 2; ++k) {
      if (q[k] == -1.0 && g[k] < -tol) return false;
      if (q[k] == 1.0 && g[k] > tol) return false;
    }
    return true;
  };

  // The edges: each one's minimum by convex_edge_minimum (f is strictly convex along it), not the reference's
  // 33 samples; the same point to rounding. Nearest sphere first; an edge whose sphere is beyond the best
  // point (with a margin for rounding) cannot win.
  projection::FaceClosestPoint out;
  double best = std::numeric_limits<double>::infinity();
  if (interior) {
    out = projection::nearest_of_interior_and_quadratic_edges(face, relative, &p, iterations, nullptr, true);
    if (out.status != Status::kOk) return std::nullopt;
    if (edges_farther) return out;
    best = (relative - face.position(out.param[0], out.param[1])).norm();
  }
  const std::size_t corners = triangle ? 3 : 4;
  std::array<std::pair<double, std::size_t>, 4> order;
  for (std::size_t e = 0; e < corners; ++e)
    order[e] = {(relative - c.edge_centre[e]).norm() - c.edge_radius[e], e};
  std::sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(corners));
  const auto& x = face.nodes();
  std::array<double, 2> nearest{};
  bool edge_wins = false;
  std::size_t winner = 0;
  for (std::size_t k = 0; k < corners; ++k) {
    const auto [bound, e] = order[k];
    if (bound > best + 1e-12 * (best + c.length)) break;
    const double t = convex_edge_minimum(x[e], x[corners + e], x[(e + 1) % corners], relative);
    const std::array<double, 2> q = triangle ? projection::triangle_edge_param(static_cast<int>(e), t)
                                             : projection::quad_edge_param(static_cast<int>(e), t);
    const double distance = (relative - face.position(q[0], q[1])).norm();
    // Strictly nearer replaces (the interior first, as the reference); equal distances keep the lower edge,
    // as the reference's order does.
    if (distance < best || (edge_wins && distance == best && e < winner)) {
      best = distance;
      nearest = q;
      edge_wins = true;
      winner = e;
      // Without an interior point: the first edge point that is the face's minimum (step 3) is the answer;
      // every other edge point is farther by mu |q' - q|^2 / 2 in f (the same corner where they meet).
      if (!interior && minimum_at(q)) break;
    }
  }
  if (!std::isfinite(best)) return std::nullopt;
  if (!edge_wins) return out;                     // the interior point, nearer than every edge
  if (!minimum_at(nearest)) return std::nullopt;  // the face holds a nearer point the run missed
  out = projection::quadratic_face_point(face, relative, nearest, interior ? iterations : 0);
  if (out.status != Status::kOk) return std::nullopt;
  return out;
}

/// The certificate's face: `world` relative to its first node (c.origin), with its edges' spheres and its
/// characteristic length; null (c left without a certificate) where a node is not finite.
template <class Face>
const Face* relative_face(QuadraticCertificate& c, const Face& world, std::size_t corners) {
  c.origin = world.nodes()[0];
  if (!c.origin.allFinite() || !all_finite(world.nodes())) return nullptr;
  auto x = world.nodes();
  for (Vec3& node : x) node -= c.origin;
  const Face& face = c.face.emplace<Face>(x);
  edge_spheres(c, x, corners);
  c.length = face.characteristic_length();
  return &face;
}

}  // namespace

QuadraticCertificate QuadraticCertificate::prepare(const geometry::SerendipityQuad& world) {
  QuadraticCertificate c;
  const geometry::SerendipityQuad* relative = relative_face(c, world, 4);
  if (relative == nullptr) return c;
  const geometry::SerendipityQuad& face = *relative;
  if (!(c.length > 0.0) || !std::isfinite(c.length) || geometry::is_degenerate_segment(face.corners()))
    return c;
  // The second derivatives' corner values.
  c.curvature[0] = face.evaluate(0.0, -1.0).d_ss;
  c.curvature[1] = face.evaluate(0.0, 1.0).d_ss;
  c.curvature[2] = face.evaluate(-1.0, 0.0).d_tt;
  c.curvature[3] = face.evaluate(1.0, 0.0).d_tt;
  c.curvature[4] = face.evaluate(-1.0, -1.0).d_st;
  c.curvature[5] = face.evaluate(1.0, -1.0).d_st;
  c.curvature[6] = face.evaluate(1.0, 1.0).d_st;
  c.curvature[7] = face.evaluate(-1.0, 1.0).d_st;
  const std::array<Vec3, 9> q = face.bezier_control_points();  // q[3 j + i]: i along s, j along t
  ranges(c, q, 8);
  // The Bezier forms of P_s (degree 1 in s, 2 in t: D_ij = Q_{i+1, j} - Q_ij, the factor 2 of d/du and the
  // 1/2 of du/ds cancelling) and P_t (E_ij = Q_{i, j+1} - Q_ij).
  const auto at = [&](std::size_t i, std::size_t j) { return q[3 * j + i]; };
  Vec3 d[2][3], e[3][2];
  double most_d = 0.0, most_e = 0.0;
  for (std::size_t i = 0; i < 2; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      d[i][j] = at(i + 1, j) - at(i, j);
      e[j][i] = at(j, i + 1) - at(j, i);
      most_d = std::max(most_d, d[i][j].squaredNorm());
      most_e = std::max(most_e, e[j][i].squaredNorm());
    }
  }
  const Vec3 centre = face.evaluate(0.0, 0.0).d_s.cross(face.evaluate(0.0, 0.0).d_t);
  const double norm = centre.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return c;
  const Vec3 n = centre / norm;
  Vec3 e_cross_n[3][2];  // (D x E).n = D.(E x n)
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 2; ++j) e_cross_n[i][j] = e[i][j].cross(n);
  }
  // (P_s x P_t).n in the Bernstein basis of degree (3, 3): B^1_a B^2_b = C(1,a) C(2,b) / C(3,a+b) B^3_{a+b}.
  double coefficient[4][4] = {};
  for (std::size_t i1 = 0; i1 < 2; ++i1) {
    for (std::size_t j1 = 0; j1 < 3; ++j1) {
      for (std::size_t i2 = 0; i2 < 3; ++i2) {
        for (std::size_t j2 = 0; j2 < 2; ++j2) {
          const std::size_t k = i1 + i2, l = j1 + j2;
          const double weight = kBinomial[1][i1] * kBinomial[2][i2] / kBinomial[3][k] * kBinomial[2][j1] *
                                kBinomial[1][j2] / kBinomial[3][l];
          coefficient[k][l] += weight * d[i1][j1].dot(e_cross_n[i2][j2]);
        }
      }
    }
  }
  double nu = std::numeric_limits<double>::infinity();
  for (const auto& row : coefficient) {
    for (const double v : row) nu = std::min(nu, v);
  }
  c.lambda_floor = eigenvalue_floor(nu, most_d + most_e);
  return c;
}

QuadraticCertificate QuadraticCertificate::prepare(const geometry::QuadraticTriangle& world) {
  QuadraticCertificate c;
  c.triangle = true;
  const geometry::QuadraticTriangle* relative = relative_face(c, world, 3);
  if (relative == nullptr) return c;
  const geometry::QuadraticTriangle& face = *relative;
  const std::array<Vec3, 6>& x = face.nodes();
  // The reference's degenerate triangle.
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0];
  const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (x[2] - x[1]).squaredNorm()});
  if (!(c.length > 0.0) || !std::isfinite(c.length) || !(e1.cross(e2).norm() > 1e-12 * longest2)) return c;
  const geometry::SurfacePoint centre = face.evaluate(1.0 / 3.0, 1.0 / 3.0);
  c.curvature[0] = centre.d_ss;
  c.curvature[1] = centre.d_st;
  c.curvature[2] = centre.d_tt;
  ranges(c, face.bezier_control_points(), 3);
  // P_r, P_s are affine: their values D_m, E_m at the corners are their Bezier coefficients (barycentric).
  static constexpr std::array<std::array<double, 2>, 3> kCorner = {{{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}}};
  std::array<Vec3, 3> d, e;
  double trace = 0.0;
  for (std::size_t m = 0; m < 3; ++m) {
    const geometry::SurfacePoint sp = face.evaluate(kCorner[m][0], kCorner[m][1]);
    d[m] = sp.d_s;
    e[m] = sp.d_t;
    trace = std::max(trace, d[m].squaredNorm() + e[m].squaredNorm());  // convex: largest at a corner
  }
  const Vec3 normal = centre.d_s.cross(centre.d_t);
  const double norm = normal.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return c;
  const Vec3 n = normal / norm;
  // (P_r x P_s).n in the quadratic Bernstein basis: D_m x E_m at the corners, (D_m x E_l + D_l x E_m) / 2
  // between.
  double nu = std::numeric_limits<double>::infinity();
  for (std::size_t m = 0; m < 3; ++m) {
    for (std::size_t l = m; l < 3; ++l) nu = std::min(nu, 0.5 * (d[m].cross(e[l]) + d[l].cross(e[m])).dot(n));
  }
  c.lambda_floor = eigenvalue_floor(nu, trace);
  return c;
}

bool QuadraticCertificate::convex_for(const Vec3& relative) const {
  // lambda_max(M) <= max(m00, m11) + |m01| (Gershgorin), with upper bounds of m00 = r.P_ss and m11 = r.P_tt
  // (signed: on a face's convex side they are negative and help) and a bound of |m01| = |r.P_st|.
  const double bound = triangle ? std::max(upper(*this, relative, 0, 1), upper(*this, relative, 2, 3)) +
                                      largest(*this, relative, 1, 2)
                                : std::max(upper(*this, relative, 0, 2), upper(*this, relative, 2, 4)) +
                                      largest(*this, relative, 4, 8);
  return bound < kMargin * lambda_floor;
}

std::optional<projection::FaceClosestPoint> QuadraticCertificate::closest_point(
    const Vec3& slave, const projection::ProjectionOptions& options,
    const std::array<double, 2>* start) const {
  const Vec3 relative = slave - origin;
  if (!(lambda_floor > 0.0) || !relative.allFinite() || !convex_for(relative)) return std::nullopt;
  std::optional<projection::FaceClosestPoint> out;
  if (const auto* tri6 = std::get_if<geometry::QuadraticTriangle>(&face)) {
    out = certified(*this, *tri6, relative, options, start);
  } else if (const auto* quad8 = std::get_if<geometry::SerendipityQuad>(&face)) {
    out = certified(*this, *quad8, relative, options, start);
  }
  if (out) out->point += origin;
  return out;
}

}  // namespace contactnn::contact
