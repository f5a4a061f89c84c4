#include "projection/closest_point_on_quadratic_face.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "geometry/segment_checks.hpp"

namespace contactnn::projection {

namespace {

using geometry::QuadraticTriangle;
using geometry::SerendipityQuad;
using geometry::SurfacePoint;

bool finite(const Vec3& x) { return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]); }

template <std::size_t N>
bool all_finite(const std::array<Vec3, N>& nodes) {
  return std::all_of(nodes.begin(), nodes.end(), [](const Vec3& x) { return finite(x); });
}

/// An edge as the quadratic curve C(t) = c0 + c1 t + c2 t^2 through X (t = 0), M (t = 1/2) and Y (t = 1).
struct QuadraticCurve {
  Vec3 c0, c1, c2;
  static QuadraticCurve through(const Vec3& x, const Vec3& m, const Vec3& y) {
    return {x, Vec3(-3.0 * x + 4.0 * m - y), Vec3(2.0 * x - 4.0 * m + 2.0 * y)};
  }
  [[nodiscard]] Vec3 at(double t) const { return c0 + t * (c1 + t * c2); }
};

/// The t in [0, 1] of the point of `curve` nearest `slave`: f = |C - S|^2 / 2 at 33 samples (ends included),
/// every sampled local minimum refined by 1-D Newton (f' = C'.(C - S), f'' = C'.C' + C''.(C - S)) kept in its
/// neighbours' bracket: the Newton step where f'' > 0, else a quarter of the bracket downhill, halved until f
/// does not increase (a Newton step below 1e-6 is taken whole: f's changes are rounding there); stops when a
/// step no longer moves t. f' is a cubic: at most two minima, each in the
/// bracket of a sampled local minimum once the samples resolve the curve (33 samples on a curve whose
/// mid-side node is off its chord by less than the chord's length).
double nearest_parameter(const QuadraticCurve& curve, const Vec3& slave) {
  constexpr int kSamples = 33;
  const auto f = [&](double t) { return 0.5 * (curve.at(t) - slave).squaredNorm(); };
  std::array<double, kSamples> ts{}, fs{};
  for (int i = 0; i < kSamples; ++i) {
    const auto u = static_cast<std::size_t>(i);
    ts[u] = i == kSamples - 1 ? 1.0 : static_cast<double>(i) / (kSamples - 1);
    fs[u] = f(ts[u]);
  }
  double best_t = 0.0, best_f = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kSamples; ++i) {
    const auto u = static_cast<std::size_t>(i);
    if ((i > 0 && fs[u] > fs[u - 1]) || (i < kSamples - 1 && fs[u] > fs[u + 1])) continue;
    const double a = ts[static_cast<std::size_t>(std::max(i - 1, 0))];
    const double b = ts[static_cast<std::size_t>(std::min(i + 1, kSamples - 1))];
    double t = ts[u], ft = fs[u];
    for (int iteration = 0; iteration < 60; ++iteration) {
      const Vec3 r = curve.at(t) - slave;
      const Vec3 d1 = curve.c1 + (2.0 * t) * curve.c2;
      const double f1 = d1.dot(r), f2 = d1.dot(d1) + 2.0 * curve.c2.dot(r);
      if (f1 == 0.0 || !std::isfinite(f1) || !std::isfinite(f2)) break;
      double step = f2 > 0.0 ? -f1 / f2 : (f1 > 0.0 ? -0.25 : 0.25) * (b - a);
      if (f2 > 0.0 && std::abs(step) < 1e-6) {
        // Converging: f's changes are below its rounding here, and only the full Newton step reaches the
        // minimum to rounding in t (as the reference projection skips its line search for tiny steps).
        const double next = std::clamp(t + step, a, b);
        if (next == t) break;
        t = next;
        ft = f(t);
        if (std::abs(step) <= 4.0 * std::numeric_limits<double>::epsilon()) break;
        continue;
      }
      bool moved = false;
      for (int halving = 0; halving < 60; ++halving) {
        const double next = std::clamp(t + step, a, b);
        if (next == t) break;
        const double f_next = f(next);
        if (f_next <= ft) {
          moved = std::abs(next - t) > 4.0 * std::numeric_limits<double>::epsilon();
          t = next;
          ft = f_next;
          break;
        }
        step *= 0.5;
      }
      if (!moved) break;
    }
    if (ft < best_f) {
      best_f = ft;
      best_t = t;
    }
  }
  return best_t;
}

