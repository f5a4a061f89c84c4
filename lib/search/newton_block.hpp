// Internal to lib/search: Newton's method on paper Eqs 7-8 for the W lanes of a block, on a surface block of
// surface_block.hpp (slave node at the origin, the caller's own segment and parameters: SPEC 8). Three forms:
//  - lean_newton: K undamped steps, as an explicit FE code runs them (the fair baseline);
//  - converged_newton: undamped steps until the step is below a tolerance (an FE code's "to convergence");
//  - safeguarded_newton: the hybrids' refinement of an estimate, kept in a box, with step control.
// Each lane runs independently: a lane that stops keeps its iterate and status while the others go on, so a
// lane's result is the same in any block, at any position, with any neighbours. Each runs in its surface's
// canonical parametrisation (LaneSymmetry or LaneSwap, surface_block.hpp): the lanes' coordinates go in and
// come out in the caller's, and in between the arithmetic is the same for each of the caller's 8 node orders
// of a segment, so that no status, coordinate or gap depends on the node order (far slave nodes and folded
// segments made them depend on it: there the rounding of the caller's own order decided).
#pragma once

#include <cmath>
#include <limits>

#include "search/surface_block.hpp"

namespace contactnn::search::detail {

/// Per-lane state of a block: the iterate in the caller's parameters, the status (kOk while running) and
/// the Newton steps taken.
template <int W>
struct LaneState {
  double u[W], v[W];
  double status[W];
  double iterations[W];
};

/// Residual r_i = P_i.(S - P) and the exact Jacobian H_ij = P_i.P_j - P_ij.(S - P) of Eqs 7-8 (Newton's
/// update solves H dp = r), with S at the origin; G = P_i.P_j is the Gauss-Newton part.
struct NewtonSystem {
  double r0, r1, g00, g01, g11, h00, h01, h11;
};

template <bool kPureSecond>
CONTACTNN_SEARCH_INLINE NewtonSystem newton_system(const Eval& e) {
  NewtonSystem q;
  const double* p = e.p;
  q.r0 = -(e.ps[0] * p[0] + e.ps[1] * p[1] + e.ps[2] * p[2]);
  q.r1 = -(e.pt[0] * p[0] + e.pt[1] * p[1] + e.pt[2] * p[2]);
  q.g00 = e.ps[0] * e.ps[0] + e.ps[1] * e.ps[1] + e.ps[2] * e.ps[2];
  q.g01 = e.ps[0] * e.pt[0] + e.ps[1] * e.pt[1] + e.ps[2] * e.pt[2];
  q.g11 = e.pt[0] * e.pt[0] + e.pt[1] * e.pt[1] + e.pt[2] * e.pt[2];
  // S - P = -P: H = G + P_ij . P.
  q.h01 = q.g01 + (e.pst[0] * p[0] + e.pst[1] * p[1] + e.pst[2] * p[2]);
  if constexpr (kPureSecond) {
    q.h00 = q.g00 + (e.pss[0] * p[0] + e.pss[1] * p[1] + e.pss[2] * p[2]);
    q.h11 = q.g11 + (e.ptt[0] * p[0] + e.ptt[1] * p[1] + e.ptt[2] * p[2]);
  } else {
    q.h00 = q.g00;
    q.h11 = q.g11;
  }
  return q;
}

/// The system of Eqs 7-8 at (u, v) for the undamped steps (lean_newton, converged_newton), from the surface's
/// point and derivatives there.
template <class Surf, int W>
struct PlainSystem {
  explicit PlainSystem(const Surf& s) : surf(s) {}
  CONTACTNN_SEARCH_INLINE NewtonSystem at(int l, double u, double v) const {
    Eval e;
    surf.template eval_canonical<true>(l, u, v, e);
    return newton_system<Surf::kHasPureSecond>(e);
  }
  const Surf& surf;
};

/// On a bilinear facet, P = a0 + u a1 + v a2 + u v a3 with S at the origin, the residual and the Jacobian are
/// polynomials in (u, v) whose coefficients are dot products d_ij = a_i . a_j, taken once per query:
///   g00 = |P_u|^2 = d11 + 2 d13 v + d33 v^2,   g11 = |P_v|^2 = d22 + 2 d23 u + d33 u^2,
///   r0 = -P_u . P = -(d10 + e v + d23 v^2 + g00 u),   r1 = -P_v . P = -(d20 + e u + d13 u^2 + g11 v),
///   h01 = P_u . P_v + P_uv . P = e + 2 d13 u + 2 d23 v + 2 d33 u v,   e = d12 + d03,
///   g01 = P_u . P_v = d12 + d13 u + d23 v + d33 u v,   h00 = g00, h11 = g11 (P_uu = P_vv = 0).
/// A step's system then costs 32 flops instead of 64 (the point, both tangents and five dot products anew,
/// as the hybrids' safeguarded steps still take them: they need P itself), on a shorter chain of dependent
/// operations: one query at a time newton:5 116 -> 98 ns, batched 21.3 -> 20.2 ns (bench_search, A/B). The
/// same iterates to rounding: both forms carry the rounding of P, eps |a0|, into the residual.
template <int W>
struct PlainSystem<BilinearBlock<W>, W> {
  explicit PlainSystem(const BilinearBlock<W>& b) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const auto dot = [&b, l](int i, int j) {
        return b.a[3 * i][l] * b.a[3 * j][l] + b.a[3 * i + 1][l] * b.a[3 * j + 1][l] +
               b.a[3 * i + 2][l] * b.a[3 * j + 2][l];
      };
      d10[l] = dot(1, 0);
      d20[l] = dot(2, 0);
      d11[l] = dot(1, 1);
      d22[l] = dot(2, 2);
      d33[l] = dot(3, 3);
      d12[l] = dot(1, 2);
      d13[l] = dot(1, 3);
      d23[l] = dot(2, 3);
      e[l] = d12[l] + dot(0, 3);
    }
  }
  CONTACTNN_SEARCH_INLINE NewtonSystem at(int l, double u, double v) const {
    NewtonSystem q;
    const double t13 = 2.0 * d13[l], t23 = 2.0 * d23[l], uv = u * v;
    q.g00 = d11[l] + v * (t13 + v * d33[l]);
    q.g11 = d22[l] + u * (t23 + u * d33[l]);
    q.g01 = d12[l] + u * d13[l] + v * d23[l] + uv * d33[l];
    q.r0 = -((d10[l] + v * (e[l] + v * d23[l])) + u * q.g00);
    q.r1 = -((d20[l] + u * (e[l] + u * d13[l])) + v * q.g11);
    q.h00 = q.g00;
    q.h11 = q.g11;
    q.h01 = e[l] + u * t13 + v * t23 + 2.0 * uv * d33[l];
    return q;
  }
  double d10[W], d20[W], d11[W], d22[W], d33[W], d12[W], d13[W], d23[W], e[W];
};

