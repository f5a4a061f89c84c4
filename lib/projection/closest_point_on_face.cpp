#include "projection/closest_point_on_face.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::projection {

namespace {

bool finite(const Vec3& x) { return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]); }

/// Half the squared distance along the edge and its first two derivatives in t:
/// f = |C - S|^2 / 2, f' = C'.(C - S), f'' = C'.C' + C''.(C - S).
template <class SurfaceT>
struct EdgeFunction {
  const SurfaceT& surface;
  const Vec3& slave;
  int edge;
  ParamDomain d;

  [[nodiscard]] double value(double t) const {
    const auto p = domain_edge_param(edge, t, d);
    return 0.5 * (surface.position(p[0], p[1]) - slave).squaredNorm();
  }
  void derivatives(double t, double& f1, double& f2) const {
    const auto p = domain_edge_param(edge, t, d);
    const geometry::SurfacePoint sp = surface.evaluate(p[0], p[1]);
    const bool along_s = edge == 0 || edge == 2;
    const Vec3& c1 = along_s ? sp.d_s : sp.d_t;
    const Vec3& c2 = along_s ? sp.d_ss : sp.d_tt;
    const Vec3 r = sp.position - slave;
    f1 = c1.dot(r);
    f2 = c1.dot(c1) + c2.dot(r);
  }
};

/// Safeguarded 1-D Newton for a local minimum of f in [a, b] from t: the Newton step where f'' > 0, else a
/// quarter of the bracket downhill; halved until f does not increase. Stops when the step is below rounding.
template <class SurfaceT>
double refine_on_edge(const EdgeFunction<SurfaceT>& fn, double t, double a, double b, double& f) {
  const double width = b - a;
  f = fn.value(t);
  for (int iteration = 0; iteration < 60; ++iteration) {
    double f1 = 0.0, f2 = 0.0;
    fn.derivatives(t, f1, f2);
    if (!(std::isfinite(f1) && std::isfinite(f2))) break;
    double step = f2 > 0.0 ? -f1 / f2 : (f1 > 0.0 ? -0.25 * width : 0.25 * width);
    if (f1 == 0.0) break;
    if (f2 > 0.0 && std::abs(step) < 1e-6 * width) {
      // Near the minimum f is flat to rounding (a descent test stalls about sqrt(eps) off): Newton on f' = 0,
      // kept while |f'| decreases, converges to full precision.
      const double next = std::clamp(t + step, a, b);
      if (next == t) break;
      double g1 = 0.0, g2 = 0.0;
      fn.derivatives(next, g1, g2);
      if (!(std::abs(g1) < std::abs(f1))) break;
      t = next;
      f = fn.value(t);
      continue;
    }
    bool moved = false;
    for (int halving = 0; halving < 60; ++halving) {
      const double next = std::clamp(t + step, a, b);
      if (next == t) break;
      const double f_next = fn.value(next);
      if (f_next <= f) {
        moved =
            std::abs(next - t) > 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
        t = next;
        f = f_next;
        break;
      }
      step *= 0.5;
    }
    if (!moved) break;
  }
  return t;
}

}  // namespace

