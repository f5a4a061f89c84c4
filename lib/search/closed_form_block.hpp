// Internal to lib/search: the closed-form estimate on a bilinear facet, for the W lanes of a block.
//
// S is projected onto the plane through the facet's centre a0 spanned by its centre tangents a1 = P_xi(0,0)
// and a2 = P_eta(0,0), whose normal n = a1 x a2 is parallel to the diagonals' cross product (C - A) x (D -
// B). That plane, rather than the plane of A, B, D, treats the four nodes alike (the estimate does not depend
// on the node order) and stays well defined when the angle at A is near 0 or 180 degrees; for a flat facet
// both are the facet's own plane and the estimate is exact. In the plane, q = xi a1 + eta a2 + xi eta a3 (q =
// S - a0, every vector projected along n) is solved as the inverse bilinear map: with [x, y] = n . (x x y),
// which is the same for a vector and its projection,
//   k2 eta^2 + k1 eta + k0 = 0,  k2 = [a3, a2],  k1 = [q, a3] + [a1, a2],  k0 = [q, a1],
// then xi by least squares along w = a1 + eta a3. The roots come from the stable form Q = -(k1 + sign(k1)
// sqrt(disc)) / 2, eta = k0 / Q and Q / k2: a parallelogram (k2 = 0) gives the linear root k0 / Q without a
// division by ~0, the other root being infinite and rejected. Of the two, the one nearer the domain (smaller
// max(|xi|, |eta|)) is taken: inside the domain when either is.
// The facet is the block's canonical one (LaneSwap): the estimate is the same for each of the caller's node
// orders, mapped to the caller's (xi, eta) exactly (every step is odd in xi and in eta with their
// coefficients). Statuses: ok or outside by the domain; no_convergence when the discriminant is negative (the
// projected point lies beyond the fold of the map: the discriminant is taken as 0 and the nearer of the two
// roots above reported, a finite estimate that Newton can refine; as the start of a hybrid solved both ways,
// eta first and xi first, the estimate nearer S: closed_form_beyond_fold); degenerate when the facet has no
// plane
// (|a1 x a2| <= 1e-12 |a1| |a2|) or no root is finite.
#pragma once

#include <cmath>

#include "search/newton_block.hpp"

namespace contactnn::search::detail {

/// The closed form for one facet a0..a3 (S at the origin): (xi, eta), whether the point lies beyond the fold
/// (`fold`) and whether the facet has no plane or no root is finite (`degenerate`).
CONTACTNN_SEARCH_INLINE void closed_form_lane(const double* a0, const double* a1, const double* a2,
                                              const double* a3, double& xi_out, double& eta_out, bool& fold,
                                              bool& degenerate) {
  const double q[3] = {-a0[0], -a0[1], -a0[2]};
  const double n[3] = {a1[1] * a2[2] - a1[2] * a2[1], a1[2] * a2[0] - a1[0] * a2[2],
                       a1[0] * a2[1] - a1[1] * a2[0]};
  const double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  const auto triple = [&n](const double* x, const double* y) {
    return n[0] * (x[1] * y[2] - x[2] * y[1]) + n[1] * (x[2] * y[0] - x[0] * y[2]) +
           n[2] * (x[0] * y[1] - x[1] * y[0]);
  };
  // Divided by nn (~ size^4): the discriminant would be ~ size^8 and leave the double range beyond sizes of
  // 1e+-38 (at 1e+-60 the estimate was another point, or no_convergence).
  const double inv_nn = 1.0 / nn;
  const double k2 = triple(a3, a2) * inv_nn, k1 = triple(q, a3) * inv_nn + 1.0, k0 = triple(q, a1) * inv_nn;
  const double disc_raw = k1 * k1 - 4.0 * k2 * k0;
  fold = disc_raw < 0.0;
  const double root = std::sqrt(fold ? 0.0 : disc_raw);
  const double big_q = -0.5 * (k1 + (k1 >= 0.0 ? root : -root));
  const double eta1 = k0 / big_q, eta2 = big_q / k2;
  // q and a3 projected onto the plane (a1 and a2 lie in it).
  const double qn = (q[0] * n[0] + q[1] * n[1] + q[2] * n[2]) * inv_nn;
  const double an = (a3[0] * n[0] + a3[1] * n[1] + a3[2] * n[2]) * inv_nn;
  double xi[2];
  const double eta[2] = {eta1, eta2};
  CONTACTNN_UNROLL
  for (int r = 0; r < 2; ++r) {
    double num = 0.0, den = 0.0;
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      const double w = a1[c] + eta[r] * (a3[c] - an * n[c]);
      num += (q[c] - qn * n[c] - eta[r] * a2[c]) * w;
      den += w * w;
    }
    xi[r] = num / den;
  }
  const double score1 = max_of(std::fabs(xi[0]), std::fabs(eta1));
  const double score2 = max_of(std::fabs(xi[1]), std::fabs(eta2));
  const bool ok1 = is_finite(score1), ok2 = is_finite(score2);
  const bool first = ok1 & (!ok2 | (score1 <= score2));
  const double a1_sq = a1[0] * a1[0] + a1[1] * a1[1] + a1[2] * a1[2];
  const double a2_sq = a2[0] * a2[0] + a2[1] * a2[1] + a2[2] * a2[2];
  const bool flat = !(nn > 1e-24 * a1_sq * a2_sq);
  degenerate = flat | !(ok1 | ok2);
  xi_out = first ? xi[0] : xi[1];
  eta_out = first ? eta1 : eta2;
}