/// The undamped Newton step H dp = r at an iterate (lean_newton, converged_newton): singular when det H = 0,
/// finite when both components are.
struct PlainStep {
  double du, dv;
  bool singular, finite;
};

CONTACTNN_SEARCH_INLINE PlainStep plain_step(const NewtonSystem& q) {
  const double det = q.h00 * q.h11 - q.h01 * q.h01;
  const double inv = 1.0 / det;
  PlainStep p;
  p.du = (q.h11 * q.r0 - q.h01 * q.r1) * inv;
  p.dv = (q.h00 * q.r1 - q.h01 * q.r0) * inv;
  p.singular = det == 0.0;
  p.finite = is_finite(p.du) & is_finite(p.dv);
  return p;
}

/// Lean Newton: `steps` undamped steps H dp = r from the lanes' iterates. A lane stops early, keeping its
/// last iterate, with status degenerate when det H = 0 (as projection::newton_fixed_iterations stops) or
/// no_convergence when the step is not finite. No line search, no box, no convergence test.
template <class Surf, int W>
CONTACTNN_SEARCH_INLINE void lean_steps(const Surf& surf, int steps, LaneState<W>& s) {
  const PlainSystem<Surf, W> system(surf);
  for (int k = 0; k < steps; ++k) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const PlainStep p = plain_step(system.at(l, s.u[l], s.v[l]));
      const double du = p.du, dv = p.dv;
      const bool active = s.status[l] == kOk;
      const bool singular = p.singular, finite = p.finite;
      const bool take = active & !singular & finite;
      s.u[l] = take ? s.u[l] + du : s.u[l];
      s.v[l] = take ? s.v[l] + dv : s.v[l];
      s.iterations[l] += take ? 1.0 : 0.0;
      s.status[l] =
          (active & singular) ? kDegenerate : ((active & !singular & !finite) ? kNoConvergence : s.status[l]);
    }
  }
}

/// The lanes' coordinates from the caller's parametrisation to the surface's canonical one (Surf::sym).
template <class Surf, int W>
CONTACTNN_SEARCH_INLINE void to_canonical(const Surf& surf, LaneState<W>& s) {
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) surf.sym.template to_canonical<Surf::kReflect>(l, s.u[l], s.v[l]);
}