template <geometry::Surface SurfaceT>
EdgePoint closest_point_on_edge(const SurfaceT& surface, int edge, const Vec3& slave) {
  const ParamDomain d = param_domain(SurfaceT::kKind);
  EdgePoint best;
  if constexpr (SurfaceT::kKind == SurfaceKind::kBilinear) {
    // A bilinear facet's edges are straight and linear in the parameter: the clamped projection is exact.
    const auto p0 = domain_edge_param(edge, d.lo, d);
    const auto p1 = domain_edge_param(edge, d.hi, d);
    const Vec3 x0 = surface.position(p0[0], p0[1]);
    const Vec3 chord = surface.position(p1[0], p1[1]) - x0;
    const double length2 = chord.squaredNorm();
    const double tau = length2 > 0.0 ? std::clamp((slave - x0).dot(chord) / length2, 0.0, 1.0) : 0.0;
    // The ends exactly (vertices): lo + 1 x width may round away from hi.
    const double t = tau == 1.0 ? d.hi : d.lo + tau * (d.hi - d.lo);
    best.param = domain_edge_param(edge, t, d);
  } else {
    // A curved edge: 33 samples, every sampled local minimum refined in its neighbours' bracket.
    constexpr int kSamples = 33;
    const EdgeFunction<SurfaceT> fn{surface, slave, edge, d};
    std::array<double, kSamples> ts{}, fs{};
    for (int i = 0; i < kSamples; ++i) {
      ts[static_cast<std::size_t>(i)] =
          i == kSamples - 1 ? d.hi : d.lo + (d.hi - d.lo) * static_cast<double>(i) / (kSamples - 1);
      fs[static_cast<std::size_t>(i)] = fn.value(ts[static_cast<std::size_t>(i)]);
    }
    double best_f = std::numeric_limits<double>::infinity();
    double best_t = d.lo;
    for (int i = 0; i < kSamples; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const bool left_ok = i == 0 || fs[u] <= fs[u - 1];
      const bool right_ok = i == kSamples - 1 || fs[u] <= fs[u + 1];
      if (!(left_ok && right_ok)) continue;
      const double a = ts[static_cast<std::size_t>(std::max(i - 1, 0))];
      const double b = ts[static_cast<std::size_t>(std::min(i + 1, kSamples - 1))];
      double f = 0.0;
      const double t = refine_on_edge(fn, ts[u], a, b, f);
      if (f < best_f) {
        best_f = f;
        best_t = t;
      }
    }
    best.param = domain_edge_param(edge, best_t, d);
  }
  best.distance = (slave - surface.position(best.param[0], best.param[1])).norm();
  return best;
}

template <geometry::Surface SurfaceT>
FaceClosestPoint closest_point_on_face(const SurfaceT& surface, const Vec3& slave,
                                       const ProjectionOptions& options) {
  FaceClosestPoint out;
  if (!finite(slave)) return out;  // invalid
  // Relative to the face's first node: the projection's residual tolerance is relative to the face's size,
  // and world coordinates far from the origin round the residual above it (a face of size 0.03 at |x| = 70
  // missed most of its interior points).
  const Vec3& origin = surface.nodes()[0];
  if (finite(origin) && !origin.isZero()) {
    std::array<Vec3, 4> nodes = surface.nodes();
    for (Vec3& x : nodes) x -= origin;
    FaceClosestPoint shifted;
    if constexpr (SurfaceT::kKind == SurfaceKind::kGregory) {
      shifted =
          closest_point_on_face(geometry::GregoryPatch(nodes, surface.normals()), slave - origin, options);
    } else {
      shifted = closest_point_on_face(geometry::BilinearPatch(nodes), slave - origin, options);
    }
    if (shifted.status == Status::kOk) shifted.point += origin;
    return shifted;
  }
  if (!options.face_checked) {
    if (!std::isfinite(surface.characteristic_length())) return out;  // invalid
    if (geometry::is_degenerate_segment(surface.nodes())) {
      out.status = Status::kDegenerate;
      return out;
    }
  }
  // 1. The interior stationary point (the reference projection). A sound face may still have none: the
  //    stationary point of a slave beside a planar quad can lie beyond the fold of its bilinear map, where
  //    the projection reports degenerate; the boundary then holds the answer.
  const ProjectionResult interior = project_point(surface, slave, options);
  if (interior.status == Status::kInvalid) return out;
  return nearest_of_interior_and_edges(
      surface, slave, interior.status == Status::kOk ? &interior.param : nullptr, interior.iterations);
}

