/* canonical_frame_ties.h (part of canonical_frame.h): every canonical form of a query on a tie. */
#ifndef CONTACTNN_CANONICAL_FRAME_TIES_H
#define CONTACTNN_CANONICAL_FRAME_TIES_H

#include "search/canonical_frame_lane.h"

/* ---- Ties: every canonical form of a query (geometry::canonical_forms) ----
 *
 * A query on a tie (info row 5 of the block pass: another node as near S, |AB| = |AD| with S on the diagonal,
 * or, for Gregory, S and C on the plane of A, B, D) has several canonical configurations that are the same
 * problem. A network's answer is the mean of its predictions, mapped back to the caller's node order, over
 * those of them in the network's domain (over all of them, flagged out of the domain, when none is): so that
 * the answer does not depend on the node order the caller happens to use (SPEC 4 takes the first tied node in
 * the caller's order; with a network that would make the answer depend on it), and no form the network was
 * not trained on enters it. Ties are rare on random queries and common on
 * structured meshes (a slave midway between two master nodes). cnn_cf_forms makes the forms of one query; a
 * block of queries can instead list each tie lane's symmetries (cnn_cf_symmetries) and run cnn_cf_lane with
 * each one forced, a block of forms at a time, as lib/search does: the same forms, bit for bit. */

/* True when lane's info row 5 `tie` asks for cnn_cf_forms. */
CNN_CF_INLINE int cnn_cf_needs_forms(double tie, int gregory) {
  const int code = (int)tie;
  return (code & 1) | (gregory & (code >> 1));
}

/* The symmetries geometry::canonical_symmetries lists for query `x` (15 or more values, SPEC 6 order): one
 * per node tied for nearest, in the caller's order, two (no mirror, mirror) for such a node with |AB| = |AD|
 * and S on the diagonal. The arithmetic of cnn_cf_lane's symmetry step on the query scaled by the power of
 * two that brings its largest coordinate into [0.5, 1) (exact; nothing under- or overflows). sym[k] =
 * rotation + 4 * mirror; returns the count (1 to 8). */
static inline int cnn_cf_symmetries(const double* CNN_CF_RESTRICT x_in, int* CNN_CF_RESTRICT sym) {
  const double eps = 2.220446049250313e-16;
  const double shrink = (1.0 - 1e-12) * (1.0 - 1e-12);
  double x[15], q[4], big = 0.0, tie_noise, nearest_plus, reach;
  int k, r, e = 0, count = 0;
  for (k = 0; k < 15; ++k) big = cnn_cf_max(big, fabs(x_in[k]));
  if (big > 0.0 && big <= 1.7976931348623157e308) (void)frexp(big, &e);
  if (e > -1000 && e < 1000) {
    /* A product with an exact power of two rounds as ldexp does; one call instead of sixteen. */
    const double p = ldexp(1.0, -e);
    for (k = 0; k < 15; ++k) x[k] = x_in[k] * p;
    big = big * p;
  } else {
    for (k = 0; k < 15; ++k) x[k] = ldexp(x_in[k], -e);
    big = ldexp(big, -e);
  }
  tie_noise = 16.0 * eps * big;
  for (r = 0; r < 4; ++r) {
    const double sx = x[12] - x[3 * r], sy = x[13] - x[3 * r + 1], sz = x[14] - x[3 * r + 2];
    q[r] = sx * sx + sy * sy + sz * sz;
  }
  nearest_plus = sqrt(cnn_cf_min(cnn_cf_min(q[0], q[1]), cnn_cf_min(q[2], q[3]))) + tie_noise;
  reach = nearest_plus * nearest_plus;
  for (r = 0; r < 4; ++r) {
    const double* a = x + 3 * r;
    const double* b = x + 3 * ((r + 1) % 4);
    const double* d = x + 3 * ((r + 3) % 4);
    double sax, say, saz, e_bx, e_by, e_bz, e_dx, e_dy, e_dz, len_b, len_d, xbx, xby, xbz, xdx, xdy, xdz,
        to_b, to_d;
    if (!(q[r] * shrink <= reach)) continue;
    sax = x[12] - a[0];
    say = x[13] - a[1];
    saz = x[14] - a[2];
    e_bx = b[0] - a[0];
    e_by = b[1] - a[1];
    e_bz = b[2] - a[2];
    e_dx = d[0] - a[0];
    e_dy = d[1] - a[1];
    e_dz = d[2] - a[2];
    len_b = sqrt(e_bx * e_bx + e_by * e_by + e_bz * e_bz);
    len_d = sqrt(e_dx * e_dx + e_dy * e_dy + e_dz * e_dz);
    if (!(fabs(len_d - len_b) <= 1e-12 * cnn_cf_max(len_d, len_b) + tie_noise)) {
      sym[count++] = r + (len_d > len_b ? 4 : 0);
      continue;
    }
    xbx = say * e_bz - saz * e_by;
    xby = saz * e_bx - sax * e_bz;
    xbz = sax * e_by - say * e_bx;
    xdx = say * e_dz - saz * e_dy;
    xdy = saz * e_dx - sax * e_dz;
    xdz = sax * e_dy - say * e_dx;
    to_b = sqrt(xbx * xbx + xby * xby + xbz * xbz) * (1.0 / len_b);
    to_d = sqrt(xdx * xdx + xdy * xdy + xdz * xdz) * (1.0 / len_d);
    if (!(fabs(to_d - to_b) <= 1e-12 * cnn_cf_max(to_d, to_b) + tie_noise)) {
      sym[count++] = r + (to_d < to_b ? 4 : 0);
    } else {
      sym[count++] = r;
      sym[count++] = r + 4;
    }
  }
  return count;
}

