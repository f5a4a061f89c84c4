/* canonical_frame_float.h (part of canonical_frame.h): the canonical frame and the domain test of one
 * bilinear lane in float (cnn_cff_lane), for a float network; canonical_frame_float_block.h runs it over
 * blocks. */
#ifndef CONTACTNN_CANONICAL_FRAME_FLOAT_H
#define CONTACTNN_CANONICAL_FRAME_FLOAT_H

#include "search/canonical_frame_domain.h"
#include "search/canonical_frame_geometry.h"

/* ---- The frame and the domain test in float, for a bilinear float network (cnn_canonicalise_domain_block_f)
 * ----
 *
 * A float network reads its inputs in float, yet the frame and the domain test above run in double: they
 * decide ties and thresholds at 1e-12. This pass computes the features in float (16 lanes per 512-bit vector
 * instead of 8) and keeps every decision exact: a lane whose float arithmetic cannot decide one of them is
 * left to the double pass (cnn_canonicalise_block and cnn_domain_block on the gathered lanes), so status,
 * symmetry, orientation, tie code and domain verdict are those of the double pass on every lane, and only the
 * features of the lanes decided in float differ, by float rounding: within delta = 32 u (1 + R) / sin(angle
 * at A) of the double pass's, u = 2^-24, R the query's extent over |AB| (measured on random lanes up to 15 u
 * (1 + F) / sin(angle at A), F the largest feature).
 *
 * Each query's nodes are taken relative to its slave node S and scaled by the power of two that brings max
 * |S| into [0.5, 1) (exact), so the pass gives the same bits in every node order and at every power-of-two
 * scale, as the double pass does. A lane is decided in float when (else it goes to the double pass):
 *  - its values are finite, max |S| lies in [1e-290, 1e290] (a slave at the origin goes to the double pass),
 * the scaled nodes lie within [1e-12, 1e12] of S, |AB| is at least 1e-6 of the query's distance from the
 * origin (so that the double pass's noise terms, 16 eps max|x|, stay far below the margins below), and the
 * extent R is below 1e4;
 *  - one node is nearer S than the others by a margin (256 u max|x - A|^2 in the squared distances), |AB|^2
 * and |AD|^2 differ by that margin, |AD|^2 >= 1e-6 |AB|^2 and sin^2(angle at A) >= 1e-4: no tie, the mirror
 *    decided, the frame well conditioned (so square elements, |AB| = |AD|, go to the double pass);
 *  - |z_S| exceeds 2 delta plus the double pass's z tolerance: S off the plane on a known side (a slave node
 * on the master's plane, touching contact, goes to the double pass);
 *  - the segment is far from collapsed: every side and diagonal squared above 1e-6 of the longest plus its
 * error bound, every corner's cross product above 1e-7 of the longest squared plus its error bound;
 *  - with the domain: every test of cnn_domain_lane decided beyond its error bound (from the test's partial
 *    derivatives times delta, twice over, plus rounding), or one failed beyond it.
 * A domain with angle bounds (a Gregory study's) is not decided in float: the whole block takes the double
 * pass. Lanes left to the double pass get their bits from it alone, as in a block of any width; lanes decided
 * in float get theirs from their own values alone: a query gives the same bits alone and in a block. On
 * random queries of the paper's bilinear domain, placed at random, with bilinear-8's domain, 2 lanes in 100
 * go to the double pass (mostly corners at A of under a degree); lib/search gathers them from many blocks
 * (LocalSearch::run), an exported header redoes them in each block (cnn_canonicalise_domain_block_f). */

#define CNN_CFF_MAX_LANES 64

/* A lane's nodes relative to S, scaled (rel's 12 rows). */
struct cnn_cff_query {
  float ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz;
};

/* The canonical relabelling in float; CNN_CF_CANON_FIELDS, then: */
struct cnn_cff_canon {
  CNN_CF_CANON_FIELDS(float);
  float lb2, ld2;   /* |AB|^2 and |AD|^2 before the mirror */
  float lab2, lad2; /* after it */
  int nearest;      /* how many nodes are within the margin of the nearest */
};

