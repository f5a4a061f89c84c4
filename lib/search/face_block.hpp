// Internal to lib/search: FaceSearch's block kernels (face_search.hpp), W queries at once as structures of
// arrays, every loop over the lanes. Included by face_kernels.cpp, compiled once per instruction-set variant
// (isa_dispatch.hpp), as the quad kernels are.
//
// A face is held in monomial form relative to S (S at the origin), in units of a power of two near its
// largest node offset from S (exact scaling: squares and products stay in the double range at any scale):
//   tri3   P = c0 + c1 r + c2 s
//   tri6   P = c0 + c1 r + c2 s + c3 r^2 + c4 r s + c5 s^2
//   quad8  P = c0 + c1 x + c2 y + c3 x^2 + c4 x y + c5 y^2 + c6 x^2 y + c7 x y^2      (x = xi, y = eta)
// from the nodes by the shape functions of geometry::QuadraticTriangle and geometry::SerendipityQuad (the
// same expressions; the tests compare both). Eqs 7-8 and their exact Jacobian follow from the monomials: a
// step costs the point, two tangents and three second derivatives.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "search/closed_form_block.hpp"
#include "search/face_search.hpp"
#include "search/isa_dispatch.hpp"
#include "search/surface_block.hpp"

namespace contactnn::search {
class FaceNetwork;
}

namespace contactnn::search::detail {

template <class Real>
using FaceBlockFn = void (*)(const FacePlan& plan, const Real* raw, const Results<Real>& out,
                             std::size_t first);

/// What a FaceSearch fixed at construction, and its kernels (one variant's).
struct FacePlan {
  KernelIsa isa = KernelIsa::kBaseline;
  FaceKind kind = FaceKind::kTri3;
  Method method;
  SearchOptions options;
  const FaceNetwork* network = nullptr;
  double box_margin = 0.0;  ///< hybrids: iterates stay in the domain enlarged by this (parameter units)
  double max_step = 0.0;    ///< hybrids: the longest step (max norm, parameter units)
  int block_size = 32;
  FaceBlockFn<float> block_f = nullptr, single_f = nullptr;
  FaceBlockFn<double> block_d = nullptr, single_d = nullptr;
};

/// kFace: 0 tri3, 1 tri6, 2 quad8 (FaceKind's values).
template <int kFace>
struct FaceTraits {
  static constexpr int kNodes = kFace == 0 ? 3 : (kFace == 1 ? 6 : 8);
  static constexpr int kStride = 3 * kNodes + 3;
  static constexpr bool kTriangle = kFace != 2;
  static constexpr bool kLinear = kFace == 0;
  /// The centre of the parameter domain: the centroid (1/3, 1/3) of a triangle, (0, 0) of the quad.
  static constexpr double kCentre = kTriangle ? 1.0 / 3.0 : 0.0;
};

/// a * b + c, rounded once in the variants with FMA and twice in baseline, whatever the compiler would
/// contract: for the expressions whose contraction GCC chose differently in the vectorised lane loops and in
/// the one-lane kernel (face_kernels_single.cpp), so that a query's bits do not depend on its place in a
/// batch.
CONTACTNN_SEARCH_INLINE double mul_add(double a, double b, double c) {
#if defined(__FMA__) || defined(__ARM_FEATURE_FMA)
  return __builtin_fma(a, b, c);
#else
  return a * b + c;
#endif
}

/// The face of W queries: monomial coefficients c[3 k + comp][l] relative to S in units unit[l]; corner
/// offsets from S in the same units; per-lane status (kOk, kInvalid, kDegenerate).
template <int kFace, int W>
struct FaceBlock {
  using T = FaceTraits<kFace>;
  static constexpr int kCorners = T::kTriangle ? 3 : 4;
  double c[3 * T::kNodes][W];
  double corner[3 * kCorners][W];
  double unit[W];
  double status[W];
  /// S's distance to the face's nearest node, in the block's units: a gap's cap.
  double nearest[W];

