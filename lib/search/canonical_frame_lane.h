/* canonical_frame_lane.h (part of canonical_frame.h): the canonical frame of one lane in double
 * (cnn_cf_lane), in the steps canonical_frame.h lists, each a function always inlined into the lane; the lane
 * redone with its magnitudes scaled (cnn_cf_lane_scaled); the block (cnn_canonicalise_block). */
#ifndef CONTACTNN_CANONICAL_FRAME_LANE_H
#define CONTACTNN_CANONICAL_FRAME_LANE_H

#include "search/canonical_frame_geometry.h"

/* A lane's values: nodes A..D and S, the node normals (Gregory; else (0, 0, 1) each). */
struct cnn_cf_query {
  double ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, sx, sy, sz;
  double nax, nay, naz, nbx, nby, nbz, ncx, ncy, ncz, ndx, ndy, ndz;
};

/* The canonical relabelling in double (step 2); CNN_CF_CANON_FIELDS, then: */
struct cnn_cf_canon {
  CNN_CF_CANON_FIELDS(double);
  double mirror;               /* 0 or 1 */
  double length_ab, length_ad; /* |AB|, |AD|, canonical */
};

CNN_CF_DEFINE_LOAD_NODES(cnn_cf_load_nodes, cnn_cf_query, double)
CNN_CF_DEFINE_ROTATE(cnn_cf_rotate, cnn_cf_query, cnn_cf_edges, double)
CNN_CF_DEFINE_MIRROR(cnn_cf_mirror, cnn_cf_query, cnn_cf_edges, cnn_cf_canon)
CNN_CF_DEFINE_FRAME(cnn_cf_axes, cnn_cf_canon, cnn_cf_frame, double, sqrt)
CNN_CF_DEFINE_CORNERS(cnn_cf_segment_corners, cnn_cf_corners, double, cnn_cf_max, cnn_cf_min)

/* Quantity k at in[k * is]. */
CNN_CF_INLINE void cnn_cf_load(const double* CNN_CF_RESTRICT in, int is, int gregory,
                               struct cnn_cf_query* CNN_CF_RESTRICT q) {
  cnn_cf_load_nodes(in, is, q);
  q->sx = in[12 * is];
  q->sy = in[13 * is];
  q->sz = in[14 * is];
  q->nax = gregory ? in[15 * is] : 0.0;
  q->nay = gregory ? in[16 * is] : 0.0;
  q->naz = gregory ? in[17 * is] : 1.0;
  q->nbx = gregory ? in[18 * is] : 0.0;
  q->nby = gregory ? in[19 * is] : 0.0;
  q->nbz = gregory ? in[20 * is] : 1.0;
  q->ncx = gregory ? in[21 * is] : 0.0;
  q->ncy = gregory ? in[22 * is] : 0.0;
  q->ncz = gregory ? in[23 * is] : 1.0;
  q->ndx = gregory ? in[24 * is] : 0.0;
  q->ndy = gregory ? in[25 * is] : 0.0;
  q->ndz = gregory ? in[26 * is] : 1.0;
}

/* 1. Finite: the sum of the values is finite exactly when every value is, as long as no sum overflows; a lane
 *    with a magnitude beyond 1e50 (coordinates) or a normal beyond it goes through cnn_cf_lane_scaled, whose
 *    values are scaled first, so the sum cannot overflow here. 0 when finite. */
CNN_CF_INLINE double cnn_cf_finite(const struct cnn_cf_query* CNN_CF_RESTRICT q) {
  return (q->ax + q->ay + q->az + q->bx + q->by + q->bz + q->cx + q->cy + q->cz + q->dx + q->dy + q->dz +
          q->sx + q->sy + q->sz + q->nax + q->nay + q->naz + q->nbx + q->nby + q->nbz + q->ncx + q->ncy +
          q->ncz + q->ndx + q->ndy + q->ndz) *
         0.0;
}

/* max |x| over the nodes A..D. */
CNN_CF_INLINE double cnn_cf_big_nodes(const struct cnn_cf_query* CNN_CF_RESTRICT q) {
  const double big_nodes =
      cnn_cf_max(cnn_cf_max(cnn_cf_max(fabs(q->ax), fabs(q->ay)), cnn_cf_max(fabs(q->az), fabs(q->bx))),
                 cnn_cf_max(cnn_cf_max(fabs(q->by), fabs(q->bz)), cnn_cf_max(fabs(q->cx), fabs(q->cy))));
  return cnn_cf_max(big_nodes,
                    cnn_cf_max(cnn_cf_max(fabs(q->cz), fabs(q->dx)), cnn_cf_max(fabs(q->dy), fabs(q->dz))));
}