/* The corner tests' thresholds (cnn_cff_fold_tests). */
struct cnn_cff_folds {
  float longest, fold_ab, fold_c, fold_d; /* the longest side squared; the fold thresholds at A and B, C, D */
  float kcz, kdz;                         /* z of the cross products at C and D */
  int far;                                /* the segment decidedly far from collapsed */
};

/* The features of a lane. */
struct cnn_cff_features {
  float xc, yc, zc, xd, yd, xs, ys, zs;
};

CNN_CF_DEFINE_LOAD_NODES(cnn_cff_load_nodes, cnn_cff_query, float)
CNN_CF_DEFINE_ROTATE(cnn_cff_rotate, cnn_cff_query, cnn_cff_edges, float)
CNN_CF_DEFINE_MIRROR(cnn_cff_mirror, cnn_cff_query, cnn_cff_edges, cnn_cff_canon)
CNN_CF_DEFINE_FRAME(cnn_cff_axes, cnn_cff_canon, cnn_cff_frame, float, sqrtf)
CNN_CF_DEFINE_CORNERS(cnn_cff_segment_corners, cnn_cff_corners, float, cnn_cff_max, cnn_cff_min)

/* max |x| over the nodes relative to S; a NaN or infinity fails every comparison below and sends the lane to
 * the double pass. */
CNN_CF_INLINE float cnn_cff_magnitude(const struct cnn_cff_query* CNN_CF_RESTRICT q) {
  const float m_ab =
      cnn_cff_max(cnn_cff_max(fabsf(q->ax), fabsf(q->ay)), cnn_cff_max(fabsf(q->az), fabsf(q->bx)));
  const float m_bc =
      cnn_cff_max(cnn_cff_max(fabsf(q->by), fabsf(q->bz)), cnn_cff_max(fabsf(q->cx), fabsf(q->cy)));
  const float m_cd =
      cnn_cff_max(cnn_cff_max(fabsf(q->cz), fabsf(q->dx)), cnn_cff_max(fabsf(q->dy), fabsf(q->dz)));
  return cnn_cff_max(cnn_cff_max(m_ab, m_bc), m_cd);
}

/* The nearest node (one, by the margin mq in the squared distances), the nodes from it on, and the mirror
 * when |AD| > |AB| (decided when they differ by the margin). S is the origin: S - A = -A. */
CNN_CF_INLINE void cnn_cff_relabel(const struct cnn_cff_query* CNN_CF_RESTRICT q, float mq,
                                   struct cnn_cff_canon* CNN_CF_RESTRICT c) {
  const float q0 = q->ax * q->ax + q->ay * q->ay + q->az * q->az,
              q1 = q->bx * q->bx + q->by * q->by + q->bz * q->bz;
  const float q2 = q->cx * q->cx + q->cy * q->cy + q->cz * q->cz,
              q3 = q->dx * q->dx + q->dy * q->dy + q->dz * q->dz;
  const float reach = cnn_cff_min(cnn_cff_min(q0, q1), cnn_cff_min(q2, q3)) + mq;
  const int t0 = q0 <= reach, t1 = q1 <= reach, t2 = q2 <= reach, t3 = q3 <= reach;
  struct cnn_cff_edges e;
  float lb2, ld2;
  c->t0 = t0;
  c->t1 = t1;
  c->t2 = t2;
  c->nearest = t0 + t1 + t2 + t3;
  c->rot = t0 ? 0.0f : t1 ? 1.0f : t2 ? 2.0f : 3.0f;
  cnn_cff_rotate(q, t0, t1, t2, &e);
  lb2 = e.e_bx * e.e_bx + e.e_by * e.e_by + e.e_bz * e.e_bz;
  ld2 = e.e_dx * e.e_dx + e.e_dy * e.e_dy + e.e_dz * e.e_dz;
  cnn_cff_mirror(q, &e, ld2 > lb2, c);
  c->asx = -e.pax;
  c->asy = -e.pay;
  c->asz = -e.paz;
  c->lb2 = lb2;
  c->ld2 = ld2;
  c->lab2 = c->mir ? ld2 : lb2;
  c->lad2 = c->mir ? lb2 : ld2;
  c->scale = 1.0f / sqrtf(c->lab2);
}