  /// From raw[k][l] (the rows of SPEC 9 nodes, then S). A lane with a non-finite value gets status kInvalid
  /// and a unit face one below S in its place (no NaN in the other lanes' vector operations).
  CONTACTNN_SEARCH_INLINE void build(const double (*raw)[W]) {
    constexpr int kN = T::kNodes;
    // Loops over the values outside and the lanes inside: each vectorises across the lanes (a lane loop
    // around the 21 to 27 values ran them as one scalar chain per lane: 38% of a tri6 query's time).
    double x[3 * kN][W], check[W], largest[W], inv[W], finite[W];
    for (int l = 0; l < W; ++l) check[l] = largest[l] = 0.0;
    for (int k = 0; k < T::kStride; ++k) {
#pragma omp simd
      for (int l = 0; l < W; ++l) check[l] += 0.0 * raw[k][l];
    }
    for (int k = 0; k < 3 * kN; ++k) {
      const int slave_row = 3 * kN + k % 3;
#pragma omp simd
      for (int l = 0; l < W; ++l) {
        const double d = raw[k][l] - raw[slave_row][l];
        x[k][l] = d;
        largest[l] = max_of(largest[l], std::fabs(d));
      }
    }
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      finite[l] = check[l] == 0.0 ? 1.0 : 0.0;
      // A power of two at most the largest offset: exact scaling, |x| in [1, 2) or 0 (every node on S).
      const double u = finite[l] != 0.0 ? power_of_two_below(largest[l]) : 1.0;
      inv[l] = 1.0 / u;
      unit[l] = u;
      status[l] = finite[l] != 0.0 ? kOk : kInvalid;
    }
    for (int k = 0; k < 3 * kN; ++k) {
      const double replacement = unit_face(k);
#pragma omp simd
      for (int l = 0; l < W; ++l) x[k][l] = finite[l] != 0.0 ? x[k][l] * inv[l] : replacement;
    }
    double near[W];
    for (int l = 0; l < W; ++l) near[l] = std::numeric_limits<double>::max();
    for (int i = 0; i < kN; ++i) {
#pragma omp simd
      for (int l = 0; l < W; ++l) {
        near[l] = min_of(near[l], x[3 * i][l] * x[3 * i][l] + x[3 * i + 1][l] * x[3 * i + 1][l] +
                                      x[3 * i + 2][l] * x[3 * i + 2][l]);
      }
    }
#pragma omp simd
    for (int l = 0; l < W; ++l) nearest[l] = std::sqrt(near[l]);
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      CONTACTNN_UNROLL
      for (int comp = 0; comp < 3; ++comp) {
        const auto n = [&](int i) { return x[3 * i + comp][l]; };
        if constexpr (kFace == 0) {
          c[comp][l] = n(0);
          c[3 + comp][l] = n(1) - n(0);
          c[6 + comp][l] = n(2) - n(0);
        } else if constexpr (kFace == 1) {
          const double a = n(0), b = n(1), cc = n(2), ab = n(3), bc = n(4), ca = n(5);
          c[comp][l] = a;
          c[3 + comp][l] = -3.0 * a - b + 4.0 * ab;
          c[6 + comp][l] = -3.0 * a - cc + 4.0 * ca;
          c[9 + comp][l] = 2.0 * a + 2.0 * b - 4.0 * ab;
          c[12 + comp][l] = 4.0 * (a - ab + bc - ca);
          c[15 + comp][l] = 2.0 * a + 2.0 * cc - 4.0 * ca;
        } else {
          const double a = n(0), b = n(1), cc = n(2), d = n(3), ab = n(4), bc = n(5), cd = n(6), da = n(7);
          const double corners = a + b + cc + d;
          c[comp][l] = -0.25 * corners + 0.5 * (ab + bc + cd + da);
          c[3 + comp][l] = 0.5 * (bc - da);
          c[6 + comp][l] = 0.5 * (cd - ab);
          c[9 + comp][l] = 0.25 * corners - 0.5 * (ab + cd);
          c[12 + comp][l] = 0.25 * (a - b + cc - d);
          c[15 + comp][l] = 0.25 * corners - 0.5 * (bc + da);
          c[18 + comp][l] = 0.25 * (-a - b + cc + d) - 0.5 * (cd - ab);
          c[21 + comp][l] = 0.25 * (-a + b + cc - d) - 0.5 * (bc - da);
        }
        CONTACTNN_UNROLL
        for (int i = 0; i < kCorners; ++i) corner[3 * i + comp][l] = n(i);
      }
      status[l] = status[l] == kOk && collapsed(l) ? kDegenerate : status[l];
    }
  }

  /// The corners' test of geometry::is_degenerate_segment (quads) and of the triangle closest point (a
  /// triangle without area), on squared lengths: coincident corners (shortest distance at most 1e-10 of the
  /// longest), no area, a corner of zero angle.
  CONTACTNN_SEARCH_INLINE bool collapsed(int l) const {
    double longest = 0.0, shortest = std::numeric_limits<double>::max();
    CONTACTNN_UNROLL
    for (int i = 0; i < kCorners; ++i) {
      CONTACTNN_UNROLL
      for (int j = i + 1; j < kCorners; ++j) {
        double d = 0.0;
        CONTACTNN_UNROLL
        for (int comp = 0; comp < 3; ++comp) {
          const double e = corner[3 * j + comp][l] - corner[3 * i + comp][l];
          d += e * e;
        }
        longest = max_of(longest, d);
        shortest = min_of(shortest, d);
      }
    }
    const auto cross_sq = [&](int p, int q, int r, int s) {  // |(P - Q) x (R - S)|^2
      double e[3], f[3];
      CONTACTNN_UNROLL
      for (int comp = 0; comp < 3; ++comp) {
        e[comp] = corner[3 * p + comp][l] - corner[3 * q + comp][l];
        f[comp] = corner[3 * r + comp][l] - corner[3 * s + comp][l];
      }
      const double x = e[1] * f[2] - e[2] * f[1], y = e[2] * f[0] - e[0] * f[2],
                   z = e[0] * f[1] - e[1] * f[0];
      return x * x + y * y + z * z;
    };
    const double l4 = longest * longest;
    bool bad = !(longest > 0.0) | !(shortest > 1e-20 * longest);
    if constexpr (T::kTriangle) {
      bad = bad | !(cross_sq(1, 0, 2, 0) > 1e-24 * l4);
    } else {
      bad = bad | !(cross_sq(2, 0, 3, 1) > 4e-24 * l4);
      CONTACTNN_UNROLL
      for (int i = 0; i < 4; ++i) {
        const int next = (i + 1) % 4, prev = (i + 3) % 4;
        double dot = 0.0;
        CONTACTNN_UNROLL
        for (int comp = 0; comp < 3; ++comp) {
          dot += (corner[3 * next + comp][l] - corner[3 * i + comp][l]) *
                 (corner[3 * prev + comp][l] - corner[3 * i + comp][l]);
        }
        bad = bad | ((dot > 0.0) & !(cross_sq(next, i, prev, i) > 1e-24 * l4));
      }
    }
    return bad;
  }

  /// A face below S (z = -1) in place of a lane with a non-finite input: value k of its node rows.
  static constexpr double unit_face(int k) {
    // tri: (0,0), (1,0), (0,1), mid-sides; quad: (-1,-1), (1,-1), (1,1), (-1,1), mid-sides.
    constexpr double kTri[18] = {0, 0, -1, 1, 0, -1, 0, 1, -1, 0.5, 0, -1, 0.5, 0.5, -1, 0, 0.5, -1};
    constexpr double kQuad[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                  0,  -1, -1, 1, 0,  -1, 0, 1, -1, -1, 0, -1};
    return T::kTriangle ? kTri[k] : kQuad[k];
  }

  /// P and its derivatives at (s, t), lane l (kSecond: with the second derivatives). Each multiply-add
  /// written out (mul_add): its rounding is the source's, not the compiler's choice of what to contract,
  /// which differed between the block's vectorised lanes and the one-lane kernel (issue 39).
  template <bool kSecond>
  CONTACTNN_SEARCH_INLINE void eval(int l, double s, double t, Eval& e) const {
    CONTACTNN_UNROLL
    for (int comp = 0; comp < 3; ++comp) {
      const auto k = [&](int i) { return c[3 * i + comp][l]; };
      if constexpr (kFace == 0) {
        e.p[comp] = mul_add(t, k(2), mul_add(s, k(1), k(0)));
        e.ps[comp] = k(1);
        e.pt[comp] = k(2);
        if constexpr (kSecond) e.pss[comp] = e.pst[comp] = e.ptt[comp] = 0.0;
      } else if constexpr (kFace == 1) {
        // k0 + s (k1 + s k3 + t k4) + t (k2 + t k5)
        const double a = mul_add(t, k(4), mul_add(s, k(3), k(1))), b = mul_add(t, k(5), k(2));
        e.p[comp] = mul_add(t, b, mul_add(s, a, k(0)));
        e.ps[comp] = mul_add(t, k(4), mul_add(2.0 * s, k(3), k(1)));
        e.pt[comp] = mul_add(2.0 * t, k(5), mul_add(s, k(4), k(2)));
        if constexpr (kSecond) {
          e.pss[comp] = 2.0 * k(3);
          e.pst[comp] = k(4);
          e.ptt[comp] = 2.0 * k(5);
        }
      } else {
        // k0 + s (k1 + s k3 + t k4 + s t k6) + t (k2 + t k5 + s t k7)
        const double st = s * t, st2 = 2.0 * st, s2 = 2.0 * s, t2 = 2.0 * t;
        const double a = mul_add(st, k(6), mul_add(t, k(4), mul_add(s, k(3), k(1))));
        const double b = mul_add(st, k(7), mul_add(t, k(5), k(2)));
        e.p[comp] = mul_add(t, b, mul_add(s, a, k(0)));
        e.ps[comp] = mul_add(t * t, k(7), mul_add(st2, k(6), mul_add(t, k(4), mul_add(s2, k(3), k(1)))));
        e.pt[comp] = mul_add(st2, k(7), mul_add(s * s, k(6), mul_add(t2, k(5), mul_add(s, k(4), k(2)))));
        if constexpr (kSecond) {
          e.pss[comp] = mul_add(t2, k(6), 2.0 * k(3));
          e.pst[comp] = mul_add(t2, k(7), mul_add(s2, k(6), k(4)));
          e.ptt[comp] = mul_add(s2, k(7), 2.0 * k(5));
        }
      }
    }
  }

  /// |P(s, t) - S|^2 in the block's units.
  CONTACTNN_SEARCH_INLINE double distance_sq(int l, double s, double t) const {
    Eval e;
    eval<false>(l, s, t, e);
    return e.p[0] * e.p[0] + e.p[1] * e.p[1] + e.p[2] * e.p[2];
  }
};