/// The lanes' canonical coordinates back to the caller's (Surf::report).
template <class Surf, int W>
CONTACTNN_SEARCH_INLINE void to_caller(Surf& surf, LaneState<W>& s) {
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) surf.report(l, s.u[l], s.v[l]);
}

/// Lean Newton from the domain centre (search_rows starts every lane there; no symmetry moves it, so the
/// lanes need no map into the canonical parametrisation), reported in the caller's. No fold test
/// (converged_newton's, safeguarded_newton's): the K steps stop wherever they are, and their status says only
/// whether a step could be taken; the test at the last iterate cost newton:5 5% (its gap's sign at a fold is
/// the side the iterate is on, the same in every node order).
template <class Surf, int W>
static void lean_newton(Surf& surf, int steps, LaneState<W>& s) {
  if constexpr (W == 1) {
    // One lane: its state in a local, which the compiler keeps in registers. Through `s` (which might alias
    // `surf` as far as it knows) every step stored its iterate and loaded it again, a store-to-load delay in
    // each step's chain of dependent operations.
    LaneState<1> local = s;
    lean_steps<Surf, 1>(surf, steps, local);
    to_caller<Surf, 1>(surf, local);
    s = local;
  } else {
    lean_steps<Surf, W>(surf, steps, s);
    to_caller<Surf, W>(surf, s);
  }
}

/// |P_s x P_t|^2 of e.
CONTACTNN_SEARCH_INLINE double normal_sq(const Eval& e) {
  const double nx = e.ps[1] * e.pt[2] - e.ps[2] * e.pt[1];
  const double ny = e.ps[2] * e.pt[0] - e.ps[0] * e.pt[2];
  const double nz = e.ps[0] * e.pt[1] - e.ps[1] * e.pt[0];
  return nx * nx + ny * ny + nz * nz;
}

/// The normal of e vanishes to the labels' precision: |P_s x P_t| <= 1e-12 L^2 with longest_sq = L^2, the
/// reference's test at its solution (fill_solution: such a solution is no label, and a segment with no other
/// is degenerate). At the fold of a folded segment's map (C inside the triangle ABD, or a reflex corner) the
/// nearest point of the surface is such a point for every slave node beyond the fold's image, and there the
/// normal's direction, and the gap's sign, was the rounding's: ok with a gap of 0, +0.2 or -0.2 by the
/// caller's node order.
CONTACTNN_SEARCH_INLINE bool normal_vanishes(const Eval& e, double longest_sq) {
  return !(normal_sq(e) > 1e-24 * longest_sq * longest_sq);
}

/// The iterate (canonical) lies in the parameter domain enlarged by `margin`.
template <class Surf>
CONTACTNN_SEARCH_INLINE bool in_domain(double u, double v, double margin) {
  constexpr double lo = Surf::kKind == SurfaceKind::kGregory ? 0.0 : -1.0, hi = 1.0;
  return (u >= lo - margin) & (u <= hi + margin) & (v >= lo - margin) & (v <= hi + margin);
}

template <class Surf, int W>
static void converged_steps(const Surf& surf, int max_iterations, double tol, bool pause, LaneState<W>& s) {
  const PlainSystem<Surf, W> system(surf);
  double running[W];
  for (int l = 0; l < W; ++l) running[l] = s.status[l] == kOk ? 1.0 : 0.0;
  for (int k = 0; k < max_iterations; ++k) {
    double any = 0.0;
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const PlainStep p = plain_step(system.at(l, s.u[l], s.v[l]));
      const double du = p.du, dv = p.dv;
      const bool active = running[l] != 0.0;
      const bool singular = p.singular, finite = p.finite;
      const bool take = active & !singular & finite;
      const double size = max_of(std::fabs(du), std::fabs(dv));
      s.u[l] = take ? s.u[l] + du : s.u[l];
      s.v[l] = take ? s.v[l] + dv : s.v[l];
      s.iterations[l] += take ? 1.0 : 0.0;
      s.status[l] =
          (active & singular) ? kDegenerate : ((active & !singular & !finite) ? kNoConvergence : s.status[l]);
      running[l] = (take & !(size <= tol)) ? 1.0 : 0.0;
    }
    any = any_of<W>(running);
    if (any == 0.0) return;
  }
  const double stopped = pause ? kPending : kNoConvergence;
  for (int l = 0; l < W; ++l) s.status[l] = running[l] != 0.0 ? stopped : s.status[l];
}