/* The segment far from collapsed: sides and diagonals (squared, canonical units) and each corner's cross
 * product beyond their error bounds, from the features' error bound delta. A corner is folded when its cross
 * product is below max(1e-12 longest, the double pass's noise, at most 3.6e-9 longest here); decided unfolded
 * above 1e-7 longest plus its error bound, twice the sum of the edges' components times delta (at A and B 4
 * delta). */
CNN_CF_INLINE void cnn_cff_fold_tests(const struct cnn_cff_features* CNN_CF_RESTRICT x, float delta,
                                      struct cnn_cff_folds* CNN_CF_RESTRICT r) {
  const float xc = x->xc, yc = x->yc, zc = x->zc, xd = x->xd, yd = x->yd;
  struct cnn_cff_corners k;
  float side_err, fold0, kb_sq, fold_w;
  cnn_cff_segment_corners(xc, yc, zc, xd, yd, &k);
  side_err = 4.0f * delta * (1.0f + k.longest_sq);
  fold0 = 1e-7f * k.longest_sq;
  kb_sq = zc * zc + yc * yc; /* at B: (0, -z_C, y_C) */
  r->longest = k.longest_sq;
  r->fold_ab = fold0 + 4.0f * delta;
  r->fold_c = fold0 + 4.0f * delta *
                          (fabsf(k.ncdx) + fabsf(k.ncdy) + fabsf(k.ncdz) + fabsf(k.pcbx) + fabsf(k.pcby) +
                           fabsf(k.pcbz));
  r->fold_d = fold0 + 4.0f * delta * (fabsf(xd) + fabsf(yd) + fabsf(k.pdcx) + fabsf(k.pdcy) + fabsf(k.pdcz));
  fold_w = fold0 + 4.0f * delta * (fabsf(xc) + fabsf(yc) + fabsf(xd - 1.0f) + fabsf(yd));
  r->kcz = k.kcz;
  r->kdz = k.kdz;
  r->far = (k.shortest_sq > 1e-6f * k.longest_sq + side_err) & (yd > r->fold_ab) &
           (kb_sq > r->fold_ab * r->fold_ab) &
           (k.kcx * k.kcx + k.kcy * k.kcy + k.kcz * k.kcz > r->fold_c * r->fold_c) &
           (k.kdx * k.kdx + k.kdy * k.kdy + k.kdz * k.kdz > r->fold_d * r->fold_d) &
           (k.wz * k.wz > fold_w * fold_w);
}

/* cnn_domain_lane's tests in float, each as a violation v (the test fails when v > 0, or >= 0 if strict)
 * with a bound m on its error, gathered into *fail (max of v - m: failed when > 0) and *unsure (max of v + m:
 * undecided when >= 0 and none failed). First the feature ranges, m1 the error bound of a feature. */
CNN_CF_INLINE void cnn_cff_ranges(const struct cnn_domain* CNN_CF_RESTRICT d, const float* CNN_CF_RESTRICT ff,
                                  int s, float m1, float* CNN_CF_RESTRICT fail,
                                  float* CNN_CF_RESTRICT unsure) {
  const float u = 5.9604645e-8f; /* 2^-24 */
  int k;
  CNN_CF_UNROLL
  for (k = 0; k < 8; ++k) {
    const float fk = ff[k * s];
    const float lo = (float)d->lo[k], hi = (float)d->hi[k];
    const float mk = m1 + 4.0f * u * (fabsf(lo) + fabsf(hi));
    const float v = cnn_cff_max(lo - fk, fk - hi);
    *fail = cnn_cff_max(*fail, v - mk);
    *unsure = cnn_cff_max(*unsure, v + mk);
  }
}

/* The xy and z limits, |AD| <= |AB|, A nearest S and the segment test (Eqs 3-6 at A), with error bounds from
 * the tests' partial derivatives; `big` 1 + the largest feature. */