/// (s, t) inside the face's domain enlarged by m.
template <int kFace>
CONTACTNN_SEARCH_INLINE bool face_inside(double s, double t, double m) {
  if constexpr (FaceTraits<kFace>::kTriangle) {
    return (s >= -m) & (t >= -m) & (s + t <= 1.0 + m);
  } else {
    return (s >= -1.0 - m) & (s <= 1.0 + m) & (t >= -1.0 - m) & (t <= 1.0 + m);
  }
}

/// (s, t) held in the domain enlarged by m: the quad's box; the triangle's r, s >= -m, then r + s <= 1 + m by
/// moving both back along (1, 1) (and r, s >= -m again).
template <int kFace>
CONTACTNN_SEARCH_INLINE void face_clamp(double& s, double& t, double m) {
  if constexpr (FaceTraits<kFace>::kTriangle) {
    s = max_of(s, -m);
    t = max_of(t, -m);
    const double excess = max_of(s + t - (1.0 + m), 0.0);
    s = max_of(s - 0.5 * excess, -m);
    t = max_of(t - 0.5 * excess, -m);
  } else {
    s = min_of(max_of(s, -1.0 - m), 1.0 + m);
    t = min_of(max_of(t, -1.0 - m), 1.0 + m);
  }
}

/// Closed form of the corner facet: the corner triangle's projection (exact on tri3) or the quad's corners as
/// a bilinear facet (closed_form_lane, LocalSearch's closed form), for the lanes still ok. Status: ok (later
/// ok or outside by the domain); no_convergence where the quad's projected point lies beyond the fold of the
/// bilinear map (the estimate is still reported); degenerate where the facet has no plane.
template <int kFace, int W>
static void face_closed_form(const FaceBlock<kFace, W>& f, LaneState<W>& s) {
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    double u, v;
    bool fold = false, degenerate = false;
    if constexpr (FaceTraits<kFace>::kTriangle) {
      double e1[3], e2[3], q[3];
      CONTACTNN_UNROLL
      for (int comp = 0; comp < 3; ++comp) {
        e1[comp] = f.corner[3 + comp][l] - f.corner[comp][l];
        e2[comp] = f.corner[6 + comp][l] - f.corner[comp][l];
        q[comp] = -f.corner[comp][l];
      }
      const double g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
      const double g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
      const double g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
      const double b1 = e1[0] * q[0] + e1[1] * q[1] + e1[2] * q[2];
      const double b2 = e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2];
      const double det = g11 * g22 - g12 * g12;
      const double inv = 1.0 / det;
      u = (g22 * b1 - g12 * b2) * inv;
      v = (g11 * b2 - g12 * b1) * inv;
      degenerate = !(det > 1e-24 * g11 * g22);
    } else {
      double a0[3], a1[3], a2[3], a3[3];
      CONTACTNN_UNROLL
      for (int comp = 0; comp < 3; ++comp) {
        const double a = f.corner[comp][l], b = f.corner[3 + comp][l], cc = f.corner[6 + comp][l],
                     d = f.corner[9 + comp][l];
        a0[comp] = 0.25 * (a + b + cc + d);
        a1[comp] = 0.25 * (-a + b + cc - d);
        a2[comp] = 0.25 * (-a - b + cc + d);
        a3[comp] = 0.25 * (a - b + cc - d);
      }
      closed_form_lane(a0, a1, a2, a3, u, v, fold, degenerate);
    }
    const bool active = s.status[l] == kOk;
    const bool take = active & !degenerate & is_finite(u) & is_finite(v);
    s.u[l] = take ? u : s.u[l];
    s.v[l] = take ? v : s.v[l];
    s.status[l] = !active ? s.status[l] : (!take ? kDegenerate : (fold ? kNoConvergence : kOk));
  }
}

