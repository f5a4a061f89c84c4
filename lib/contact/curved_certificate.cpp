#include "contact/curved_certificate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <type_traits>

#include "contact/bilinear_certificate.hpp"
#include "geometry/configuration.hpp"
#include "geometry/segment_checks.hpp"
#include "geometry/surface_of.hpp"
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
void ranges(CurvedCertificate& c, const std::array<Vec3, N>& q, std::size_t count) {
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
double upper(const CurvedCertificate& c, const Vec3& relative, std::size_t from, std::size_t to) {
  double m = -std::numeric_limits<double>::infinity();
  for (std::size_t k = from; k < to; ++k) m = std::max(m, relative.dot(c.curvature[k]) - c.lo[k]);
  return m;
}

/// The largest |S.v_k - Q.v_k| over the control points (a bound of |r.v|), for k in [from, to).
double largest(const CurvedCertificate& c, const Vec3& relative, std::size_t from, std::size_t to) {
  double m = 0.0;
  for (std::size_t k = from; k < to; ++k) {
    const double at = relative.dot(c.curvature[k]);
    m = std::max({m, std::abs(at - c.lo[k]), std::abs(at - c.hi[k])});
  }
  return m;
}

/// Edge e's sphere about the mean of its Bezier control points `q` (the edge lies in their hull), through the
/// farthest (a little larger, for rounding).
void edge_sphere(CurvedCertificate& c, std::size_t e, std::span<const Vec3> q) {
  Vec3 centre = Vec3::Zero();
  for (const Vec3& x : q) centre += x;
  centre /= static_cast<double>(q.size());
  double radius = 0.0;
  for (const Vec3& x : q) radius = std::max(radius, (x - centre).norm());
  c.edge_centre[e] = centre;
  c.edge_radius[e] = (1.0 + 1e-12) * radius;
}

/// Edge e's chord end C(1) (the sum of its curve's coefficients: the same bits when prepared and searched).
Vec3 edge_end(const CurvedCertificate& c, std::size_t e) {
  const std::array<Vec3, 4>& k = c.edge_curve[e];
  return ((k[0] + k[1]) + k[2]) + k[3];
}

/// The distance from x to the segment from a to b.
double segment_distance(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double dd = d.squaredNorm();
  const double t = dd > 0.0 ? std::clamp((x - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return (x - a - t * d).norm();
}

/// Edge e's bulge (CurvedCertificate::edge_bulge) from its Bezier control points `q`, its curve set.
void edge_chord(CurvedCertificate& c, std::size_t e, std::span<const Vec3> q) {
  const Vec3& a = c.edge_curve[e][0];
  const Vec3 b = edge_end(c, e);
  double bulge = 0.0;
  for (const Vec3& x : q) bulge = std::max(bulge, segment_distance(x, a, b));
  // The control points' distances, and the chord's ends (rounded sums), to far above their rounding.
  c.edge_bulge[e] = (1.0 + 1e-9) * bulge + 1e-12 * (c.edge_radius[e] + a.norm() + b.norm());
}

/// Each quadratic edge's sphere (about its Bezier control points X, 2 M - (X + Y) / 2, Y) and its curve
/// C(t) = X (1 - t)(1 - 2t) + 4 M t (1 - t) + Y t (2t - 1) in powers of t.
void quadratic_edges(CurvedCertificate& c, std::span<const Vec3> x, std::size_t corners) {
  for (std::size_t e = 0; e < corners; ++e) {
    const Vec3& a = x[e];
    const Vec3& b = x[(e + 1) % corners];
    const Vec3& m = x[corners + e];
    const std::array<Vec3, 3> q = {a, b, Vec3(2.0 * m - 0.5 * (a + b))};  // summed in this order, as before
    edge_sphere(c, e, q);
    c.edge_curve[e] = {a, Vec3(-3.0 * a + 4.0 * m - b), Vec3(2.0 * a - 4.0 * m + 2.0 * b), Vec3::Zero()};
    edge_chord(c, e, q);
  }
}

constexpr double kBinomial[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};

/// The t in [0, 1] of the nearest point to `slave` of an edge's curve C(t) = c0 + c1 t + c2 t^2 + c3 t^3 (the
/// reference's edge curve: quadratic through a quadratic face's corners and mid-side node, c3 = 0, or a
/// Gregory patch's cubic boundary), where f = |C - S|^2 / 2 is strictly convex in t (the certificate holds
/// on the face, and an edge is a segment of its parameters): f' = C'.(C - S) increases, so its root (or the
/// end where it has none) is the edge's one minimum, found by Newton kept in a shrinking bracket (bisection
/// where a step leaves it), to rounding. With c3 = 0 every operation below gives the quadratic's own bits.
double convex_edge_minimum(const std::array<Vec3, 4>& curve, const Vec3& slave) {
  const Vec3 c0 = curve[0] - slave;
  const Vec3 &c1 = curve[1], &c2 = curve[2], &c3 = curve[3];
  const auto slope = [&](double t) {
    return (c1 + t * (2.0 * c2 + (3.0 * t) * c3)).dot(c0 + t * (c1 + t * (c2 + t * c3)));
  };
  const double s0 = slope(0.0), s1 = slope(1.0);
  if (!(s0 < 0.0)) return 0.0;
  if (!(s1 > 0.0)) return 1.0;
  // The root of f' between, from the secant's (f' is nearly linear on a mildly curved edge).
  double a = 0.0, b = 1.0, t = s0 / (s0 - s1);
  for (int it = 0; it < 100; ++it) {
    const Vec3 d1 = c1 + t * (2.0 * c2 + (3.0 * t) * c3);
    const Vec3 r = c0 + t * (c1 + t * (c2 + t * c3));
    const double g = d1.dot(r);
    if (g == 0.0 || !std::isfinite(g)) break;
    if (g < 0.0) {
      a = t;
    } else {
      b = t;
    }
    const double h = d1.squaredNorm() + (2.0 * c2 + (6.0 * t) * c3).dot(r);
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

/// A curved face's parameter domain as `certified` walks it: the triangle r, s >= 0, r + s <= 1, or the
/// square of centre `mid` and half width `half` ([-1, 1]^2 for a quad8, [0, 1]^2 for a Gregory patch).
struct Domain {
  bool triangle = false;
  double mid = 0.0, half = 1.0;

  /// A fresh run's first iterate.
  [[nodiscard]] std::array<double, 2> centre() const {
    return triangle ? std::array<double, 2>{1.0 / 3.0, 1.0 / 3.0} : std::array<double, 2>{mid, mid};
  }
  /// How far q lies beyond the domain, in parameter units (negative inside).
  [[nodiscard]] double outside(const std::array<double, 2>& q) const {
    return triangle ? std::max({-q[0], -q[1], q[0] + q[1] - 1.0})
                    : std::max(std::abs(q[0] - mid), std::abs(q[1] - mid)) - half;
  }
  /// q within `margin` of the domain (the reference's test of an interior stationary point).
  [[nodiscard]] bool inside(const std::array<double, 2>& q, double margin) const {
    return triangle ? q[0] >= -margin && q[1] >= -margin && q[0] + q[1] <= 1.0 + margin
                    : std::abs(q[0] - mid) <= half + margin && std::abs(q[1] - mid) <= half + margin;
  }
  /// The parameter distance from q to the boundary (positive inside).
  [[nodiscard]] double depth(const std::array<double, 2>& q) const {
    return triangle ? std::min({q[0], q[1], (1.0 - q[0] - q[1]) / std::sqrt(2.0)})
                    : half - std::max(std::abs(q[0] - mid), std::abs(q[1] - mid));
  }
  /// out.location and out.feature from out.param.
  void locate(bool gregory, projection::FaceClosestPoint& out) const {
    if (triangle) {
      projection::locate_on_triangle(out);
    } else {
      projection::locate_on_quad(gregory ? param_domain(SurfaceKind::kGregory) : ParamDomain{-1.0, 1.0}, out);
    }
  }
};

/// Step 3 of `certified`, the certificate of a boundary point q: no descent into the face from it
/// (Karush-Kuhn-Tucker; the edge search leaves it stationary along its edge). f being convex, q is then the
/// face's minimum.
template <class Face>
bool no_descent_from(const CurvedCertificate& c, const Face& face, const Domain& d, const Vec3& relative,
                     const std::array<double, 2>& q) {
  const geometry::SurfacePoint at = face.evaluate(q[0], q[1]);
  const Vec3 r = relative - at.position;
  const double g[2] = {-at.d_s.dot(r), -at.d_t.dot(r)};
  const double tol = 1e-12 * (1.0 - kMargin) * c.lambda_floor;
  if (d.triangle) {
    // The directions to the triangle's vertices span the cone into the face from any point of its boundary
    // (along the point's own edge the slope is the edge search's rounding).
    static constexpr std::array<std::array<double, 2>, 3> kVertex = {{{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}}};
    for (const auto& v : kVertex) {
      if (g[0] * (v[0] - q[0]) + g[1] * (v[1] - q[1]) < -tol) return false;
    }
    return true;
  }
  // The square: at a bound, no descent back into it (a corner: both bounds, its whole cone).
  for (std::size_t k = 0; k < 2; ++k) {
    if (q[k] == d.mid - d.half && g[k] < -tol) return false;
    if (q[k] == d.mid + d.half && g[k] > tol) return false;
  }
  return true;
}

/// The Newton run, the edges and the certificate of a boundary answer, for either face (Face: the face
/// relative to its first node).
template <class Face>
bool certified(const CurvedCertificate& c, const Face& face, const Vec3& relative,
               const projection::ProjectionOptions& options, const std::array<double, 2>* start,
               projection::FaceClosestPoint& out) {
  constexpr bool gregory = std::is_same_v<Face, geometry::GregoryPatch>;
  // How far outside the domain an iterate may go before the boundary decides: a Gregory patch's denominators
  // vanish on lines through its corners just beyond the reference's box of 0.1.
  constexpr double escape = gregory ? 0.1 : 0.5;
  const Domain d{c.triangle, gregory ? 0.5 : 0.0, gregory ? 0.5 : 1.0};
  const double residual_floor = options.tol_residual * c.length * c.length;
  // 2. (below) As the reference: the interior point (moved onto the face), then the edges, the nearest wins.
  //    f grows by at least mu |q - p|^2 / 2 from the interior minimum p to any q of the face (mu = (1 -
  //    kMargin) x lambda_floor), so every edge point's squared distance exceeds p's by mu delta^2 at least,
  //    delta the parameter distance from p to the boundary. Where that is 1e8 times the rounding of the
  //    squared distances (`squared_distance` p's), the edges cannot win and are not computed.
  const auto edges_farther_from = [&](const std::array<double, 2>& q, double squared_distance) {
    const double delta = d.depth(q);
    return delta > 0.0 &&
           (1.0 - kMargin) * c.lambda_floor * delta * delta > 1e-8 * (squared_distance + c.length * c.length);
  };
  // 1. One Newton run on grad f = 0 (undamped: f is strictly convex on the face).
  std::array<double, 2> p = start != nullptr ? *start : d.centre();
  bool converged = false;
  int iterations = 0;
  double squared = 0.0;  // |S - P|^2 at the last iterate evaluated (the converged point's, to rounding)
  for (int it = 1; it <= kMaxIterations; ++it) {
    // A fresh run's first iterate is the centre, where the face's evaluation is kept (the same bits).
    const bool at_centre = it == 1 && start == nullptr;
    // A Gregory patch's second derivatives only where the run goes on (a converged run reports from the
    // point and its first derivatives; the same bits either way).
    geometry::SurfacePoint evaluated;
    [[maybe_unused]] geometry::GregoryPatch::Partial partial;
    if constexpr (gregory) {
      if (!at_centre) face.evaluate_first(p[0], p[1], partial, evaluated);
    } else {
      if (!at_centre) evaluated = face.evaluate(p[0], p[1]);
    }
    const geometry::SurfacePoint& sp = at_centre ? c.at_centre : evaluated;
    const Vec3 r = relative - sp.position;
    squared = r.squaredNorm();
    const double r0 = sp.d_s.dot(r), r1 = sp.d_t.dot(r);
    if (std::abs(r0) <= residual_floor && std::abs(r1) <= residual_floor) {
      converged = true;
      iterations = it - 1;
      if (d.inside(p, options.domain_margin) && edges_farther_from(p, squared)) {
        // The answer is p, inside the face (delta > 0: nothing to clamp), where the run has just evaluated
        // the face: the report step 2 would make, without evaluating it again.
        out.param = p;
        out.iterations = iterations;
        out.by_method = false;
        d.locate(gregory, out);
        projection::report_at(sp, relative, out);
        return out.status == Status::kOk;
      }
      break;
    }
    if constexpr (gregory) {
      if (!at_centre) face.complete(partial, evaluated);
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
    const double outside = d.outside(p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || outside > escape ||
        (it > 1 && outside > 10.0 * step)) {
      break;
    }
    if (step <= options.tol_param) {
      converged = true;
      iterations = it;
      break;
    }
  }
  const bool interior = converged && d.inside(p, options.domain_margin);
  const bool edges_farther = interior && edges_farther_from(p, squared);

  // The edges: each one's minimum by convex_edge_minimum (f is strictly convex along it), not the reference's
  // 33 samples; the same point to rounding. Nearest sphere first; an edge whose sphere or chord (chord_bound)
  // is beyond the best point (with a margin for rounding) cannot win.
  double best = std::numeric_limits<double>::infinity();
  // The report of the point q of the closed face, as the reference's (its steps 2 and 3 for a point that has
  // already won).
  const auto report = [&](const std::array<double, 2>& q, int its) {
    if constexpr (gregory) {
      return projection::nearest_of_interior_and_edges(face, relative, &q, its, nullptr, true);
    } else {
      return projection::nearest_of_interior_and_quadratic_edges(face, relative, &q, its, nullptr, true);
    }
  };
  if constexpr (gregory) {
    if (edges_farther) {
      // The run ended on its step inside the face: report's answer at p (clamped onto the face), from the
      // point's position and first derivatives alone (report evaluates the second too; the same bits).
      const ParamDomain g = param_domain(SurfaceKind::kGregory);
      out.param = {std::clamp(p[0], g.lo, g.hi), std::clamp(p[1], g.lo, g.hi)};
      out.iterations = iterations;
      out.by_method = false;
      d.locate(true, out);
      geometry::GregoryPatch::Partial partial;
      geometry::SurfacePoint at;
      face.evaluate_first(out.param[0], out.param[1], partial, at);
      projection::report_at(at, relative, out);
      return out.status == Status::kOk;
    }
  }
  if (interior) {
    out = report(p, iterations);
    if (out.status != Status::kOk) return false;
    if (edges_farther) return true;
    best = (relative - face.position(out.param[0], out.param[1])).norm();
  }
  const std::size_t corners = d.triangle ? 3 : 4;
  std::array<std::pair<double, std::size_t>, 4> order;
  for (std::size_t e = 0; e < corners; ++e)
    order[e] = {(relative - c.edge_centre[e]).norm() - c.edge_radius[e], e};
  std::sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(corners));
  std::array<double, 2> nearest{};
  bool edge_wins = false;
  std::size_t winner = 0;
  for (std::size_t k = 0; k < corners; ++k) {
    const auto [bound, e] = order[k];
    const double margin = 1e-12 * (best + c.length);
    if (bound > best + margin) break;
    // The chord's bound, where the sphere's leaves the edge in (0 beside a nearly straight edge: a node over
    // a tri6 sheet's shared edge searched all three edges of both faces).
    if (c.chord_bound(e, relative) > best + margin) continue;
    const double t = convex_edge_minimum(c.edge_curve[e], relative);
    const auto edge = static_cast<int>(e);
    const std::array<double, 2> q =
        d.triangle ? projection::triangle_edge_param(edge, t)
        : gregory  ? projection::domain_edge_param(edge, t, param_domain(SurfaceKind::kGregory))
                   : projection::quad_edge_param(edge, t);
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
      if (!interior && no_descent_from(c, face, d, relative, q)) break;
    }
  }
  if (!std::isfinite(best)) return false;
  if (!edge_wins) return true;  // the interior point, nearer than every edge
  // 3. The face holds a nearer point the run missed, unless no descent leads into it from the edge's point.
  if (!no_descent_from(c, face, d, relative, nearest)) return false;
  if constexpr (gregory) {
    out = report(nearest, interior ? iterations : 0);
  } else {
    out = projection::quadratic_face_point(face, relative, nearest, interior ? iterations : 0);
  }
  return out.status == Status::kOk;
}

/// The certificate's face: `world` relative to its first node (c.origin), with its edges' spheres and its
/// characteristic length; null (c left without a certificate) where a node is not finite.
template <class Face>
const Face* relative_face(CurvedCertificate& c, const Face& world, std::size_t corners) {
  c.origin = world.nodes()[0];
  if (!c.origin.allFinite() || !all_finite(world.nodes())) return nullptr;
  auto x = world.nodes();
  for (Vec3& node : x) node -= c.origin;
  const Face& face = c.face.emplace<Face>(x);
  quadratic_edges(c, x, corners);
  c.length = face.characteristic_length();
  return &face;
}

}  // namespace

CurvedCertificate CurvedCertificate::prepare(const geometry::SerendipityQuad& world) {
  CurvedCertificate c;
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
  c.at_centre = face.evaluate(0.0, 0.0);
  const Vec3 centre = c.at_centre.d_s.cross(c.at_centre.d_t);
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

CurvedCertificate CurvedCertificate::prepare(const geometry::QuadraticTriangle& world) {
  CurvedCertificate c;
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
  c.at_centre = centre;
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

namespace {

/// A Gregory patch's bicubic point b_ij (i along u, j along v; the interior ones P_ij1, gregory_patch.hpp).
const Vec3& bicubic_point(const std::array<Vec3, 20>& q, int i, int j) {
  using geometry::GregoryPatch;
  const bool inner = i > 0 && i < 3 && j > 0 && j < 3;
  return q[static_cast<std::size_t>(inner ? GregoryPatch::interior_index(i, j, 1)
                                          : GregoryPatch::control_index(i, j))];
}

/// [along n, across n] of v.
std::array<double, 2> split(const Vec3& v, const Vec3& n) {
  const double along = v.dot(n);
  return {std::abs(along), (v - along * n).norm()};
}

/// g.second (the header's bounds of P_ss, P_st, P_tt, along g.normal and across it) for control points `q`;
/// returns the bounds of |P_ss|, |P_st|, |P_tt|.
std::array<double, 3> second_derivative_bounds(CurvedCertificate::GregoryBounds& g,
                                               const std::array<Vec3, 20>& q) {
  using geometry::GregoryPatch;
  std::array<double, 2> delta = {0.0, 0.0};
  for (int i = 1; i <= 2; ++i) {
    for (int j = 1; j <= 2; ++j) {
      const auto d = split(q[static_cast<std::size_t>(GregoryPatch::interior_index(i, j, 0))] -
                               q[static_cast<std::size_t>(GregoryPatch::interior_index(i, j, 1))],
                           g.normal);
      delta = {std::max(delta[0], d[0]), std::max(delta[1], d[1])};
    }
  }
  // The bicubic's Bezier coefficients (second differences), plus the bounds of the rational terms (the
  // largest |delta_k| part times kGregoryBound).
  std::array<std::array<double, 2>, 3> most{};  // ss, st, tt; [along, across]
  const auto include = [&](std::size_t k, const Vec3& v) {
    const auto d = split(v, g.normal);
    most[k] = {std::max(most[k][0], d[0]), std::max(most[k][1], d[1])};
  };
  const auto b = [&](int i, int j) -> const Vec3& { return bicubic_point(q, i, j); };
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 2; ++j) {
      include(0, 6.0 * (b(j + 2, i) - 2.0 * b(j + 1, i) + b(j, i)));
      include(2, 6.0 * (b(i, j + 2) - 2.0 * b(i, j + 1) + b(i, j)));
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) include(1, 9.0 * (b(i + 1, j + 1) - b(i + 1, j) - b(i, j + 1) + b(i, j)));
  }
  std::array<double, 3> whole{};
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t part = 0; part < 2; ++part) {
      most[k][part] = (1.0 + 1e-12) * (most[k][part] + kGregoryBound[k] * delta[part]);
      g.second[2 * k + part] = most[k][part];
    }
    whole[k] = std::hypot(most[k][0], most[k][1]);
  }
  return whole;
}

/// g's hull: the control points' mean, their range along g.normal and their largest distance across it.
void hull_bounds(CurvedCertificate::GregoryBounds& g, const std::array<Vec3, 20>& q, double length) {
  g.centre = Vec3::Zero();
  for (const Vec3& v : q) g.centre += v;
  g.centre /= static_cast<double>(q.size());
  g.below = std::numeric_limits<double>::infinity();
  g.above = -g.below;
  for (const Vec3& v : q) {
    const double along = (v - g.centre).dot(g.normal);
    g.below = std::min(g.below, along);
    g.above = std::max(g.above, along);
    g.across = std::max(g.across, split(v - g.centre, g.normal)[1]);
  }
  g.across *= 1.0 + 1e-12;
  g.below -= 1e-12 * length;
  g.above += 1e-12 * length;
}

/// The edges: cubic Bezier curves on the boundary points (the rational terms vanish there), in powers of t,
/// and their spheres.
void gregory_edges(CurvedCertificate& c, const std::array<Vec3, 20>& q) {
  for (int e = 0; e < 4; ++e) {
    std::array<Vec3, 4> p;
    for (int k = 0; k < 4; ++k) {
      const std::array<int, 2> ij = e == 0   ? std::array<int, 2>{k, 0}
                                    : e == 1 ? std::array<int, 2>{3, k}
                                    : e == 2 ? std::array<int, 2>{k, 3}
                                             : std::array<int, 2>{0, k};
      p[static_cast<std::size_t>(k)] = bicubic_point(q, ij[0], ij[1]);
    }
    const auto u = static_cast<std::size_t>(e);
    edge_sphere(c, u, p);
    c.edge_curve[u] = {p[0], Vec3(3.0 * (p[1] - p[0])), Vec3(3.0 * (p[0] - 2.0 * p[1] + p[2])),
                       Vec3(p[3] - p[0] + 3.0 * (p[1] - p[2]))};
    edge_chord(c, u, p);
  }
}

}  // namespace

void CurvedCertificate::prepare_gregory(CurvedCertificate& c, void* room, const std::array<Vec3, 4>& nodes,
                                        const std::array<Vec3, 4>& normals) {
  c.lambda_floor = 0.0;
  c.triangle = false;
  c.origin = nodes[0];
  // The reference's patch: on the nodes relative to the first, with the normals as given (the caller has
  // found the world nodes sound: closest_on_face's check).
  std::array<Vec3, 4> x = nodes;
  for (Vec3& node : x) node -= c.origin;
  if (!c.origin.allFinite() || !all_finite(x) ||
      geometry::GregoryPatch::diagnose(x, normals) != geometry::GregoryDefect::kNone) {
    c.face.emplace<std::monostate>();
    return;
  }
  const geometry::GregoryPatch& face =
      *::new (room) geometry::GregoryPatch(x, normals, geometry::GregoryPatch::Diagnosed{});
  c.face = &face;
  c.length = face.characteristic_length();
  if (!(c.length > 0.0) || !std::isfinite(c.length) || geometry::is_degenerate_segment(face.nodes())) return;
  const std::array<Vec3, 20>& q = face.control_points();
  // Everything split along the unit normal n at the centre and across it: a patch near its tangent plane
  // has small normal extent and mostly normal second derivatives, and r.P_ss <= |r.n| |P_ss.n| + |r_t|
  // |P_ss_t|.
  const geometry::SurfacePoint middle = face.evaluate(0.5, 0.5);
  c.at_centre = middle;
  const Vec3 normal = middle.d_s.cross(middle.d_t);
  if (!(normal.norm() > 0.0) || !normal.allFinite()) return;
  c.gregory = CurvedCertificate::GregoryBounds{};
  c.gregory.normal = normal.normalized();
  const std::array<double, 3> whole = second_derivative_bounds(c.gregory, q);
  hull_bounds(c.gregory, q, c.length);
  gregory_edges(c, q);
  // lambda_min(J^T J) over the square: sigma_min(J) at a point less |J - J(point)|_F, each column's change at
  // most half the width of the square about the point times its second derivatives. First the centre for the
  // whole square; where that gives under 3/4 of the centre's sigma, the better of it and 2 x 2 sub-squares.
  const auto sigma_at = [&](const geometry::SurfacePoint& at) {
    return std::sqrt(
        eigenvalue_floor(at.d_s.cross(at.d_t).norm(), at.d_s.squaredNorm() + at.d_t.squaredNorm()));
  };
  const double change = std::hypot(whole[0] + whole[1], whole[1] + whole[2]) * 0.5 * (1.0 + 1e-12);
  const double at_middle = sigma_at(middle) * (1.0 - 1e-12);
  double sigma = at_middle - change;
  if (sigma < 0.75 * at_middle) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const double u : {0.25, 0.75}) {
      for (const double v : {0.25, 0.75}) smallest = std::min(smallest, sigma_at(face.evaluate(u, v)));
    }
    sigma = std::max(sigma, smallest * (1.0 - 1e-12) - 0.5 * change);
  }
  c.lambda_floor = sigma > 0.0 && std::isfinite(sigma) ? sigma * sigma * (1.0 - 1e-12) : 0.0;
}