/// For the lanes beyond the fold (`fold`, still their canonical estimate in xi, eta): the closed form solved
/// the other way round too (xi from the quadratic, then eta), and of the two estimates the one nearer S kept,
/// in the caller's coordinates in s. Beyond the fold each is only a point near the fold's image, and which
/// one a facet gave depended on its parametrisation (the caller's node order, now the canonical one): the
/// nearer is the same in any, and a better start for Newton (of 2000 random bilinear queries of the paper's
/// domain, the one whose closed_form+newton:3 went from an error of 0.14 to 0.88 in the canonical
/// parametrisation came back). Out of line and cold: 0.6% of such queries, whose one or two lanes in a block
/// cost the closed form 6% (a scalar solve of long latency): done for the hybrids' start only. The closed
/// form alone reports such a lane no_convergence, with its first estimate (the canonical parametrisation's,
/// the same in every node order).
template <int W>
[[gnu::noinline, gnu::cold]] static void closed_form_beyond_fold(const BilinearBlock<W>& b,
                                                                 const double* fold, const double* xi,
                                                                 const double* eta, LaneState<W>& s) {
  for (int l = 0; l < W; ++l) {
    if (fold[l] == 0.0) continue;
    double a[4][3];
    for (int k = 0; k < 4; ++k) {
      for (int c = 0; c < 3; ++c) a[k][c] = b.a[3 * k + c][l];
    }
    double x2, e2;
    bool fold2, degenerate2;
    closed_form_lane(a[0], a[2], a[1], a[3], e2, x2, fold2, degenerate2);  // (eta, xi)
    const auto distance_sq = [&a](double x, double e) {
      double d = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double p = a[0][c] + x * a[1][c] + e * a[2][c] + x * e * a[3][c];
        d += p * p;
      }
      return d;
    };
    if (degenerate2 || !(distance_sq(x2, e2) < distance_sq(xi[l], eta[l]))) continue;
    b.sym.template to_caller<BilinearBlock<W>::kReflect>(l, x2, e2);
    s.u[l] = x2;
    s.v[l] = e2;
  }
}

template <int W>
static void closed_form(const BilinearBlock<W>& b, LaneState<W>& s, bool start) {
  double xi[W], eta[W], beyond[W];
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    double a0[3], a1[3], a2[3], a3[3];
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      a0[c] = b.a[c][l];
      a1[c] = b.a[3 + c][l];
      a2[c] = b.a[6 + c][l];
      a3[c] = b.a[9 + c][l];
    }
    bool fold, degenerate;
    closed_form_lane(a0, a1, a2, a3, xi[l], eta[l], fold, degenerate);
    const bool active = s.status[l] == kOk;
    double u = xi[l], v = eta[l];
    b.sym.template to_caller<BilinearBlock<W>::kReflect>(l, u, v);  // exact
    s.u[l] = active & !degenerate ? u : s.u[l];
    s.v[l] = active & !degenerate ? v : s.v[l];
    s.status[l] = !active ? s.status[l] : (degenerate ? kDegenerate : (fold ? kNoConvergence : kOk));
    beyond[l] = active & fold & !degenerate ? 1.0 : 0.0;
  }
  if (start && any_of<W>(beyond) != 0.0) closed_form_beyond_fold<W>(b, beyond, xi, eta, s);
}

}  // namespace contactnn::search::detail