/// The undamped Newton step of Eqs 7-8 at (s, t) with the exact Jacobian: (ds, dt), whether det H = 0, and
/// |P - S|^2 there.
struct FaceStep {
  double ds, dt, dist_sq;
  bool singular;
};

template <int kFace, int W>
CONTACTNN_SEARCH_INLINE FaceStep face_newton_step(const FaceBlock<kFace, W>& f, int l, double s, double t,
                                                  bool gauss_newton_fallback) {
  Eval e;
  f.template eval<true>(l, s, t, e);
  const NewtonSystem q = newton_system<true>(e);
  double h00 = q.h00, h01 = q.h01, h11 = q.h11;
  double det = h00 * h11 - h01 * h01;
  if (gauss_newton_fallback) {
    // Where the exact Jacobian is not positive definite (a saddle or a maximum of |S - P| ahead), the
    // Gauss-Newton system, as the reference solver.
    const bool definite = (h00 > 0.0) & (det > 0.0);
    h00 = definite ? h00 : q.g00;
    h01 = definite ? h01 : q.g01;
    h11 = definite ? h11 : q.g11;
    det = definite ? det : h00 * h11 - h01 * h01;
  }
  const double inv = 1.0 / det;
  FaceStep step;
  step.ds = (h11 * q.r0 - h01 * q.r1) * inv;
  step.dt = (h00 * q.r1 - h01 * q.r0) * inv;
  step.singular = det == 0.0;
  step.dist_sq = e.p[0] * e.p[0] + e.p[1] * e.p[1] + e.p[2] * e.p[2];
  return step;
}