double CurvedCertificate::chord_bound(std::size_t e, const Vec3& relative) const {
  return segment_distance(relative, edge_curve[e][0], edge_end(*this, e)) - edge_bulge[e];
}

bool CurvedCertificate::convex_for(const Vec3& relative) const {
  if (std::holds_alternative<const geometry::GregoryPatch*>(face)) {
    // lambda_max(M) <= max(|m00|, |m11|) + |m01|, each |r.v| <= |r.n| |v.n| + |r_t| |v_t|: |r.n| at most the
    // slave's height beyond the hull's range along n, |r_t| its distance across n plus the hull's.
    const Vec3 d = relative - gregory.centre;
    const double along = d.dot(gregory.normal);
    const double r_n = std::max(std::abs(along - gregory.below), std::abs(along - gregory.above));
    const double r_t = (d - along * gregory.normal).norm() + gregory.across;
    const auto bound = [&](std::size_t k) {
      return r_n * gregory.second[2 * k] + r_t * gregory.second[2 * k + 1];
    };
    return std::max(bound(0), bound(2)) + bound(1) < kMargin * lambda_floor;
  }
  // lambda_max(M) <= max(m00, m11) + |m01| (Gershgorin), with upper bounds of m00 = r.P_ss and m11 = r.P_tt
  // (signed: on a face's convex side they are negative and help) and a bound of |m01| = |r.P_st|.
  const double bound = triangle ? std::max(upper(*this, relative, 0, 1), upper(*this, relative, 2, 3)) +
                                      largest(*this, relative, 1, 2)
                                : std::max(upper(*this, relative, 0, 2), upper(*this, relative, 2, 4)) +
                                      largest(*this, relative, 4, 8);
  return bound < kMargin * lambda_floor;
}