CNN_CF_INLINE void cnn_cff_shape(const struct cnn_domain* CNN_CF_RESTRICT d,
                                 const struct cnn_cff_features* CNN_CF_RESTRICT x, float delta, float big,
                                 float m1, float* CNN_CF_RESTRICT fail, float* CNN_CF_RESTRICT unsure) {
  const float u = 5.9604645e-8f; /* 2^-24 */
  const float xc = x->xc, yc = x->yc, zc = x->zc, xd = x->xd, yd = x->yd, xs = x->xs, ys = x->ys, zs = x->zs;
  const float xy = (float)d->xy, zl = (float)d->z, adb = (float)d->ad_bound;
  const float inv_1tol = (float)d->inv_one_plus_tol, tol = (float)d->tol;
  const float m_ad = 8.0f * big * delta + 8.0f * u * big * big;
  const float off_ad = d->ad_not_longer ? 0.0f : -1e30f, off_near = d->nearest_a ? 0.0f : -1e30f;
  const float off_seg = d->segment_test ? 0.0f : -1e30f;
  const float vxy =
      cnn_cff_max(cnn_cff_max(cnn_cff_max(fabsf(xc), fabsf(yc)), cnn_cff_max(fabsf(xd), fabsf(yd))),
                  cnn_cff_max(fabsf(xs), fabsf(ys))) -
      xy;
  const float vz = cnn_cff_max(fabsf(zc), fabsf(zs)) - zl;
  const float mxy = m1 + 4.0f * u * xy, mz = m1 + 4.0f * u * zl;
  const float vad = (xd * xd + yd * yd - adb) + off_ad;
  const float to_a = (xs * xs + ys * ys + zs * zs) * inv_1tol;
  const float to_b = (xs - 1.0f) * (xs - 1.0f) + ys * ys + zs * zs;
  const float to_c = (xs - xc) * (xs - xc) + (ys - yc) * (ys - yc) + (zs - zc) * (zs - zc);
  const float to_d = (xs - xd) * (xs - xd) + (ys - yd) * (ys - yd) + zs * zs;
  const float vnear = (to_a - cnn_cff_min(cnn_cff_min(to_b, to_c), to_d)) + off_near;
  const float r_sq = xs * xs + ys * ys, d_sq = xd * xd + yd * yd;
  const float lengths = sqrtf(r_sq * d_sq);
  const float m_seg2 = 2.0f * (fabsf(ys) + fabsf(yd)) * delta + 8.0f * u * big * big;
  const float m_seg3 =
      2.0f * (fabsf(xs * yd) + 2.0f * fabsf(ys * xd) + fabsf(ys * yd) + fabsf(ys * xs) + ys * ys) * delta +
      16.0f * u * big * big * big;
  const float m_near = 4.0f * delta *
                           (2.0f * (fabsf(xs) + fabsf(ys) + fabsf(zs)) + 2.0f + fabsf(xc) + fabsf(yc) +
                            fabsf(zc) + fabsf(xd) + fabsf(yd)) +
                       16.0f * u * big * big;
  const float vseg1 = -fabsf(yd) + off_seg;
  const float vseg2 = (-(ys * yd) - tol * lengths) + off_seg;
  const float vseg3 = (-(ys * (xs * yd - ys * xd)) - tol * lengths * sqrtf(r_sq)) + off_seg;
  *fail = cnn_cff_max(*fail,
                      cnn_cff_max(cnn_cff_max(vxy - mxy, vz - mz), cnn_cff_max(vad - m_ad, vnear - m_near)));
  *unsure = cnn_cff_max(
      *unsure, cnn_cff_max(cnn_cff_max(vxy + mxy, vz + mz), cnn_cff_max(vad + m_ad, vnear + m_near)));
  *fail = cnn_cff_max(*fail, cnn_cff_max(vseg1 - m1, cnn_cff_max(vseg2 - m_seg2, vseg3 - m_seg3)));
  *unsure = cnn_cff_max(*unsure, cnn_cff_max(vseg1 + m1, cnn_cff_max(vseg2 + m_seg2, vseg3 + m_seg3)));
}