/// The nearest local minimum of |S - P|^2 that damped Newton reaches from `starts` inside the face.
struct Interior {
  bool found = false;
  bool invalid = false;
  std::array<double, 2> param{0.0, 0.0};
  double sqr_distance = std::numeric_limits<double>::infinity();
  int iterations = 0;
};

/// Damped Newton on Eqs 7-8 from each start (the header's step 1); `keep(p)` moves an iterate back onto the
/// closed face (so a run cannot leave for a stationary point of the surface's extension beyond an edge: one
/// pinned to the boundary stops, and the edges' own search covers it), `width` is the domain's, `inside(p)`
/// says whether a converged point lies within the domain's margin.
template <class Face, class Keep, class Inside>
Interior interior_minimum(const Face& face, const Vec3& slave,
                          const std::vector<std::array<double, 2>>& starts, const Keep& keep, double width,
                          const Inside& inside, const ProjectionOptions& options) {
  Interior best;
  const double length = face.characteristic_length();
  const double l2 = length * length;
  const double det_floor = 1e-24 * l2 * l2;  // |P_s x P_t|^2 ~ L^4: a singular Gram matrix at this level
  const double residual_floor = options.tol_residual * l2;
  const double max_step = 0.5 * width;
  for (const auto& start : starts) {
    std::array<double, 2> p = start;
    bool converged = false;
    int it = 1;
    for (; it <= options.max_iterations; ++it) {
      const SurfacePoint sp = face.evaluate(p[0], p[1]);
      if (!sp.position.allFinite() || !sp.d_s.allFinite() || !sp.d_t.allFinite()) {
        best.invalid = true;
        break;
      }
      const Vec3 d = slave - sp.position;
      const double r0 = sp.d_s.dot(d), r1 = sp.d_t.dot(d);
      if (std::abs(r0) <= residual_floor && std::abs(r1) <= residual_floor) {
        converged = true;
        break;
      }
      const double g00 = sp.d_s.dot(sp.d_s), g01 = sp.d_s.dot(sp.d_t), g11 = sp.d_t.dot(sp.d_t);
      const double h00 = g00 - sp.d_ss.dot(d), h01 = g01 - sp.d_st.dot(d), h11 = g11 - sp.d_tt.dot(d);
      // The exact Newton step where the Hessian is positive definite, else Gauss-Newton (downhill).
      double a = h00, b = h01, c = h11;
      if (!(h00 > 0.0 && h00 * h11 - h01 * h01 > det_floor)) {
        a = g00;
        b = g01;
        c = g11;
      }
      const double det = a * c - b * b;
      if (!(std::abs(det) > det_floor)) break;  // no direction: this start gives nothing
      std::array<double, 2> step = {(c * r0 - b * r1) / det, (a * r1 - b * r0) / det};
      const double step_length = std::max(std::abs(step[0]), std::abs(step[1]));
      if (!std::isfinite(step_length)) break;
      if (step_length > max_step) {
        step[0] *= max_step / step_length;
        step[1] *= max_step / step_length;
      }
      const double f0 = 0.5 * d.squaredNorm();
      const double slope = -(r0 * step[0] + r1 * step[1]);
      double alpha = 1.0;
      std::array<double, 2> next{};
      for (int halvings = 0;; ++halvings) {
        next = keep(std::array<double, 2>{p[0] + alpha * step[0], p[1] + alpha * step[1]});
        if (step_length * alpha < 1e-6 || halvings >= 30) break;
        if (0.5 * (slave - face.position(next[0], next[1])).squaredNorm() <= f0 + 1e-4 * alpha * slope) break;
        alpha *= 0.5;
      }
      const double moved = std::max(std::abs(next[0] - p[0]), std::abs(next[1] - p[1]));
      p = next;
      if (step_length <= options.tol_param) {
        converged = true;
        break;
      }
      if (moved <= options.tol_param)
        break;  // pinned against the boundary: no interior stationary point here
    }
    if (!converged || !inside(p)) continue;
    // A local minimum only: the exact Hessian positive semi-definite to rounding (not a saddle or a maximum).
    const SurfacePoint sp = face.evaluate(p[0], p[1]);
    const Vec3 d = slave - sp.position;
    const double h00 = sp.d_s.dot(sp.d_s) - sp.d_ss.dot(d), h01 = sp.d_s.dot(sp.d_t) - sp.d_st.dot(d),
                 h11 = sp.d_t.dot(sp.d_t) - sp.d_tt.dot(d);
    const double tol = 1e-10 * l2;
    if (!(h00 >= -tol && h11 >= -tol && h00 * h11 - h01 * h01 >= -tol * tol)) continue;
    const double d2 = d.squaredNorm();
    if (d2 < best.sqr_distance) {  // ties keep the earlier start
      best.found = true;
      best.param = p;
      best.sqr_distance = d2;
      best.iterations = std::min(it, options.max_iterations);
    }
  }
  return best;
}