/* 2a. Canonical A (geometry::canonical_symmetry): the first node nearest S, distances within 1e-12 relative
 *     plus tie_noise a tie (forced: node forced_sym & 3). Sets c's t0, t1, t2 and rot; returns how many nodes
 *     are as near S as the nearest. */
CNN_CF_INLINE int cnn_cf_nearest(const struct cnn_cf_query* CNN_CF_RESTRICT q, int forced, int forced_sym,
                                 double tie_noise, struct cnn_cf_canon* CNN_CF_RESTRICT c) {
  const double s0x = q->sx - q->ax, s0y = q->sy - q->ay, s0z = q->sz - q->az;
  const double s1x = q->sx - q->bx, s1y = q->sy - q->by, s1z = q->sz - q->bz;
  const double s2x = q->sx - q->cx, s2y = q->sy - q->cy, s2z = q->sz - q->cz;
  const double s3x = q->sx - q->dx, s3y = q->sy - q->dy, s3z = q->sz - q->dz;
  const double q0 = s0x * s0x + s0y * s0y + s0z * s0z, q1 = s1x * s1x + s1y * s1y + s1z * s1z;
  const double q2 = s2x * s2x + s2y * s2y + s2z * s2z, q3 = s3x * s3x + s3y * s3y + s3z * s3z;
  /* dist_i ties the nearest when dist_i (1 - 1e-12) <= nearest + noise; compared squared. */
  const double nearest_plus = sqrt(cnn_cf_min(cnn_cf_min(q0, q1), cnn_cf_min(q2, q3))) + tie_noise;
  const double reach = nearest_plus * nearest_plus;
  const double shrink = (1.0 - 1e-12) * (1.0 - 1e-12);
  const int n0 = q0 * shrink <= reach, n1 = q1 * shrink <= reach, n2 = q2 * shrink <= reach,
            n3 = q3 * shrink <= reach;
  const int fr = forced_sym & 3;
  c->t0 = forced ? fr == 0 : n0;
  c->t1 = forced ? fr == 1 : n1;
  c->t2 = forced ? fr == 2 : n2;
  c->rot = c->t0 ? 0.0 : c->t1 ? 1.0 : c->t2 ? 2.0 : 3.0;
  return n0 + n1 + n2 + n3;
}

/* 2b. The nodes from canonical A on, its edges to the next (B) and the previous (D) node, and the mirror when
 *     |AD| > |AB| (on a tie: S nearer the line AD than the line AB; forced: forced_sym's). Sets the rest of
 * c; returns 1 when |AD| = |AB| with S on the diagonal (another canonical form). */
CNN_CF_INLINE int cnn_cf_relabel(const struct cnn_cf_query* CNN_CF_RESTRICT q, int forced, int forced_sym,
                                 double tie_noise, struct cnn_cf_canon* CNN_CF_RESTRICT c) {
  struct cnn_cf_edges e;
  double sax, say, saz, len_b, len_d, inv_b, inv_d, xbx, xby, xbz, xdx, xdy, xdz, to_b, to_d;
  int lengths_tie, line_tie, mir;
  cnn_cf_rotate(q, c->t0, c->t1, c->t2, &e);
  sax = q->sx - e.pax;
  say = q->sy - e.pay;
  saz = q->sz - e.paz;
  len_b = sqrt(e.e_bx * e.e_bx + e.e_by * e.e_by + e.e_bz * e.e_bz);
  len_d = sqrt(e.e_dx * e.e_dx + e.e_dy * e.e_dy + e.e_dz * e.e_dz);
  inv_b = 1.0 / len_b;
  inv_d = 1.0 / len_d;
  lengths_tie = fabs(len_d - len_b) <= 1e-12 * cnn_cf_max(len_d, len_b) + tie_noise;
  xbx = say * e.e_bz - saz * e.e_by;
  xby = saz * e.e_bx - sax * e.e_bz;
  xbz = sax * e.e_by - say * e.e_bx;
  xdx = say * e.e_dz - saz * e.e_dy;
  xdy = saz * e.e_dx - sax * e.e_dz;
  xdz = sax * e.e_dy - say * e.e_dx;
  to_b = sqrt(xbx * xbx + xby * xby + xbz * xbz) * inv_b;
  to_d = sqrt(xdx * xdx + xdy * xdy + xdz * xdz) * inv_d;
  line_tie = fabs(to_d - to_b) <= 1e-12 * cnn_cf_max(to_d, to_b) + tie_noise;
  c->mirror = forced        ? (double)(forced_sym >> 2)
              : lengths_tie ? ((!line_tie & (to_d < to_b)) ? 1.0 : 0.0)
                            : (len_d > len_b ? 1.0 : 0.0);
  mir = c->mirror != 0.0;
  cnn_cf_mirror(q, &e, mir, c);
  c->asx = sax;
  c->asy = say;
  c->asz = saz;
  c->length_ab = mir ? len_d : len_b;
  c->length_ad = mir ? len_b : len_d;
  c->scale = mir ? inv_d : inv_b;
  return lengths_tie & line_tie;
}