/* Convexity: a corner fails when (next x prev) . (0, 0, yd) <= -tol |next| |prev| yd, i.e. (yd > 0 in the
 * frame) when the cross product's z, kz, is <= -tol |next| |prev|: kz = yd, yc, kcz, kdz at A, B, C, D, each
 * with the error bound of its fold test (tol's term, below 2 tol longest, added). */
CNN_CF_INLINE void cnn_cff_convex(const struct cnn_domain* CNN_CF_RESTRICT d,
                                  const struct cnn_cff_features* CNN_CF_RESTRICT x,
                                  const struct cnn_cff_folds* CNN_CF_RESTRICT k, float* CNN_CF_RESTRICT fail,
                                  float* CNN_CF_RESTRICT unsure) {
  const float u = 5.9604645e-8f; /* 2^-24 */
  const float tol = (float)d->tol, off_convex = d->convex ? 0.0f : -1e30f;
  const float mt = 8.0f * u * k->longest + 2.0f * tol * k->longest;
  const float fold_ab = k->fold_ab, fold_c = k->fold_c, fold_d = k->fold_d;
  const float va = -x->yd + off_convex, vb = -x->yc + off_convex, vc = -k->kcz + off_convex,
              vd = -k->kdz + off_convex;
  *fail = cnn_cff_max(*fail, cnn_cff_max(cnn_cff_max(va - fold_ab - mt, vb - fold_ab - mt),
                                         cnn_cff_max(vc - fold_c - mt, vd - fold_d - mt)));
  *unsure = cnn_cff_max(*unsure, cnn_cff_max(cnn_cff_max(va + fold_ab + mt, vb + fold_ab + mt),
                                             cnn_cff_max(vc + fold_c + mt, vd + fold_d + mt)));
}

/* The domain test of a lane whose features ff (rows at ff[k * s], also in x) have the error bound delta: its
 * status (0, or 5 when a test failed beyond its error bound) into *status; *redo = 1 when no test failed and
 * one is undecided. */
CNN_CF_INLINE void cnn_cff_domain(const struct cnn_domain* CNN_CF_RESTRICT d, const float* CNN_CF_RESTRICT ff,
                                  int s, const struct cnn_cff_features* CNN_CF_RESTRICT x, float delta,
                                  const struct cnn_cff_folds* CNN_CF_RESTRICT k,
                                  float* CNN_CF_RESTRICT status, float* CNN_CF_RESTRICT redo) {
  const float u = 5.9604645e-8f; /* 2^-24 */
  const float big =
      1.0f +
      cnn_cff_max(
          cnn_cff_max(cnn_cff_max(fabsf(x->xc), fabsf(x->yc)), cnn_cff_max(fabsf(x->zc), fabsf(x->xd))),
          cnn_cff_max(cnn_cff_max(fabsf(x->yd), fabsf(x->xs)), cnn_cff_max(fabsf(x->ys), fabsf(x->zs))));
  /* Error bounds, twice the sum of the test's partial derivatives (in `big`) times delta, plus rounding. */
  const float m1 = 2.0f * delta + 8.0f * u * big;
  float fail = -1.0f, unsure = -1.0f;
  cnn_cff_ranges(d, ff, s, m1, &fail, &unsure);
  cnn_cff_shape(d, x, delta, big, m1, &fail, &unsure);
  cnn_cff_convex(d, x, k, &fail, &unsure);
  *status = fail > 0.0f ? (float)CNN_CF_STATUS_OUT_OF_DOMAIN : 0.0f;
  *redo = ((fail > 0.0f) | !(unsure >= 0.0f)) ? *redo : 1.0f;
}

/* One lane. rel: 12 rows at rel[k * s]: A - S, B - S, C - S, D - S (x, y, z each), scaled by a power of two.
 * Writes ff[k * s], 8 feature rows, and fi[k * s]: 0 symmetry code, 1 orientation, 2 scale (1 / |AB|), 3
 * status (0 or 5), 4 redo (1: the double pass decides this lane). `domain` 0: no domain test (d unused). The
 * nodes relative to S are the same values whatever the caller's node order, so the lane's arithmetic (which
 * takes differences of these after the canonical relabelling) gives the same bits for all 8 orders. */