/// Plain Newton from the lanes' iterates: `steps` undamped steps (to_convergence false), or until the step is
/// at most tol (max norm) within `steps` (to_convergence true: a lane still running after them gets
/// no_convergence). A lane stops with degenerate where det H = 0 and with no_convergence where the step is
/// not finite, keeping its last iterate.
template <int kFace, int W>
static void face_plain_newton(const FaceBlock<kFace, W>& f, int steps, bool to_convergence, double tol,
                              LaneState<W>& s) {
  double running[W];
  for (int l = 0; l < W; ++l) running[l] = s.status[l] == kOk ? 1.0 : 0.0;
  for (int k = 0; k < steps; ++k) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const FaceStep step = face_newton_step<kFace, W>(f, l, s.u[l], s.v[l], false);
      const bool run = running[l] != 0.0;
      const bool finite = is_finite(step.ds) & is_finite(step.dt);
      const bool move = run & !step.singular & finite;
      s.u[l] = move ? s.u[l] + step.ds : s.u[l];
      s.v[l] = move ? s.v[l] + step.dt : s.v[l];
      s.iterations[l] += move ? 1.0 : 0.0;
      s.status[l] =
          !run ? s.status[l] : (step.singular ? kDegenerate : (!finite ? kNoConvergence : s.status[l]));
      const bool converged = to_convergence & (max_of(std::fabs(step.ds), std::fabs(step.dt)) <= tol);
      running[l] = move & !converged ? 1.0 : 0.0;
    }
    if (to_convergence && any_of<W>(running) == 0.0) break;
  }
  if (to_convergence) {
    for (int l = 0; l < W; ++l) s.status[l] = running[l] != 0.0 ? kNoConvergence : s.status[l];
  }
}

