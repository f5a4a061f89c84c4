// Internal to lib/search: the method four_triangles for the W lanes of a block of bilinear segments, after
// the production local search of OpenRadioss's type 7 contact (engine/source/interfaces/int07/i7dst3.F and
// intsort/i7pen3.F): no iteration. The quad A B C D is split about its centroid O = (A + B + C + D) / 4 into
// the triangles ABO, BCO, CDO, DAO; S's closest point on each (interior, edge or vertex), the nearest wins.
//
// What differs from OpenRadioss, and why:
//  - The clamping. i7dst3.F projects S on the triangle's plane (barycentric coordinates from cross products
//    with S, as here) and, where a coordinate is negative, projects S on the one edge beyond whose line it
//    lies farthest (the weights lambda |lambda| / |edge|^2: "HLA ... necessaires pour triangle angle obtu"),
//    clamped to the edge. That choice gave the exact closest point on 400000 random triangles, thin and
//    obtuse ones among them (a check made for this port, outside the tests). Here every edge of the triangle
//    competes instead: the same exact point without a branch per lane, and the edges shared by two triangles
//    (the spokes) are computed once.
//  - Type 7 needs no sign: its contact is two-sided with a gap (the penetration is gap - min_k |S - P_k|, the
//    force along a blend of the vectors S - P_k: i7for3.F). Here the gap is signed as lib/search's others are
//    (SPEC 2: < 0 is penetration), by the segment's normal direction N = (C - A) x (D - B). N is the sum of
//    the four triangles' area vectors (twice it), so it is the area-weighted normal of the four-triangle
//    surface, the same for each of the four triangles, for any cyclic relabelling of the nodes (the mirror
//    order reverses it, as it reverses P_xi x P_eta) and parallel to the bilinear facet's normal at its
//    centre (the closed form's plane). A triangle's own normal would give the gap a different sign rule at
//    each ridge.
//
// The shared edges (the four spokes X -> O) and the vertices are computed once per lane, so a point on an
// edge or at a vertex has the same key (its squared distance from S less |S - O|^2) whichever triangle
// reaches it; the candidates are compared in the order: per triangle (ABO, BCO, CDO, DAO) its interior, its
// outer edge, its spoke from the next node, its spoke from the first node; a candidate replaces the best only
// when strictly nearer (ties: the first).
#pragma once

#include <cmath>
#include <limits>

#include "search/newton_block.hpp"

namespace contactnn::search::detail {

/// For the lanes whose status is ok: (s.u, s.v) = (xi, eta) of the nearest point P of the four triangles in
/// the piecewise-linear parametrisation (A (-1, -1), B (1, -1), C (1, 1), D (-1, 1), O (0, 0), linear on each
/// triangle); s.status = outside where P is on the quad's outer boundary (an outer edge or a corner:
/// max(|xi|, |eta|) = 1) and S does not project onto it: the projection of S on the plane of the winning
/// triangle, in that triangle's parametrisation extended over its plane, lies more than `margin` (max norm,
/// parameter units) from P; ok otherwise. gap[l] (every lane) = +-|S - P|, negative where (S - P) . N < 0, N
/// = (C - A) x (D - B); units of q (LocalSearch::run multiplies back a rescaled block's). A triangle X Y O
/// without a plane (|n|^2 <= 1e-24 |Y - X|^2 |O - X|^2) offers its edges only, and a point it gives is ok.
/// `b` is the facet of q (its a0 is O - S).
template <int W>
static void four_triangles(const QueryBlock<W>& q, const BilinearBlock<W>& b, double margin, LaneState<W>& s,
                           double* gap) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  CONTACTNN_LANES
  for (int l = 0; l < W; ++l) {
    // Relative to the centroid O: the nodes r[i] = P_i - O (r[4] = O - O = 0) and the slave node sv = S - O.
    // Candidates are compared by key = |P - O|^2 - 2 (S - O) . (P - O) = |S - P|^2 - |S - O|^2: the common
    // |S - O|^2 taken out, two candidates' keys differ by what tells them apart, with the rounding of
    // (S - O) . (P - O), eps |S - O| |P - O|. Squared distances from S (|S - O|^2 + ~size^2) lose that
    // difference to rounding once S is more than ~1e7 element sizes away, and then an edge point 1e-5 of the
    // element from the answer already tied with it at 1e3 sizes.
    double r[5][3], sv[3];
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      const double o = b.a[c][l];  // O - S
      CONTACTNN_UNROLL
      for (int i = 0; i < 4; ++i) r[i][c] = q.node[3 * i + c][l] - o;
      r[4][c] = 0.0;
      sv[c] = -o;
    }
    constexpr double kU[5] = {-1.0, 1.0, 1.0, -1.0, 0.0};
    constexpr double kV[5] = {-1.0, -1.0, 1.0, 1.0, 0.0};
    // Per point its key; per node sv x r[i] (two triangles' barycentric coordinates use it).
    double key[5], sxr[4][3];
    CONTACTNN_UNROLL
    for (int i = 0; i < 5; ++i) {
      key[i] = r[i][0] * (r[i][0] - 2.0 * sv[0]) + r[i][1] * (r[i][1] - 2.0 * sv[1]) +
               r[i][2] * (r[i][2] - 2.0 * sv[2]);
    }
    CONTACTNN_UNROLL
    for (int i = 0; i < 4; ++i) {
      sxr[i][0] = sv[1] * r[i][2] - sv[2] * r[i][1];
      sxr[i][1] = sv[2] * r[i][0] - sv[0] * r[i][2];
      sxr[i][2] = sv[0] * r[i][1] - sv[1] * r[i][0];
    }