template <geometry::Surface SurfaceT>
FaceClosestPoint nearest_of_interior_and_edges(const SurfaceT& surface, const Vec3& slave,
                                               const std::array<double, 2>* interior, int iterations,
                                               bool* from_interior, bool edges_farther) {
  const ParamDomain d = param_domain(SurfaceT::kKind);
  FaceClosestPoint out;
  out.iterations = iterations;
  double best = std::numeric_limits<double>::infinity();
  bool interior_wins = false;
  if (interior != nullptr) {
    out.param = {std::clamp((*interior)[0], d.lo, d.hi), std::clamp((*interior)[1], d.lo, d.hi)};
    // Its distance only decides against the edges: where they are farther (the caller's proof), the report's
    // own evaluation below gives it (a non-finite one makes the status invalid there).
    best = edges_farther ? 0.0 : (slave - surface.position(out.param[0], out.param[1])).norm();
    interior_wins = true;
  }
  // 2. The edges, ends included; 3. the nearest wins (strictly nearer replaces: ties keep the earlier).
  for (int edge = 0; edge < (interior != nullptr && edges_farther ? 0 : kQuadEdges); ++edge) {
    const EdgePoint e = closest_point_on_edge(surface, edge, slave);
    if (e.distance < best) {
      best = e.distance;
      out.param = e.param;
      interior_wins = false;
    }
  }
  if (from_interior != nullptr) *from_interior = interior_wins;
  if (!std::isfinite(best)) return out;  // invalid: the surface has a non-finite value

  locate_on_quad(d, out);
  report_at(surface.evaluate(out.param[0], out.param[1]), slave, out);
  return out;
}

void report_at(const geometry::SurfacePoint& at, const Vec3& slave, FaceClosestPoint& out) {
  out.point = at.position;
  out.distance = (slave - at.position).norm();
  const Vec3 n = at.d_s.cross(at.d_t);
  const double length = n.norm();
  out.normal = length > 0.0 && std::isfinite(length) ? Vec3(n / length) : Vec3(Vec3::Zero());
  out.status = std::isfinite(out.distance) ? Status::kOk : Status::kInvalid;
}

void locate_on_quad(ParamDomain d, FaceClosestPoint& out) {
  const double tol = kOnBoundaryTolerance * (d.hi - d.lo);
  int on_lo[2] = {0, 0}, on_hi[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const double x = out.param[static_cast<std::size_t>(k)];
    if (x - d.lo <= tol) {
      on_lo[k] = 1;
    } else if (d.hi - x <= tol) {
      on_hi[k] = 1;
    }
  }
  const int bounds = on_lo[0] + on_hi[0] + on_lo[1] + on_hi[1];
  if (bounds == 2) {
    out.location = Location::kVertex;
    out.feature = on_lo[1] ? (on_lo[0] ? 0 : 1) : (on_hi[0] ? 2 : 3);
  } else if (bounds == 1) {
    out.location = Location::kEdge;
    out.feature = on_lo[1] ? 0 : on_hi[0] ? 1 : on_hi[1] ? 2 : 3;
  } else {
    out.location = Location::kFace;
    out.feature = -1;
  }
}

void locate_on_triangle(FaceClosestPoint& out) {
  const double r = out.param[0], s = out.param[1];
  const double tol = kOnBoundaryTolerance;
  const bool on[3] = {s <= tol, 1.0 - r - s <= tol, r <= tol};  // edges A->B, B->C, C->A
  const int bounds = on[0] + on[1] + on[2];
  if (bounds >= 2) {
    out.location = Location::kVertex;
    out.feature = on[2] && on[0] ? 0 : on[0] && on[1] ? 1 : 2;
  } else if (bounds == 1) {
    out.location = Location::kEdge;
    out.feature = on[0] ? 0 : on[1] ? 1 : 2;
  } else {
    out.location = Location::kFace;
    out.feature = -1;
  }
}

PreparedTriangle prepare_triangle(const std::array<Vec3, 3>& nodes) {
  PreparedTriangle t;
  t.nodes = nodes;
  if (!finite(nodes[0]) || !finite(nodes[1]) || !finite(nodes[2])) return t;  // invalid
  for (std::size_t k = 0; k < 3; ++k) t.chords[k] = nodes[(k + 1) % 3] - nodes[k];
  const Vec3& e1 = t.chords[0];
  const Vec3 e2 = nodes[2] - nodes[0];
  const Vec3 n = e1.cross(e2);
  const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), t.chords[1].squaredNorm()});
  if (!(n.norm() > 1e-12 * longest2)) {
    t.status = Status::kDegenerate;
    return t;
  }
  t.normal = n.normalized();
  t.g11 = e1.dot(e1);
  t.g12 = e1.dot(e2);
  t.g22 = e2.dot(e2);
  t.det = t.g11 * t.g22 - t.g12 * t.g12;
  t.status = Status::kOk;
  return t;
}