/// Undamped Newton until the step (max norm) is at most `tol` or `max_iterations` steps: statuses as
/// lean_newton, and for a lane still moving after the last step no_convergence, or kPending when `pause`. A
/// lane converged inside the domain (enlarged by tol) where the normal vanishes (normal_vanishes: the fold of
/// a folded segment) is degenerate, as its label. (Beyond the domain such a point is left outside: the
/// extended facet of a nearly collapsed segment, C and D 1e-9 apart, has one along the line through them, and
/// the labels project there.)
template <class Surf, int W>
static void converged_newton(Surf& surf, int max_iterations, double tol, bool pause, LaneState<W>& s) {
  // From the centre, as lean_newton: no map in.
  converged_steps<Surf, W>(surf, max_iterations, tol, pause, s);
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    Eval e;
    surf.template eval_canonical<false>(l, s.u[l], s.v[l], e);
    const bool fold =
        (s.status[l] == kOk) & in_domain<Surf>(s.u[l], s.v[l], tol) & normal_vanishes(e, surf.longest[l]);
    s.status[l] = fold ? kDegenerate : s.status[l];
  }
  to_caller<Surf, W>(surf, s);
}

/// Whether the iterates of the lanes marked in `candidate` (canonical: an answer inside the domain where the
/// tangents are nearly parallel but the normal does not vanish yet) head for a fold: plain Newton from each
/// to convergence (the labels' tolerance and iteration limit), which ends inside the domain where the normal
/// vanishes. Out of line and cold: a hybrid whose few steps stop short of a fold's point (where S lies over
/// the fold's image the distance is quartic there and Newton converges linearly: closed_form+newton:3 and
/// network+newton:3 stopped 0.007 to 0.014 from it, ok with a gap of +-0.2 where the label is degenerate);
/// other lanes come here only where the tangents meet at less than 3 degrees, which a usable segment's do
/// not.
template <class Surf, int W>
[[gnu::noinline, gnu::cold]] static void mark_folds(const Surf& surf, const double* candidate,
                                                    LaneState<W>& s) {
  LaneState<W> t;
  for (int l = 0; l < W; ++l) {
    t.u[l] = s.u[l];
    t.v[l] = s.v[l];
    t.status[l] = candidate[l] != 0.0 ? kOk : kInvalid;
    t.iterations[l] = 0.0;
  }
  constexpr double kTol = 1e-13;  // ProjectionOptions' tol_param and max_iterations
  converged_steps<Surf, W>(surf, 50, kTol, false, t);
  for (int l = 0; l < W; ++l) {
    Eval e;
    surf.template eval_canonical<false>(l, t.u[l], t.v[l], e);
    const bool fold = (candidate[l] != 0.0) & (t.status[l] == kOk) & in_domain<Surf>(t.u[l], t.v[l], kTol) &
                      normal_vanishes(e, surf.longest[l]);
    s.status[l] = fold ? kDegenerate : s.status[l];
  }
}

/// The box and step control of the hybrids (SearchOptions).
struct Safeguards {
  double lo, hi;                ///< iterates stay in [lo, hi]^2
  double max_step;              ///< parameter units, max norm
  double tol;                   ///< a step this short ends the lane (converged)
  int max_halvings;             ///< halvings of a step that does not reduce |S - P|
  double inside_lo, inside_hi;  ///< the domain enlarged by domain_margin (ok versus outside)
};

/// Surface values at the current iterate of every lane, kept between steps. kPureSecond false (the bilinear
/// facet): P_ss = P_tt = 0 are neither stored nor loaded.
template <int W, bool kPureSecond>
struct EvalStore {
  double p[3][W], ps[3][W], pt[3][W], pst[3][W];
  double pss[kPureSecond ? 3 : 1][W], ptt[kPureSecond ? 3 : 1][W];
  double f[W];                    ///< |S - P|^2
  double dist[W];                 ///< |S - P|
  double orient[W], reach_sq[W];  ///< Eval::orient and Eval::reach_sq, for gap_at (set by safeguarded_newton)