/* 3. The frame exists: |AB| positive and finite, not negligible beside |AD|, and A, B, D not collinear. */
CNN_CF_INLINE int cnn_cf_frame_exists(const struct cnn_cf_canon* CNN_CF_RESTRICT c,
                                      const struct cnn_cf_frame* CNN_CF_RESTRICT fr) {
  const double length_ab = c->length_ab, min_normal = 1e-12 * cnn_cf_max(c->length_ad, length_ab);
  return (length_ab > 0.0) & (length_ab <= 1.7976931348623157e308) & !(length_ab <= 1e-12 * c->length_ad) &
         (fr->normal_sq > min_normal * min_normal);
}

/* 5. A collapsed segment, judged against the world coordinates' rounding (geometry::is_degenerate_segment on
 *    the local nodes 0, (1,0,0), C, D with noise16 = 16 eps max|node| * scale), in squared form. */
CNN_CF_INLINE int cnn_cf_collapsed(double xc, double yc, double zc, double xd, double yd, double noise16) {
  struct cnn_cf_corners k;
  double noise_sq, coincident_sq, flat_sq, wx, wy;
  int fold_a, fold_b, fold_c, fold_d;
  cnn_cf_segment_corners(xc, yc, zc, xd, yd, &k);
  noise_sq = noise16 * noise16;
  coincident_sq = cnn_cf_max(1e-20 * k.longest_sq, noise_sq);
  flat_sq = cnn_cf_max(1e-24 * k.longest_sq, noise_sq) * k.longest_sq;
  /* Twice the area: |(C - A) x (D - B)|. */
  wx = yc * 0.0 - zc * yd;
  wy = zc * (xd - 1.0) - xc * 0.0;
  /* A corner of zero angle: next . prev > 0 and next x prev ~ 0. At A: next B = (1,0,0), prev D. */
  fold_a = (xd > 0.0) & !(yd * yd > flat_sq);
  /* At B: next C - B, prev A - B = (-1, 0, 0). */
  fold_b = (-(xc - 1.0) > 0.0) & !(zc * zc + yc * yc > flat_sq);
  /* At C: next D - C, prev B - C. */
  fold_c = (k.ncdx * k.pcbx + k.ncdy * k.pcby + k.ncdz * k.pcbz > 0.0) &
           !(k.kcx * k.kcx + k.kcy * k.kcy + k.kcz * k.kcz > flat_sq);
  /* At D: next A - D = -D, prev C - D. */
  fold_d = (-xd * k.pdcx - yd * k.pdcy > 0.0) & !(k.kdx * k.kdx + k.kdy * k.kdy + k.kdz * k.kdz > flat_sq);
  return !(k.longest_sq > 0.0) | !(k.shortest_sq > coincident_sq) |
         !(0.25 * (wx * wx + wy * wy + k.wz * k.wz) > flat_sq) | fold_a | fold_b | fold_c | fold_d;
}

/* 6. Gregory: the node normals in the canonical order, rotated into the frame oriented by zsign; f rows 8..15
 *    their slopes, nrm rows 0..11 the normals, turned to the +z side. Front: n_z > max(1e-12, noise) for the
 *    unit normal, i.e. w_z > min_nz |n| for the rotated one; all on the back side: all reversed. Otherwise,
 *    or a zero normal, *bad = 1; a normal outside [1e-50, 1e50] in length, *rescale = 1. */