/// The Newton starts of step 1: every local minimum of |S - P|^2 sampled on the grid of 3 x starts_per_axis
/// points per parameter over the closed face (a triangle: the lattice points of the triangle), a sample being
/// a local minimum when no neighbour of its 8 on the face is lower. A sampled minimum lies in (or, next to
/// the boundary, beside) the basin of each minimum wider than the grid's spacing, wherever the minimum lies;
/// a grid of fixed starts may send every run to a stationary point outside the face on a strongly curved
/// face.
template <class Face>
std::vector<std::array<double, 2>> sampled_minima(const Face& face, const Vec3& slave, int starts_per_axis,
                                                  bool triangle) {
  const int m = 3 * std::max(starts_per_axis, 1);  // samples per axis, ends included
  const double lo = triangle ? 0.0 : -1.0, width = triangle ? 1.0 : 2.0;
  const auto on_face = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < m && j < m && (!triangle || i + j < m);
  };
  const auto at = [&](int i) { return i == m - 1 ? lo + width : lo + width * i / (m - 1); };
  std::vector<double> f(static_cast<std::size_t>(m * m), std::numeric_limits<double>::infinity());
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      if (on_face(i, j))
        f[static_cast<std::size_t>(i * m + j)] = (slave - face.position(at(i), at(j))).squaredNorm();
    }
  }
  std::vector<std::array<double, 2>> starts;
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      if (!on_face(i, j)) continue;
      const double here = f[static_cast<std::size_t>(i * m + j)];
      bool minimum = true;
      for (int di = -1; di <= 1 && minimum; ++di) {
        for (int dj = -1; dj <= 1 && minimum; ++dj) {
          if (on_face(i + di, j + dj) && f[static_cast<std::size_t>((i + di) * m + j + dj)] < here)
            minimum = false;
        }
      }
      if (minimum) starts.push_back({at(i), at(j)});
    }
  }
  return starts;
}

/// The point of the closed triangle r, s >= 0, r + s <= 1 nearest (r, s) in the parameter plane.
std::array<double, 2> onto_triangle(const std::array<double, 2>& p) {
  double r = p[0], s = p[1];
  if (r + s > 1.0) {  // beyond the hypotenuse: its nearest point, then clamped to its ends
    const double shift = 0.5 * (r + s - 1.0);
    r -= shift;
    s -= shift;
  }
  r = std::clamp(r, 0.0, 1.0);
  s = std::clamp(s, 0.0, 1.0);
  if (r + s > 1.0) {  // rounding: keep the larger, pull the other in
    if (r >= s) {
      s = 1.0 - r;
    } else {
      r = 1.0 - s;
    }
  }
  return {r, s};
}

/// Point, normal and distance of the face at `out.param`; status ok unless a value is not finite.
template <class Face>
void finish(const Face& face, const Vec3& slave, FaceClosestPoint& out) {
  report_at(face.evaluate(out.param[0], out.param[1]), slave, out);
}

/// The point of edge `edge` (from corner `edge` through its mid-side node, corners `corners` first) of `face`
/// nearest to `slave`, its edge parameter mapped to the face's by `face_param`.
template <class Face>
EdgePoint nearest_on_edge(const Face& face, std::size_t corners, int edge, const Vec3& slave,
                          std::array<double, 2> (*face_param)(int, double)) {
  const auto& x = face.nodes();
  const auto e = static_cast<std::size_t>(edge);
  const double t =
      nearest_parameter(QuadraticCurve::through(x[e], x[corners + e], x[(e + 1) % corners]), slave);
  EdgePoint out;
  out.param = face_param(edge, t);
  out.distance = (slave - face.position(out.param[0], out.param[1])).norm();
  return out;
}

}  // namespace

EdgePoint closest_point_on_quadratic_edge(const SerendipityQuad& face, int edge, const Vec3& slave) {
  return nearest_on_edge(face, 4, edge, slave, quad_edge_param);
}

EdgePoint closest_point_on_quadratic_edge(const QuadraticTriangle& face, int edge, const Vec3& slave) {
  return nearest_on_edge(face, 3, edge, slave, triangle_edge_param);
}