std::optional<projection::FaceClosestPoint> CurvedCertificate::closest_point(
    const Vec3& slave, const projection::ProjectionOptions& options, const std::array<double, 2>* start,
    bool convex_checked) const {
  projection::FaceClosestPoint out;
  if (!closest_point(slave, options, start, convex_checked, out)) return std::nullopt;
  return out;
}

bool CurvedCertificate::closest_point(const Vec3& slave, const projection::ProjectionOptions& options,
                                      const std::array<double, 2>* start, bool convex_checked,
                                      projection::FaceClosestPoint& out) const {
  const Vec3 relative = slave - origin;
  if (!(lambda_floor > 0.0) || !relative.allFinite() || !(convex_checked || convex_for(relative)))
    return false;
  bool found = false;
  if (const auto* tri6 = std::get_if<geometry::QuadraticTriangle>(&face)) {
    found = certified(*this, *tri6, relative, options, start, out);
  } else if (const auto* patch = std::get_if<const geometry::GregoryPatch*>(&face)) {
    found = certified(*this, **patch, relative, options, start, out);
  } else if (const auto* quad8 = std::get_if<geometry::SerendipityQuad>(&face)) {
    found = certified(*this, *quad8, relative, options, start, out);
  }
  if (found) out.point += origin;
  return found;
}

}  // namespace contactnn::contact