CNN_CF_INLINE void cnn_cf_normals(const struct cnn_cf_query* CNN_CF_RESTRICT q,
                                  const struct cnn_cf_canon* CNN_CF_RESTRICT c,
                                  const struct cnn_cf_frame* CNN_CF_RESTRICT fr, double zsign, double noise16,
                                  double* CNN_CF_RESTRICT f, double* CNN_CF_RESTRICT nrm, int os,
                                  double* CNN_CF_RESTRICT bad, double* CNN_CF_RESTRICT rescale) {
  const int t0 = c->t0, t1 = c->t1, t2 = c->t2, mir = c->mir;
  const double min_nz = cnn_cf_max(1e-12, noise16);
  const double m_nz = min_nz * min_nz;
  const double e1x = fr->e1x, e1y = fr->e1y, e1z = fr->e1z, e2x = fr->e2x, e2y = fr->e2y, e2z = fr->e2z;
  const double f3x = zsign * fr->e3x, f3y = zsign * fr->e3y, f3z = zsign * fr->e3z;
  const double c0x = CNN_CF_PICK(t0, t1, t2, q->nax, q->nbx, q->ncx, q->ndx);
  const double c0y = CNN_CF_PICK(t0, t1, t2, q->nay, q->nby, q->ncy, q->ndy);
  const double c0z = CNN_CF_PICK(t0, t1, t2, q->naz, q->nbz, q->ncz, q->ndz);
  const double r1x = CNN_CF_PICK(t0, t1, t2, q->nbx, q->ncx, q->ndx, q->nax);
  const double r1y = CNN_CF_PICK(t0, t1, t2, q->nby, q->ncy, q->ndy, q->nay);
  const double r1z = CNN_CF_PICK(t0, t1, t2, q->nbz, q->ncz, q->ndz, q->naz);
  const double c2x = CNN_CF_PICK(t0, t1, t2, q->ncx, q->ndx, q->nax, q->nbx);
  const double c2y = CNN_CF_PICK(t0, t1, t2, q->ncy, q->ndy, q->nay, q->nby);
  const double c2z = CNN_CF_PICK(t0, t1, t2, q->ncz, q->ndz, q->naz, q->nbz);
  const double r3x = CNN_CF_PICK(t0, t1, t2, q->ndx, q->nax, q->nbx, q->ncx);
  const double r3y = CNN_CF_PICK(t0, t1, t2, q->ndy, q->nay, q->nby, q->ncy);
  const double r3z = CNN_CF_PICK(t0, t1, t2, q->ndz, q->naz, q->nbz, q->ncz);
  const double c1x = mir ? r3x : r1x, c1y = mir ? r3y : r1y, c1z = mir ? r3z : r1z;
  const double c3x = mir ? r1x : r3x, c3y = mir ? r1y : r3y, c3z = mir ? r1z : r3z;
  const double l0 = c0x * c0x + c0y * c0y + c0z * c0z, l1 = c1x * c1x + c1y * c1y + c1z * c1z;
  const double l2 = c2x * c2x + c2y * c2y + c2z * c2z, l3 = c3x * c3x + c3y * c3y + c3z * c3z;
  const double w0x = e1x * c0x + e1y * c0y + e1z * c0z, w0y = e2x * c0x + e2y * c0y + e2z * c0z,
               w0z = f3x * c0x + f3y * c0y + f3z * c0z;
  const double w1x = e1x * c1x + e1y * c1y + e1z * c1z, w1y = e2x * c1x + e2y * c1y + e2z * c1z,
               w1z = f3x * c1x + f3y * c1y + f3z * c1z;
  const double w2x = e1x * c2x + e1y * c2y + e1z * c2z, w2y = e2x * c2x + e2y * c2y + e2z * c2z,
               w2z = f3x * c2x + f3y * c2y + f3z * c2z;
  const double w3x = e1x * c3x + e1y * c3y + e1z * c3z, w3y = e2x * c3x + e2y * c3y + e2z * c3z,
               w3z = f3x * c3x + f3y * c3y + f3z * c3z;
  const int away0 = w0z * w0z > m_nz * l0, away1 = w1z * w1z > m_nz * l1;
  const int away2 = w2z * w2z > m_nz * l2, away3 = w3z * w3z > m_nz * l3;
  const int front = (w0z > 0.0) & (w1z > 0.0) & (w2z > 0.0) & (w3z > 0.0) & away0 & away1 & away2 & away3;
  const int back = (w0z < 0.0) & (w1z < 0.0) & (w2z < 0.0) & (w3z < 0.0) & away0 & away1 & away2 & away3;
  const double side = back ? -1.0 : 1.0;
  const double i0 = 1.0 / w0z, i1 = 1.0 / w1z, i2 = 1.0 / w2z, i3 = 1.0 / w3z;
  *bad = (front | back) ? *bad : 1.0;
  *bad = ((l0 > 0.0) & (l1 > 0.0) & (l2 > 0.0) & (l3 > 0.0)) ? *bad : 1.0;
  *rescale = ((l0 > 1e-100) & (l0 < 1e100) & (l1 > 1e-100) & (l1 < 1e100) & (l2 > 1e-100) & (l2 < 1e100) &
              (l3 > 1e-100) & (l3 < 1e100))
                 ? *rescale
                 : 1.0;
  f[8 * os] = w0x * i0;
  f[9 * os] = w0y * i0;
  f[10 * os] = w1x * i1;
  f[11 * os] = w1y * i1;
  f[12 * os] = w2x * i2;
  f[13 * os] = w2y * i2;
  f[14 * os] = w3x * i3;
  f[15 * os] = w3y * i3;
  nrm[0 * os] = side * w0x;
  nrm[1 * os] = side * w0y;
  nrm[2 * os] = side * w0z;
  nrm[3 * os] = side * w1x;
  nrm[4 * os] = side * w1y;
  nrm[5 * os] = side * w1z;
  nrm[6 * os] = side * w2x;
  nrm[7 * os] = side * w2y;
  nrm[8 * os] = side * w2z;
  nrm[9 * os] = side * w3x;
  nrm[10 * os] = side * w3y;
  nrm[11 * os] = side * w3z;
}