namespace {

/// The starts of the interior's Newton runs: the caller's warm start, or the minima of a sampled grid.
template <class Face>
std::vector<std::array<double, 2>> interior_starts(const Face& face, const Vec3& slave,
                                                   const ProjectionOptions& options, bool triangle) {
  return options.warm_start ? std::vector<std::array<double, 2>>{options.start}
                            : sampled_minima(face, slave, options.starts_per_axis, triangle);
}

/// Steps 2-3: the interior's minimum (`interior`, moved onto the face by `keep`; null: none) against the
/// closest point of each of the face's `edges` quadratic edges, ends included; the nearest wins (strictly
/// nearer replaces: ties keep the earlier). Writes out.param (and out.iterations from the interior); returns
/// the distance, infinite when there is none. `edges_farther`: the edges are known to lose to the interior.
template <class Face, class Keep>
double nearest_of_interior_and_edges(const Face& face, const Vec3& slave,
                                     const std::array<double, 2>* interior, int iterations, const Keep& keep,
                                     int edges, FaceClosestPoint& out, bool* from_interior,
                                     bool edges_farther) {
  double best = std::numeric_limits<double>::infinity();
  bool interior_wins = false;
  if (interior != nullptr) {
    out.param = keep(*interior);
    out.iterations = iterations;
    // Its distance only decides against the edges: where they are farther (the caller's proof), the report's
    // own evaluation gives it (a non-finite one makes the status invalid there).
    best = edges_farther ? 0.0 : (slave - face.position(out.param[0], out.param[1])).norm();
    interior_wins = true;
  }
  for (int edge = 0; edge < (interior != nullptr && edges_farther ? 0 : edges); ++edge) {
    const EdgePoint e = closest_point_on_quadratic_edge(face, edge, slave);
    if (e.distance < best) {
      best = e.distance;
      out.param = e.param;
      interior_wins = false;
    }
  }
  if (from_interior != nullptr) *from_interior = interior_wins;
  return best;
}

std::array<double, 2> onto_square(const std::array<double, 2>& p) {
  return std::array<double, 2>{std::clamp(p[0], -1.0, 1.0), std::clamp(p[1], -1.0, 1.0)};
}

/// out's location on the face (its domain's), then its point, normal and distance there (finish).
void locate_and_finish(const SerendipityQuad& face, const Vec3& slave, FaceClosestPoint& out) {
  locate_on_quad({-1.0, 1.0}, out);
  finish(face, slave, out);
}
void locate_and_finish(const QuadraticTriangle& face, const Vec3& slave, FaceClosestPoint& out) {
  locate_on_triangle(out);
  finish(face, slave, out);
}

}  // namespace

template <class Face>
FaceClosestPoint nearest_of_interior_and_quadratic_edges(const Face& face, const Vec3& slave,
                                                         const std::array<double, 2>* interior,
                                                         int iterations, bool* from_interior,
                                                         bool edges_farther) {
  FaceClosestPoint out;
  constexpr bool kQuad = std::is_same_v<Face, SerendipityQuad>;
  const auto onto = [](const std::array<double, 2>& p) { return kQuad ? onto_square(p) : onto_triangle(p); };
  if (!std::isfinite(nearest_of_interior_and_edges(face, slave, interior, iterations, onto,
                                                   kQuad ? kQuadEdges : kTriangleEdges, out, from_interior,
                                                   edges_farther))) {
    return out;  // invalid
  }
  locate_and_finish(face, slave, out);
  return out;
}

template <class Face>
FaceClosestPoint quadratic_face_point(const Face& face, const Vec3& slave, const std::array<double, 2>& param,
                                      int iterations) {
  FaceClosestPoint out;
  out.param = param;
  out.iterations = iterations;
  locate_and_finish(face, slave, out);
  return out;
}

#define CONTACTNN_INSTANTIATE(Face)                                              \
  template FaceClosestPoint nearest_of_interior_and_quadratic_edges<Face>(       \
      const Face&, const Vec3&, const std::array<double, 2>*, int, bool*, bool); \
  template FaceClosestPoint quadratic_face_point<Face>(const Face&, const Vec3&, \
                                                       const std::array<double, 2>&, int);
CONTACTNN_INSTANTIATE(SerendipityQuad)
CONTACTNN_INSTANTIATE(QuadraticTriangle)
#undef CONTACTNN_INSTANTIATE