/// Safeguarded Newton from an estimate (the hybrids, as LocalSearch's): the Gauss-Newton system where the
/// exact Jacobian is not positive definite, the step shortened to plan.max_step, the iterate held in the
/// domain enlarged by plan.box_margin, and a step that does not reduce |S - P| halved up to max_halvings
/// times; still not reducing it, the lane stops on its previous iterate: outside where that lies beyond the
/// face, else no_convergence. A step at most tol_param ends the lane (converged).
template <int kFace, int W>
static void face_safeguarded_newton(const FaceBlock<kFace, W>& f, const FacePlan& plan, int steps,
                                    LaneState<W>& s) {
  double running[W];
  for (int l = 0; l < W; ++l) running[l] = s.status[l] == kOk ? 1.0 : 0.0;
  const double cap = plan.max_step, box = plan.box_margin, tol = plan.options.tol_param;
  const int halvings = plan.options.max_halvings;
  // Each step in three loops over the lanes (each vectorises; a lane loop around the halvings did not): the
  // trial point, its halvings, the update.
  double u1[W], v1[W], d1[W], allowed[W], ok_step[W], length[W], singular[W];
  for (int k = 0; k < steps; ++k) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const FaceStep step = face_newton_step<kFace, W>(f, l, s.u[l], s.v[l], true);
      const bool finite = is_finite(step.ds) & is_finite(step.dt) & !step.singular;
      length[l] = max_of(std::fabs(step.ds), std::fabs(step.dt));
      const double shorten = length[l] > cap ? cap / length[l] : 1.0;
      double u = s.u[l] + (finite ? step.ds * shorten : 0.0), v = s.v[l] + (finite ? step.dt * shorten : 0.0);
      face_clamp<kFace>(u, v, box);
      u1[l] = u;
      v1[l] = v;
      // |S - P| may grow by the rounding of P (32 eps of the block's unit size, the nodes' offsets from S
      // being below 2) without counting as an increase: |S - P|^2 up to (|S - P| + noise)^2.
      constexpr double noise = 32.0 * std::numeric_limits<double>::epsilon();
      allowed[l] = step.dist_sq + noise * (2.0 * std::sqrt(step.dist_sq) + noise);
      d1[l] = f.distance_sq(l, u, v);
      ok_step[l] = finite ? 1.0 : 0.0;
      singular[l] = step.singular ? 1.0 : 0.0;
    }
    for (int h = 0; h < halvings; ++h) {
      CONTACTNN_LANES
      for (int l = 0; l < W; ++l) {
        const bool worse = !(d1[l] <= allowed[l]);
        u1[l] = worse ? 0.5 * (s.u[l] + u1[l]) : u1[l];
        v1[l] = worse ? 0.5 * (s.v[l] + v1[l]) : v1[l];
        d1[l] = worse ? f.distance_sq(l, u1[l], v1[l]) : d1[l];
      }
    }
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const double u0 = s.u[l], v0 = s.v[l];
      const bool run = running[l] != 0.0;
      const bool finite = ok_step[l] != 0.0;
      // A step at most tol is convergence, whatever the rounding of |S - P| says.
      const bool reduced = (d1[l] <= allowed[l]) | (length[l] <= tol);
      const bool move = run & finite & reduced;
      s.u[l] = move ? u1[l] : u0;
      s.v[l] = move ? v1[l] : v0;
      s.iterations[l] += run ? 1.0 : 0.0;
      s.status[l] = !run ? s.status[l]
                         : (!finite ? (singular[l] != 0.0 ? kDegenerate : kNoConvergence)
                                    : (!reduced ? kNoConvergence : s.status[l]));
      const double moved = max_of(std::fabs(u1[l] - u0), std::fabs(v1[l] - v0));
      running[l] = move & (moved > tol) ? 1.0 : 0.0;
    }
    if (any_of<W>(running) == 0.0) break;
  }
  // A lane stopped beyond the face (held by the box, where no step along it reduces |S - P|): the distance
  // still falls outward, so the face's nearest point is on its boundary: outside, as a converged iterate out
  // there (SearchOptions::closest_point_on_face then finds that point).
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    const bool beyond = !face_inside<kFace>(s.u[l], s.v[l], plan.options.domain_margin);
    s.status[l] = (s.status[l] == kNoConvergence) & beyond ? kOutside : s.status[l];
  }
}

}  // namespace contactnn::search::detail