/* One lane. Reads quantity k at in[k * is], writes at f[k * os], nrm[k * os], info[k * os] (CNN_CF_INFO_ROWS
 * rows; row 4 receives 1 when the lane must be redone by cnn_cf_lane_scaled). `forced` 0: the canonical form
 * (form 0); 1: the form of symmetry `forced_sym` (rotation + 4 * mirror) with the other orientation of z on a
 * z tie when `other_z` (cnn_cf_forms). The loops over lanes pass forced = 0, a constant. */
CNN_CF_INLINE void cnn_cf_lane(const double* CNN_CF_RESTRICT in, int is, int gregory, int forced,
                               int forced_sym, int other_z, double* CNN_CF_RESTRICT f,
                               double* CNN_CF_RESTRICT nrm, double* CNN_CF_RESTRICT info, int os) {
  const double eps = 2.220446049250313e-16;
  struct cnn_cf_query q;
  struct cnn_cf_canon c;
  struct cnn_cf_frame fr;
  double finite, big_nodes, big, bad, rescale, z_tol, zsign, zc, zs, noise16;
  int sym_tie, s_on, z_tie;
  cnn_cf_load(in, is, gregory, &q);
  /* 1. Finite and magnitudes: beyond [1e-50, 1e50], the lane is redone scaled. */
  finite = cnn_cf_finite(&q);
  big_nodes = cnn_cf_big_nodes(&q);
  big = cnn_cf_max(big_nodes, cnn_cf_max(fabs(q.sx), cnn_cf_max(fabs(q.sy), fabs(q.sz))));
  rescale = ((big > 1e50) | (big < 1e-50)) ? 1.0 : 0.0;
  /* 2. The symmetry; another canonical form exists when another node is as near S, or |AD| = |AB| with S on
   *    the diagonal. */
  sym_tie = cnn_cf_nearest(&q, forced, forced_sym, 16.0 * eps * big, &c) > 1;
  sym_tie |= cnn_cf_relabel(&q, forced, forced_sym, 16.0 * eps * big, &c);
  /* 3. The frame on the canonical A, B, D, and 4. C, D and S in it. */
  cnn_cf_axes(&c, &fr);
  /* z oriented so that S (on the plane: C) is on its + side; a height within 1e-12 plus the rounding of the
   * world coordinates counts as 0, so that the orientation does not depend on where the query is placed.
   * Both on the plane: a z tie, no flip (the other orientation is the form with other_z). */
  z_tol = 1e-12 + 16.0 * eps * big * c.scale;
  s_on = fabs(fr.zs0) <= z_tol;
  z_tie = s_on & (fabs(fr.zc0) <= z_tol);
  zsign = (z_tie ? other_z : (s_on ? fr.zc0 < 0.0 : fr.zs0 < 0.0)) ? -1.0 : 1.0;
  zc = zsign * fr.zc0;
  zs = zsign * fr.zs0;
  /* 5. A collapsed segment. */
  noise16 = 16.0 * (eps * big_nodes * c.scale);
  bad =
      (cnn_cf_frame_exists(&c, &fr) & !cnn_cf_collapsed(fr.xc, fr.yc, zc, fr.xd, fr.yd, noise16)) ? 0.0 : 1.0;
  f[0 * os] = fr.xc;
  f[1 * os] = fr.yc;
  f[2 * os] = zc;
  f[3 * os] = fr.xd;
  f[4 * os] = fr.yd;
  f[5 * os] = fr.xs;
  f[6 * os] = fr.ys;
  f[7 * os] = zs;
  /* 6. Gregory: the node normals. */
  if (gregory) cnn_cf_normals(&q, &c, &fr, zsign, noise16, f, nrm, os, &bad, &rescale);
  info[0 * os] = finite == 0.0 ? (bad != 0.0 ? (double)CNN_CF_STATUS_DEGENERATE : (double)CNN_CF_STATUS_OK)
                               : (double)CNN_CF_STATUS_INVALID;
  info[1 * os] = c.rot + 4.0 * c.mirror;
  info[2 * os] = (c.mir ? -1.0 : 1.0) * zsign;
  info[3 * os] = c.scale;
  info[4 * os] = rescale;
  info[5 * os] = (double)(sym_tie + 2 * z_tie);
}