  CONTACTNN_SEARCH_INLINE void load(int l, Eval& e) const {
    e.orient = orient[l];
    e.reach_sq = reach_sq[l];
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      e.p[c] = p[c][l];
      e.ps[c] = ps[c][l];
      e.pt[c] = pt[c][l];
      e.pst[c] = pst[c][l];
      if constexpr (kPureSecond) {
        e.pss[c] = pss[c][l];
        e.ptt[c] = ptt[c][l];
      }
    }
  }
  /// P_s and P_t alone (normal_vanishes).
  CONTACTNN_SEARCH_INLINE void load_derivatives(int l, Eval& e) const {
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      e.ps[c] = ps[c][l];
      e.pt[c] = pt[c][l];
    }
  }
  /// Stores e for lane l where `take`, leaves the lane as it is otherwise.
  CONTACTNN_SEARCH_INLINE void store_if(int l, bool take, const Eval& e, double f_new) {
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      p[c][l] = take ? e.p[c] : p[c][l];
      ps[c][l] = take ? e.ps[c] : ps[c][l];
      pt[c][l] = take ? e.pt[c] : pt[c][l];
      pst[c][l] = take ? e.pst[c] : pst[c][l];
      if constexpr (kPureSecond) {
        pss[c][l] = take ? e.pss[c] : pss[c][l];
        ptt[c][l] = take ? e.ptt[c] : ptt[c][l];
      }
    }
    store_distance_if(l, take, f_new);
  }
  /// Only |S - P| where `take` (the surface values are filled in afterwards).
  CONTACTNN_SEARCH_INLINE void store_distance_if(int l, bool take, double f_new) {
    f[l] = take ? f_new : f[l];
    dist[l] = take ? std::sqrt(f_new) : dist[l];
  }
};

CONTACTNN_SEARCH_INLINE double clamp_to(double x, double lo, double hi) {
  x = x > hi ? hi : x;
  return x < lo ? lo : x;
}

/// The end of safeguarded_newton for the lanes held on the box's edge, out of line: inlined, its use of the
/// stored surface changed how GCC contracts the steps' multiply-adds in one of the two builds (the one-lane
/// and the vectorised kernel), and a query's bits then depended on its block.
template <int W, bool kPureSecond>
[[gnu::noinline]] static void classify_held_lanes(const Safeguards& g, LaneState<W>& s,
                                                  const EvalStore<W, kPureSecond>& store) {
  // A lane held on the box's edge. Where the box is larger than the domain, the iterate is not at a
  // stationary point in the box: no_convergence (a step pointing further out there follows a far stationary
  // point or the fold of a warped bilinear map as often as the answer: on random bilinear configurations
  // labelled inside, calling those outside gave wrong answers). Where the box's edge is the domain's (the
  // Gregory default), the gradient of |S - P|^2 at the iterate (the surface is in `store`: no evaluation)
  // says whether the nearest point of the segment is there: the distance still falling outward across the
  // edge (by more than a step of tol) -> outside, reported at the edge; otherwise -> ok, a point of the edge.
  const double lo = g.lo, hi = g.hi, tol = g.tol;
  const double in_lo = g.inside_lo, in_hi = g.inside_hi;
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    const bool at_lo_u = s.u[l] == lo, at_hi_u = s.u[l] == hi, at_lo_v = s.v[l] == lo, at_hi_v = s.v[l] == hi;
    const bool pinned = at_lo_u | at_hi_u | at_lo_v | at_hi_v;
    // r_i = P_i.(S - P) = -(1/2) d|S - P|^2 / di: positive where the distance falls as i grows.
    double r0 = 0.0, r1 = 0.0, m0 = 0.0, m1 = 0.0;
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      r0 -= store.ps[c][l] * store.p[c][l];
      r1 -= store.pt[c][l] * store.p[c][l];
      m0 += store.ps[c][l] * store.ps[c][l];
      m1 += store.pt[c][l] * store.pt[c][l];
    }
    const double t0 = tol * m0, t1 = tol * m1;
    const bool outward =
        (at_lo_u & (r0 < -t0)) | (at_hi_u & (r0 > t0)) | (at_lo_v & (r1 < -t1)) | (at_hi_v & (r1 > t1));
    const bool on_domain = (s.u[l] >= in_lo) & (s.u[l] <= in_hi) & (s.v[l] >= in_lo) & (s.v[l] <= in_hi);
    const bool held = (s.status[l] == kOk) & pinned;
    s.status[l] = (held & !on_domain) ? kNoConvergence : ((held & outward) ? kOutside : s.status[l]);
  }
}