CNN_CF_INLINE void cnn_cff_lane(const float* CNN_CF_RESTRICT rel, int s,
                                const struct cnn_domain* CNN_CF_RESTRICT d, int domain,
                                float* CNN_CF_RESTRICT ff, float* CNN_CF_RESTRICT fi) {
  const float u = 5.9604645e-8f; /* 2^-24 */
  struct cnn_cff_query q;
  struct cnn_cff_canon c;
  struct cnn_cff_frame fr;
  struct cnn_cff_features x;
  struct cnn_cff_folds k;
  float m, mq, finite, redo, extent, delta, zsign;
  int decided;
  cnn_cff_load_nodes(rel, s, &q);
  m = cnn_cff_magnitude(&q);
  mq = 256.0f * u * m * m;
  /* Their sum times 0: NaN when a value is not finite (or the scaled values overflowed float). */
  finite = (q.ax + q.ay + q.az + q.bx + q.by + q.bz + q.cx + q.cy + q.cz + q.dx + q.dy + q.dz) * 0.0f;
  redo = ((finite == 0.0f) & (m >= 1e-12f) & (m <= 1e12f)) ? 0.0f : 1.0f;
  cnn_cff_relabel(&q, mq, &c);
  cnn_cff_axes(&c, &fr);
  /* The features' error bound delta: 32 u (1 + R) over sin(angle at A) (its square >= 1e-4 is required
   * below), R the query's extent over |AB| (every node within m of S, so within 2 m of A). */
  extent = 2.0f * m * c.scale;
  delta = 32.0f * u * (1.0f + extent) * sqrtf(c.lad2 / cnn_cff_max(fr.normal_sq, 1e-30f));
  /* z oriented so that S is on its + side; S decidedly off the plane. */
  zsign = fr.zs0 < 0.0f ? -1.0f : 1.0f;
  x.xc = fr.xc;
  x.yc = fr.yc;
  x.zc = zsign * fr.zc0;
  x.xd = fr.xd;
  x.yd = fr.yd;
  x.xs = fr.xs;
  x.ys = fr.ys;
  x.zs = zsign * fr.zs0;
  cnn_cff_fold_tests(&x, delta, &k);
  /* Decided: one nearest node, the mirror by a margin, the frame well conditioned, S off the plane, the
   * segment far from collapsed, and the double pass's noise terms (16 eps max |x|, x the world coordinates;
   * scaled, max |x| <= 1 + m since |S| scaled is below 1) far below the margins: |AB| >= 1e-6 (1 + m). */
  decided = (c.nearest == 1) & ((1.0f + m) * (1.0f + m) <= 1e12f * c.lab2) & (fabsf(c.ld2 - c.lb2) > mq) &
            (c.lab2 > mq) & (c.lad2 >= 1e-6f * c.lab2) & (fr.normal_sq >= 1e-4f * c.lad2) & (extent < 1e4f) &
            (fabsf(fr.zs0) > 2.0f * delta + 4e-9f * (1.0f + extent)) & k.far;
  redo = decided ? redo : 1.0f;
  ff[0 * s] = x.xc;
  ff[1 * s] = x.yc;
  ff[2 * s] = x.zc;
  ff[3 * s] = x.xd;
  ff[4 * s] = x.yd;
  ff[5 * s] = x.xs;
  ff[6 * s] = x.ys;
  ff[7 * s] = x.zs;
  fi[0 * s] = c.rot + (c.mir ? 4.0f : 0.0f);
  fi[1 * s] = (c.mir ? -1.0f : 1.0f) * zsign;
  fi[2 * s] = c.scale;
  fi[3 * s] = 0.0f;
  if (domain) cnn_cff_domain(d, ff, s, &x, delta, &k, fi + 3 * s, &redo);
  fi[4 * s] = redo;
}

#endif /* CONTACTNN_CANONICAL_FRAME_FLOAT_H */