/* A lane whose magnitudes are extreme: the coordinates scaled by one power of two (exact), each normal by its
 * own, then cnn_cf_lane. A difference of two world coordinates that overflows makes the lane degenerate. */
static inline void cnn_cf_lane_scaled(const double* CNN_CF_RESTRICT in, int is, int gregory, int forced,
                                      int forced_sym, int other_z, double* CNN_CF_RESTRICT f,
                                      double* CNN_CF_RESTRICT nrm, double* CNN_CF_RESTRICT info, int os) {
  double x[27], m = 0.0;
  int k, i, j, e = 0, overflow = 0;
  const int count = gregory ? 27 : 15;
  for (k = 0; k < count; ++k) x[k] = in[k * is];
  for (i = 0; i < 5; ++i) {
    for (j = i + 1; j < 5; ++j) {
      for (k = 0; k < 3; ++k) overflow |= !(fabs(x[3 * i + k] - x[3 * j + k]) <= 1.7976931348623157e308);
    }
  }
  for (k = 0; k < 15; ++k) m = cnn_cf_max(m, fabs(x[k]));
  (void)frexp(m, &e);
  for (k = 0; k < 15; ++k) x[k] = ldexp(x[k], -e);
  for (i = 0; gregory && i < 4; ++i) {
    double mn = 0.0;
    int en = 0;
    for (k = 0; k < 3; ++k) mn = cnn_cf_max(mn, fabs(x[15 + 3 * i + k]));
    (void)frexp(mn, &en);
    for (k = 0; k < 3; ++k) x[15 + 3 * i + k] = ldexp(x[15 + 3 * i + k], -en);
  }
  cnn_cf_lane(x, 1, gregory, forced, forced_sym, other_z, f, nrm, info, os);
  if (overflow && info[0] == (double)CNN_CF_STATUS_OK) info[0] = (double)CNN_CF_STATUS_DEGENERATE;
  info[3 * os] = ldexp(info[3 * os], -e); /* 1 / |AB| of the coordinates as given */
  info[4 * os] = 0.0;
}

/* The block: every lane in the vectorised pass, then the rare lanes that need scaling. `info` has
 * CNN_CF_INFO_ROWS rows. Always inlined, as cnn_domain_block: GCC 12 otherwise makes a clone for the constant
 * arguments of one caller (a constant domain, n = 1) whose lane loop it does not vectorise, and uses it for
 * the block calls too (an exported header's batch ran its domain test scalar: 2.6x the library's time). */
CNN_CF_INLINE void cnn_canonicalise_block(int n, int gregory, const double* CNN_CF_RESTRICT in,
                                          double* CNN_CF_RESTRICT f, double* CNN_CF_RESTRICT nrm,
                                          double* CNN_CF_RESTRICT info) {
  int l;
  CNN_CF_IVDEP
  for (l = 0; l < n; ++l) cnn_cf_lane(in + l, n, gregory, 0, 0, 0, f + l, nrm + l, info + l, n);
  for (l = 0; l < n; ++l) {
    if (info[4 * n + l] != 0.0) cnn_cf_lane_scaled(in + l, n, gregory, 0, 0, 0, f + l, nrm + l, info + l, n);
  }
}

#endif /* CONTACTNN_CANONICAL_FRAME_LANE_H */