/// safeguarded_newton's steps, in the canonical parametrisation.
template <class Surf, int W>
static void safeguarded_steps(const Surf& surf, int steps, const Safeguards& g, const double* noise,
                              LaneState<W>& s, EvalStore<W, Surf::kHasPureSecond>& store) {
  // The settings as locals: a field read under a lane-dependent condition becomes a masked load of an
  // invariant, which GCC 12 does not vectorise.
  const double lo = g.lo, hi = g.hi, max_step = g.max_step, tol = g.tol;
  // On a bilinear facet the surface at an iterate (31 flops) is evaluated again where it is needed rather
  // than kept: storing and reloading its 12 values per lane and step cost more (bench_search A/B, batched, 1
  // thread: closed_form+newton:3 41.0 -> 39.5 ns, network+newton:3[bilinear-8] 65.4 -> 63.9). A Gregory
  // evaluation is 790 flops: kept.
  constexpr bool kEvaluateAgain = !Surf::kHasPureSecond;
  double running[W], pending[W], tu[W], tv[W], tiny[W], stalled[W];
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    s.u[l] = clamp_to(s.u[l], lo, hi);
    s.v[l] = clamp_to(s.v[l], lo, hi);
    Eval e;
    surf.template eval_canonical<true>(l, s.u[l], s.v[l], e);
    const double f = e.p[0] * e.p[0] + e.p[1] * e.p[1] + e.p[2] * e.p[2];
    if constexpr (kEvaluateAgain) {
      store.store_distance_if(l, true, f);
    } else {
      store.store_if(l, true, e, f);
    }
    running[l] = s.status[l] == kOk ? 1.0 : 0.0;
  }
  for (int k = 0; k < steps; ++k) {
    double any_pending = 0.0;
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      Eval e;
      if constexpr (kEvaluateAgain) {
        surf.template eval_canonical<true>(l, s.u[l], s.v[l], e);
      } else {
        store.load(l, e);
      }
      const NewtonSystem q = newton_system<Surf::kHasPureSecond>(e);
      const double scale = q.g00 + q.g11;
      const double floor = 1e-24 * scale * scale;
      const double det_h = q.h00 * q.h11 - q.h01 * q.h01;
      const double det_g = q.g00 * q.g11 - q.g01 * q.g01;
      const bool exact = (q.h00 > 0.0) & (det_h > floor);
      double a = exact ? q.h00 : q.g00, b = exact ? q.h01 : q.g01, c = exact ? q.h11 : q.g11;
      double det = exact ? det_h : det_g;
      if constexpr (Surf::kHasPureSecond) {
        // H not positive definite (a Gregory patch curving away from S): H + mu I with mu chosen so that its
        // smallest eigenvalue is a tenth of G's, a Newton step that keeps the curvature along the other
        // direction, instead of the Gauss-Newton step, which drops it in both.
        const double half_h = 0.5 * (q.h00 - q.h11), half_g = 0.5 * (q.g00 - q.g11);
        const double min_h = 0.5 * (q.h00 + q.h11) - std::sqrt(half_h * half_h + q.h01 * q.h01);
        const double min_g = 0.5 * (q.g00 + q.g11) - std::sqrt(half_g * half_g + q.g01 * q.g01);
        const double mu = 0.1 * min_g - min_h;
        const double sa = q.h00 + mu, sc = q.h11 + mu, det_s = sa * sc - q.h01 * q.h01;
        const bool shifted = !exact & (min_g > 0.0) & (sa > 0.0) & (det_s > floor);
        a = shifted ? sa : a;
        b = shifted ? q.h01 : b;
        c = shifted ? sc : c;
        det = shifted ? det_s : det;
      }
      const double inv = 1.0 / det;
      double du = (c * q.r0 - b * q.r1) * inv;
      double dv = (a * q.r1 - b * q.r0) * inv;
      if constexpr (Surf::kHasPureSecond) {
        // A Gregory patch, whose box is the domain: on an edge with the step pointing out of the segment, the
        // coordinate stays on the edge and the other takes the step of the problem along the edge (projected
        // Newton). The full step, clamped, moved the free coordinate by an amount meant for a move off the
        // edge too, which could raise |S - P| however it was halved: a node whose nearest point is outside,
        // held at the edge, ended no_convergence after 3 to 5 steps. Out through both edges of a corner: no
        // step (converged there). Not on the bilinear facet, whose box lies beyond the domain: a lane that
        // reaches it has left for a far stationary point, and sliding along the box's face brought some back
        // to wrong answers (closed_form+newton:3's mean error on the bilinear domain rose 1.5x).
        // A move by d from x on the box's edge that leaves the box.
        const auto leaves = [lo, hi](double x, double d) {
          return ((x <= lo) & (d < 0.0)) | ((x >= hi) & (d > 0.0));
        };
        const double du_face = q.r0 / (a > 0.0 ? a : 1.0), dv_face = q.r1 / (c > 0.0 ? c : 1.0);
        const bool out_u = leaves(s.u[l], du), out_v = leaves(s.v[l], dv);
        const bool hold_u = out_u | (out_v & leaves(s.u[l], du_face));
        const bool hold_v = out_v | (out_u & leaves(s.v[l], dv_face));
        du = hold_u ? 0.0 : (hold_v ? du_face : du);
        dv = hold_v ? 0.0 : (hold_u ? dv_face : dv);
      }
      const bool singular = !exact & !(det_g > floor);
      const double size = max_of(std::fabs(du), std::fabs(dv));
      const double shrink = size > max_step ? max_step / size : 1.0;
      du *= shrink;
      dv *= shrink;
      const bool active = running[l] != 0.0;
      s.status[l] = (active & singular) ? kDegenerate : s.status[l];
      const bool go = active & !singular & is_finite(du) & is_finite(dv);
      tu[l] = go ? clamp_to(s.u[l] + du, lo, hi) : s.u[l];
      tv[l] = go ? clamp_to(s.v[l] + dv, lo, hi) : s.v[l];
      tiny[l] = size <= tol ? 1.0 : 0.0;
      stalled[l] = 0.0;
      s.status[l] = (active & !singular & !go) ? kNoConvergence : s.status[l];
      running[l] = go ? 1.0 : 0.0;
      pending[l] = running[l];
    }
    // Reductions over lanes in loops of their own: inside a lane loop they would stop its vectorisation.
    any_pending = any_of<W>(pending);
    for (int h = 0; h <= g.max_halvings && any_pending != 0.0; ++h) {
      any_pending = 0.0;
      CONTACTNN_LANES
      for (int l = 0; l < W; ++l) {
        Eval e;
        surf.template eval_canonical<true>(l, tu[l], tv[l], e);
        const double f = e.p[0] * e.p[0] + e.p[1] * e.p[1] + e.p[2] * e.p[2];
        const double reach = noise[l] * (2.0 * store.dist[l] + noise[l]);
        const bool wait = pending[l] != 0.0;
        const bool accept = wait & ((f <= store.f[l] + reach) | (tiny[l] != 0.0));
        if constexpr (kEvaluateAgain) {
          store.store_distance_if(l, accept, f);
        } else {
          store.store_if(l, accept, e, f);
        }
        stalled[l] = accept & (tu[l] == s.u[l]) & (tv[l] == s.v[l]) ? 1.0 : stalled[l];
        s.u[l] = accept ? tu[l] : s.u[l];
        s.v[l] = accept ? tv[l] : s.v[l];
        s.iterations[l] += accept ? 1.0 : 0.0;
        const bool again = wait & !accept;
        tu[l] = again ? s.u[l] + 0.5 * (tu[l] - s.u[l]) : tu[l];
        tv[l] = again ? s.v[l] + 0.5 * (tv[l] - s.v[l]) : tv[l];
        pending[l] = again ? 1.0 : 0.0;
      }
      any_pending = any_of<W>(pending);
    }
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      const bool rejected = pending[l] != 0.0;
      s.status[l] = rejected ? kNoConvergence : s.status[l];
      running[l] = ((running[l] != 0.0) & !rejected & (tiny[l] == 0.0) & (stalled[l] == 0.0)) ? 1.0 : 0.0;
    }
    if (any_of<W>(running) == 0.0) break;
  }
  if constexpr (kEvaluateAgain) {
    CONTACTNN_LANES
    for (int l = 0; l < W; ++l) {
      Eval e;
      surf.template eval_canonical<true>(l, s.u[l], s.v[l], e);
      store.store_if(l, true, e, store.f[l]);
    }
  }
  classify_held_lanes<W, Surf::kHasPureSecond>(g, s, store);
}