    // The closest point on the segment X -> Y, clamped: the vertex itself (its exact values) where the
    // parameter t is at most 0 (or undefined: X = Y) or at least 1.
    struct Candidate {
      double key, u, v, p[3];
    };
    const auto on_edge = [&](int x, int y) {
      double e[3], w[3];
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) {
        e[c] = r[y][c] - r[x][c];
        w[c] = sv[c] - r[x][c];
      }
      const double ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
      const double t = ee > 0.0 ? (w[0] * e[0] + w[1] * e[1] + w[2] * e[2]) / ee : 0.0;
      const bool at_x = !(t > 0.0), at_y = t >= 1.0;
      Candidate k;
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) k.p[c] = at_x ? r[x][c] : (at_y ? r[y][c] : r[x][c] + t * e[c]);
      const double inner =
          k.p[0] * (k.p[0] - 2.0 * sv[0]) + k.p[1] * (k.p[1] - 2.0 * sv[1]) + k.p[2] * (k.p[2] - 2.0 * sv[2]);
      k.key = at_x ? key[x] : (at_y ? key[y] : inner);
      k.u = at_x ? kU[x] : (at_y ? kU[y] : kU[x] + t * (kU[y] - kU[x]));
      k.v = at_x ? kV[x] : (at_y ? kV[y] : kV[x] + t * (kV[y] - kV[x]));
      return k;
    };
    Candidate outer[4], spoke[4];
    CONTACTNN_UNROLL
    for (int i = 0; i < 4; ++i) {
      outer[i] = on_edge(i, (i + 1) % 4);
      spoke[i] = on_edge(i, 4);
    }

    // The running best over the candidates in order, and the winning triangle's parameters of S's projection
    // on its plane (for a triangle without a plane, the winner's own: not beyond). No flag is carried through
    // the selects (GCC 12 does not vectorise a select between two masks): whether P is on the outer boundary
    // is read from its parameters at the end, max(|xi|, |eta|) = 1, as the piecewise-linear map takes the
    // outer boundary, and only it, to the square's boundary.
    double best_key = kInf, best_u = 0.0, best_v = 0.0, best_p[3] = {0.0, 0.0, 0.0}, ext_u = 0.0, ext_v = 0.0;
    CONTACTNN_UNROLL
    for (int k = 0; k < 4; ++k) {
      const int x = k, y = (k + 1) % 4;
      // Triangle X Y O, O at the origin: n = r_X x r_Y (= (Y - X) x (O - X)); S's projection on its plane is
      // lambda_X r_X + lambda_Y r_Y with lambda_X = n . (sv x r_Y) / |n|^2, lambda_Y = n . (r_X x sv) /
      // |n|^2.
      const double* rx = r[x];
      const double* ry = r[y];
      const double n[3] = {rx[1] * ry[2] - rx[2] * ry[1], rx[2] * ry[0] - rx[0] * ry[2],
                           rx[0] * ry[1] - rx[1] * ry[0]};
      const double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
      const double exy = (ry[0] - rx[0]) * (ry[0] - rx[0]) + (ry[1] - rx[1]) * (ry[1] - rx[1]) +
                         (ry[2] - rx[2]) * (ry[2] - rx[2]);
      const double exo = rx[0] * rx[0] + rx[1] * rx[1] + rx[2] * rx[2];
      const double inv_nn = 1.0 / nn;
      const double lam_x = (n[0] * sxr[y][0] + n[1] * sxr[y][1] + n[2] * sxr[y][2]) * inv_nn;
      const double lam_y = -(n[0] * sxr[x][0] + n[1] * sxr[x][1] + n[2] * sxr[x][2]) * inv_nn;
      const double lam_o = 1.0 - lam_x - lam_y;
      const bool planar = nn > 1e-24 * exy * exo;
      const bool inside = planar & (lam_x >= 0.0) & (lam_y >= 0.0) & (lam_o >= 0.0);
      const double tri_u = lam_x * kU[x] + lam_y * kU[y], tri_v = lam_x * kV[x] + lam_y * kV[y];
      Candidate interior;
      CONTACTNN_UNROLL
      for (int c = 0; c < 3; ++c) interior.p[c] = lam_x * rx[c] + lam_y * ry[c];
      const double inner = interior.p[0] * (interior.p[0] - 2.0 * sv[0]) +
                           interior.p[1] * (interior.p[1] - 2.0 * sv[1]) +
                           interior.p[2] * (interior.p[2] - 2.0 * sv[2]);
      interior.key = inside ? inner : kInf;
      interior.u = tri_u;
      interior.v = tri_v;
      const auto consider = [&](const Candidate& cand) {
        const bool take = cand.key < best_key;
        best_key = take ? cand.key : best_key;
        best_u = take ? cand.u : best_u;
        best_v = take ? cand.v : best_v;
        CONTACTNN_UNROLL
        for (int c = 0; c < 3; ++c) best_p[c] = take ? cand.p[c] : best_p[c];
        ext_u = take ? (planar ? tri_u : cand.u) : ext_u;
        ext_v = take ? (planar ? tri_v : cand.v) : ext_v;
      };
      // The candidates of triangle k in order, each shared one where it first appears: a candidate seen
      // before has a key already matched, so with `take` strict it could not win again (the order of the
      // doc).
      consider(interior);
      consider(outer[k]);
      if (k < 3) consider(spoke[y]);
      if (k == 0) consider(spoke[x]);
    }

    const bool boundary = max_of(std::fabs(best_u), std::fabs(best_v)) >= 1.0;
    const bool beyond = max_of(std::fabs(ext_u - best_u), std::fabs(ext_v - best_v)) > margin;
    const bool outside = boundary & beyond;
    // S - P, its length and its side of N = (C - A) x (D - B).
    double g0[3], g1[3], d[3];
    CONTACTNN_UNROLL
    for (int c = 0; c < 3; ++c) {
      g0[c] = r[2][c] - r[0][c];
      g1[c] = r[3][c] - r[1][c];
      d[c] = sv[c] - best_p[c];
    }
    const double big_n[3] = {g0[1] * g1[2] - g0[2] * g1[1], g0[2] * g1[0] - g0[0] * g1[2],
                             g0[0] * g1[1] - g0[1] * g1[0]};
    const double distance = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    gap[l] = d[0] * big_n[0] + d[1] * big_n[1] + d[2] * big_n[2] < 0.0 ? -distance : distance;
    const bool active = s.status[l] == kOk;
    s.u[l] = active ? best_u : s.u[l];
    s.v[l] = active ? best_v : s.v[l];
    s.status[l] = !active ? s.status[l] : (outside ? kOutside : kOk);
  }
}

}  // namespace contactnn::search::detail