namespace {

FaceClosestPoint closest_point_on_serendipity_quad_local(const SerendipityQuad& face, const Vec3& slave,
                                                         const ProjectionOptions& options) {
  FaceClosestPoint out;
  if (!finite(slave) || !all_finite(face.nodes())) return out;  // invalid
  if (geometry::is_degenerate_segment(face.corners())) {
    out.status = Status::kDegenerate;
    return out;
  }
  // 1. The interior.
  const std::vector<std::array<double, 2>> starts = interior_starts(face, slave, options, false);
  const double margin = options.domain_margin;
  const auto inside = [&](const std::array<double, 2>& p) {
    return p[0] >= -1.0 - margin && p[0] <= 1.0 + margin && p[1] >= -1.0 - margin && p[1] <= 1.0 + margin;
  };
  const Interior interior = interior_minimum(face, slave, starts, onto_square, 2.0, inside, options);
  if (interior.invalid) return out;
  // 2. The edges, ends included; 3. the nearest wins.
  return nearest_of_interior_and_quadratic_edges(face, slave, interior.found ? &interior.param : nullptr,
                                                 interior.iterations);
}

FaceClosestPoint closest_point_on_quadratic_triangle_local(const QuadraticTriangle& face, const Vec3& slave,
                                                           const ProjectionOptions& options) {
  FaceClosestPoint out;
  if (!finite(slave) || !all_finite(face.nodes())) return out;  // invalid
  const auto x = face.corners();
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0];
  const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (x[2] - x[1]).squaredNorm()});
  if (!(e1.cross(e2).norm() > 1e-12 * longest2)) {
    out.status = Status::kDegenerate;
    return out;
  }
  // 1. The interior.
  const std::vector<std::array<double, 2>> starts = interior_starts(face, slave, options, true);
  const double margin = options.domain_margin;
  const auto inside = [&](const std::array<double, 2>& p) {
    return p[0] >= -margin && p[1] >= -margin && p[0] + p[1] <= 1.0 + margin;
  };
  const Interior interior = interior_minimum(face, slave, starts, onto_triangle, 1.0, inside, options);
  if (interior.invalid) return out;
  // 2. The edges; 3. the nearest wins.
  return nearest_of_interior_and_quadratic_edges(face, slave, interior.found ? &interior.param : nullptr,
                                                 interior.iterations);
}

/// The face and the slave moved so that the face's first node is the origin: every value then carries the
/// rounding of the face's own size, not of its distance from the world's origin (a small face far from it
/// would otherwise see Newton's steps and residuals stall above their tolerances).
template <class Face>
Face shifted(const Face& face, const Vec3& origin) {
  auto nodes = face.nodes();
  for (Vec3& x : nodes) x -= origin;
  return Face(nodes);
}

/// `local` (a closest point about the world's origin) on the face shifted to its first node, the answer moved
/// back; about the world's origin itself where the face or the slave is not finite, or the face starts there.
template <class Face>
FaceClosestPoint about_first_node(const Face& face, const Vec3& slave, const ProjectionOptions& options,
                                  FaceClosestPoint (*local)(const Face&, const Vec3&,
                                                            const ProjectionOptions&)) {
  const Vec3 origin = face.nodes()[0];
  if (!finite(slave) || !all_finite(face.nodes()) || origin.isZero(0.0)) return local(face, slave, options);
  FaceClosestPoint answer = local(shifted(face, origin), slave - origin, options);
  answer.point += origin;
  return answer;
}

}  // namespace

FaceClosestPoint closest_point_on_serendipity_quad(const SerendipityQuad& face, const Vec3& slave,
                                                   const ProjectionOptions& options) {
  return about_first_node(face, slave, options, closest_point_on_serendipity_quad_local);
}

FaceClosestPoint closest_point_on_quadratic_triangle(const QuadraticTriangle& face, const Vec3& slave,
                                                     const ProjectionOptions& options) {
  return about_first_node(face, slave, options, closest_point_on_quadratic_triangle_local);
}

std::array<double, 2> quad_edge_param(int edge, double t) {
  switch (edge) {
    case 0: return {-1.0 + 2.0 * t, -1.0};
    case 1: return {1.0, -1.0 + 2.0 * t};
    case 2: return {1.0 - 2.0 * t, 1.0};
    default: return {-1.0, 1.0 - 2.0 * t};
  }
}
std::array<double, 2> triangle_edge_param(int edge, double t) {
  switch (edge) {
    case 0: return {t, 0.0};
    case 1: return {1.0 - t, t};
    default: return {0.0, 1.0 - t};
  }
}

}  // namespace contactnn::projection