/// The hybrids' refinement: from each lane's estimate (clamped into the box), `steps` Newton steps with the
/// exact Jacobian where it is positive definite; where it is not, on a Gregory patch the Jacobian shifted to
/// positive definite (below), on a bilinear facet (and where the shift fails) the Gauss-Newton step
/// (downhill on |S - P|^2); a step is shortened to max_step, clamped into the box, and accepted when |S - P|
/// does not grow by more than the rounding of the positions (noise[l], a length); otherwise halved up to
/// max_halvings times, after which the lane stops with status no_convergence and keeps its previous iterate.
/// On a Gregory patch a lane on the box's edge whose step points out of the box steps along the edge instead.
/// A step shorter than `tol` ends the lane (converged), and so does an accepted step that does not move the
/// iterate (held in a corner of the box, every later step would be the same). Both systems singular:
/// degenerate. A lane ending on the box's edge: no_convergence where that edge lies beyond the domain; on an
/// edge of the domain, outside when |S - P| still falls outward across it, else ok (see the last loop). A
/// lane ending inside the domain where the normal vanishes (normal_vanishes: the fold of a folded segment),
/// or where it nearly does and plain Newton from there converges to such a point (mark_folds): degenerate, as
/// its label. `store` holds the surface at each lane's final iterate (in the canonical parametrisation, with
/// the orientation and the reach gap_at needs); the iterates come back in the caller's coordinates, a lane
/// that never moved with its start's own bits.
template <class Surf, int W>
static void safeguarded_newton(Surf& surf, int steps, const Safeguards& g, const double* noise,
                               LaneState<W>& s, EvalStore<W, Surf::kHasPureSecond>& store) {
  double start_u[W], start_v[W], canonical_u[W], canonical_v[W];
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    start_u[l] = s.u[l];
    start_v[l] = s.v[l];
    surf.sym.template to_canonical<Surf::kReflect>(l, s.u[l], s.v[l]);
    canonical_u[l] = s.u[l];
    canonical_v[l] = s.v[l];
  }
  safeguarded_steps<Surf, W>(surf, steps, g, noise, s, store);
  // A fold inside the domain (normal_vanishes, mark_folds): degenerate, as the labels.
  double candidate[W];
  const double in_lo = g.inside_lo, in_hi = g.inside_hi;
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    Eval e;
    store.load_derivatives(l, e);
    const double n_sq = normal_sq(e), l4 = surf.longest[l] * surf.longest[l];
    const double ps_sq = e.ps[0] * e.ps[0] + e.ps[1] * e.ps[1] + e.ps[2] * e.ps[2];
    const double pt_sq = e.pt[0] * e.pt[0] + e.pt[1] * e.pt[1] + e.pt[2] * e.pt[2];
    const bool inside =
        (s.status[l] == kOk) & (s.u[l] >= in_lo) & (s.u[l] <= in_hi) & (s.v[l] >= in_lo) & (s.v[l] <= in_hi);
    const bool vanishes = !(n_sq > 1e-24 * l4);  // normal_vanishes
    s.status[l] = inside & vanishes ? kDegenerate : s.status[l];
    // Near a fold the tangents turn parallel: the angle between them below 3 degrees (sin 0.05).
    candidate[l] = inside & !vanishes & !(n_sq > 0.0025 * ps_sq * pt_sq) ? 1.0 : 0.0;
  }
  if (any_of<W>(candidate) != 0.0) mark_folds<Surf, W>(surf, candidate, s);
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    store.orient[l] = surf.sym.orient[l];
    store.reach_sq[l] = surf.reach_sq[l];
    const bool still = (s.u[l] == canonical_u[l]) & (s.v[l] == canonical_v[l]);
    surf.report(l, s.u[l], s.v[l]);
    s.u[l] = still ? start_u[l] : s.u[l];
    s.v[l] = still ? start_v[l] : s.v[l];
  }
}