FaceClosestPoint closest_point_on_prepared_triangle(const PreparedTriangle& triangle, const Vec3& slave) {
  FaceClosestPoint out;
  closest_point_on_prepared_triangle(triangle, slave, out);
  return out;
}

void closest_point_on_prepared_triangle(const PreparedTriangle& triangle, const Vec3& slave,
                                        FaceClosestPoint& out) {
  if (triangle.status != Status::kOk || !finite(slave)) {
    out = FaceClosestPoint{};
    out.status = finite(slave) ? triangle.status : Status::kInvalid;
    return;
  }
  const std::array<Vec3, 3>& nodes = triangle.nodes;
  const Vec3& e1 = triangle.chords[0];
  const Vec3 e2 = nodes[2] - nodes[0];
  // The plane's foot point in (r, s): the Gram system of the two edges.
  const Vec3 d = slave - nodes[0];
  const double b1 = e1.dot(d), b2 = e2.dot(d);
  const double g11 = triangle.g11, g12 = triangle.g12, g22 = triangle.g22, det = triangle.det;
  double r = (g22 * b1 - g12 * b2) / det, s = (g11 * b2 - g12 * b1) / det;
  if (!(r >= 0.0 && s >= 0.0 && r + s <= 1.0)) {
    // Outside: the nearest of the clamped edge points (an edge's ends are the vertices).
    double best = std::numeric_limits<double>::infinity();
    for (int edge = 0; edge < 3; ++edge) {
      const Vec3& x0 = nodes[static_cast<std::size_t>(edge)];
      const Vec3& chord = triangle.chords[static_cast<std::size_t>(edge)];
      const double t = std::clamp((slave - x0).dot(chord) / chord.squaredNorm(), 0.0, 1.0);
      const double distance = (slave - (x0 + t * chord)).norm();
      if (distance < best) {
        best = distance;
        // (r, s) of x0 + t chord: A->B (t, 0), B->C (1 - t, t), C->A (0, 1 - t).
        r = edge == 0 ? t : edge == 1 ? 1.0 - t : 0.0;
        s = edge == 0 ? 0.0 : edge == 1 ? t : 1.0 - t;
      }
    }
  }
  out.param = {r, s};
  locate_on_triangle(out);
  out.point = nodes[0] + r * e1 + s * e2;
  out.normal = triangle.normal;
  out.distance = (slave - out.point).norm();
  out.status = std::isfinite(out.distance) ? Status::kOk : Status::kInvalid;
  out.iterations = 0;
  out.by_method = false;
}

FaceClosestPoint closest_point_on_triangle(const std::array<Vec3, 3>& nodes, const Vec3& slave) {
  if (!finite(slave)) return FaceClosestPoint{};  // invalid
  return closest_point_on_prepared_triangle(prepare_triangle(nodes), slave);
}

#define CONTACTNN_INSTANTIATE(SurfaceT)                                                   \
  template FaceClosestPoint closest_point_on_face<SurfaceT>(const SurfaceT&, const Vec3&, \
                                                            const ProjectionOptions&);    \
  template EdgePoint closest_point_on_edge<SurfaceT>(const SurfaceT&, int, const Vec3&);  \
  template FaceClosestPoint nearest_of_interior_and_edges<SurfaceT>(                      \
      const SurfaceT&, const Vec3&, const std::array<double, 2>*, int, bool*, bool);
CONTACTNN_INSTANTIATE(geometry::BilinearPatch)
CONTACTNN_INSTANTIATE(geometry::GregoryPatch)
#undef CONTACTNN_INSTANTIATE

}  // namespace contactnn::projection