/* One form of query `x` (contiguous, 15 or 27 values): cnn_cf_lane (forced or not), redone scaled where the
 * lane needs it. f: 16 values, nrm: 12, info: CNN_CF_INFO_ROWS. */
static inline void cnn_cf_form(const double* CNN_CF_RESTRICT x, int gregory, int forced, int sym, int other_z,
                               double* CNN_CF_RESTRICT f, double* CNN_CF_RESTRICT nrm,
                               double* CNN_CF_RESTRICT info) {
  cnn_cf_lane(x, 1, gregory, forced, sym, other_z, f, nrm, info, 1);
  if (info[4] != 0.0) cnn_cf_lane_scaled(x, 1, gregory, forced, sym, other_z, f, nrm, info, 1);
}

/* Every canonical form of query `x` (contiguous, 15 or 27 values), in geometry::canonical_forms' order: form
 * 0 is the block pass's (cnn_cf_lane unforced), then for each symmetry of cnn_cf_symmetries and, Gregory on a
 * z tie of form 0, each orientation of z, the forms that exist (status ok). Form k's features are at f[16 k],
 * its normals at nrm[12 k], its info rows at info[CNN_CF_INFO_ROWS k]. Returns the count (1 to
 * CNN_CF_MAX_FORMS); only form 0 when its status is not ok. */
static inline int cnn_cf_forms(const double* CNN_CF_RESTRICT x, int gregory, double* CNN_CF_RESTRICT f,
                               double* CNN_CF_RESTRICT nrm, double* CNN_CF_RESTRICT info) {
  int sym[8], k, z, count = 1, sym0, z_ties, tied;
  cnn_cf_form(x, gregory, 0, 0, 0, f, nrm, info);
  if (info[0] != (double)CNN_CF_STATUS_OK) return 1;
  sym0 = (int)info[1];
  z_ties = gregory & ((int)info[5] >> 1);
  tied = cnn_cf_symmetries(x, sym);
  for (k = 0; k < tied; ++k) {
    for (z = 0; z <= z_ties && count < CNN_CF_MAX_FORMS; ++z) {
      double* fk = f + 16 * count;
      double* nk = nrm + 12 * count;
      double* ik = info + CNN_CF_INFO_ROWS * count;
      if (sym[k] == sym0 && z == 0) continue; /* form 0 */
      cnn_cf_form(x, gregory, 1, sym[k], z, fk, nk, ik);
      if (ik[0] == (double)CNN_CF_STATUS_OK) ++count;
    }
  }
  return count;
}

/* Canonical local coordinates (x, y) -> the caller's for symmetry code `sym` (info row 1): the inverse of the
 * relabelling (SquareSymmetry::to_caller). `centre`: 0 for (xi, eta), 0.5 for (u, v). Branch-free. */
CNN_CF_INLINE void cnn_cf_to_caller(double sym, double centre, double* CNN_CF_RESTRICT px,
                                    double* CNN_CF_RESTRICT py) {
  const int mirror = sym >= 4.0;
  const double rotation = mirror ? sym - 4.0 : sym;
  const double x = *px - centre, y = *py - centre;
  const double sx = mirror ? y : x, sy = mirror ? x : y;
  /* rot(x, y) = (-y, x) applied `rotation` times. */
  *px = (rotation == 0.0 ? sx : rotation == 1.0 ? -sy : rotation == 2.0 ? -sx : sy) + centre;
  *py = (rotation == 0.0 ? sy : rotation == 1.0 ? sx : rotation == 2.0 ? -sy : -sx) + centre;
}
#endif /* CONTACTNN_CANONICAL_FRAME_TIES_H */