/// gap = n.(S - P) with n the caller's unit normal P_s x P_t (e.orient times the canonical one, whose
/// arithmetic is the same in every node order), at most the distance to the segment's nearest node
/// (sqrt(e.reach_sq)) in magnitude (issue 31; docs/conventions.md): no point of the segment is farther, so
/// the cap changes no converged answer inside the domain, while beyond the domain a method's point can be far
/// off (the Gregory closed form's estimate for a slave node 1e15 away is the patch's cubic extrapolation,
/// 2e44 away). 0 where the normal vanishes or a value is NaN. e is a surface's public eval or
/// EvalStore::load. One square root, of the smaller of gap^2 = (n.p / |n|^2) (n.p) and the reach's square
/// (n.p / |n|^2 overflows only where the gap exceeds the double range, or n.p itself for a slave node 1e154
/// element sizes away: then the cap is the gap).
CONTACTNN_SEARCH_INLINE double gap_at(const Eval& e) {
  const double nx = e.ps[1] * e.pt[2] - e.ps[2] * e.pt[1];
  const double ny = e.ps[2] * e.pt[0] - e.ps[0] * e.pt[2];
  const double nz = e.ps[0] * e.pt[1] - e.ps[1] * e.pt[0];
  const double n_sq = nx * nx + ny * ny + nz * nz;
  const double along = nx * e.p[0] + ny * e.p[1] + nz * e.p[2];  // n.(P - S) = -|n| gap
  const double gap_sq = along / n_sq * along;
  const double size = std::sqrt(min_of(gap_sq, e.reach_sq));
  const double gap = e.orient * along > 0.0 ? -size : size;
  return (n_sq > 0.0) & (gap_sq == gap_sq) ? gap : 0.0;  // not NaN (an infinite gap_sq is capped)
}

}  // namespace contactnn::search::detail
