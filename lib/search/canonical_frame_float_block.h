/* canonical_frame_float_block.h (part of canonical_frame.h): the float pass over a block (cnn_cff_block), the
 * lanes it leaves to the double pass (cnn_cff_redo), the order of the two passes on data that float mostly
 * leaves undecided (cnn_cff_block_expecting), and the whole block (cnn_canonicalise_domain_block_f). */
#ifndef CONTACTNN_CANONICAL_FRAME_FLOAT_BLOCK_H
#define CONTACTNN_CANONICAL_FRAME_FLOAT_BLOCK_H

#include "search/canonical_frame_domain.h"
#include "search/canonical_frame_float.h"
#include "search/canonical_frame_lane.h"

/* The float pass of a block of n <= CNN_CFF_MAX_LANES bilinear lanes, d without angle bounds (or null): f (8
 * rows) and info as cnn_canonicalise_block and (d not null) cnn_domain_block give them, for the lanes decided
 * in float; the others get info row 4 = 1 and unspecified values (cnn_cff_redo, or a later double pass,
 * decides them). Returns how many lanes float did not decide. */
CNN_CF_INLINE int cnn_cff_block(int n, const struct cnn_domain* CNN_CF_RESTRICT d,
                                const double* CNN_CF_RESTRICT in, double* CNN_CF_RESTRICT f,
                                double* CNN_CF_RESTRICT info) {
  float rel[12 * CNN_CFF_MAX_LANES], ff[8 * CNN_CFF_MAX_LANES], fi[5 * CNN_CFF_MAX_LANES];
  double power[CNN_CFF_MAX_LANES];
  int k, l, undecided = 0;
  CNN_CF_IVDEP
  for (l = 0; l < n; ++l) {
    /* The power of two that brings max |S| (a coordinate of the slave node, the same in every node order)
     * into [0.5, 1), from its exponent bits: the float pass sees the same values at every power-of-two scale
     * of the query, so it gives the same answer there, as the double pass does. NaN (the double pass) when
     * |S| is outside [1e-290, 1e290] or not finite (a slave node at the origin takes the double pass). */
    const double m = cnn_cf_max(fabs(in[12 * n + l]), cnn_cf_max(fabs(in[13 * n + l]), fabs(in[14 * n + l])));
    double bits_as_double;
    unsigned long long bits;
    memcpy(&bits, &m, sizeof bits);
    bits = (2046ULL - ((bits >> 52) & 2047ULL)) << 52; /* 2^-(e+1) for m in [2^e, 2^(e+1)) */
    memcpy(&bits_as_double, &bits, sizeof bits);
    power[l] = ((m >= 1e-290) & (m <= 1e290)) ? bits_as_double : (double)NAN;
  }
  for (k = 0; k < 12; ++k) {
    const double* x = in + k * n;
    const double* slave = in + (12 + k % 3) * n;
    CNN_CF_IVDEP
    for (l = 0; l < n; ++l) rel[k * n + l] = (float)((x[l] - slave[l]) * power[l]);
  }
  if (d != 0) {
    CNN_CF_IVDEP
    for (l = 0; l < n; ++l) cnn_cff_lane(rel + l, n, d, 1, ff + l, fi + l);
  } else {
    CNN_CF_IVDEP
    for (l = 0; l < n; ++l) cnn_cff_lane(rel + l, n, d, 0, ff + l, fi + l);
  }
  for (k = 0; k < 8; ++k) {
    CNN_CF_IVDEP
    for (l = 0; l < n; ++l) f[k * n + l] = (double)ff[k * n + l];
  }
  CNN_CF_IVDEP
  for (l = 0; l < n; ++l) {
    info[l] = (double)fi[3 * n + l];
    info[n + l] = (double)fi[l];
    info[2 * n + l] = (double)fi[n + l];
    info[3 * n + l] = (double)fi[2 * n + l] * power[l];
    info[4 * n + l] = (double)fi[4 * n + l];
    info[5 * n + l] = 0.0;
  }
  for (l = 0; l < n; ++l) undecided += fi[4 * n + l] != 0.0f;
  return undecided;
}

/* The double pass the float pass stands in for: cnn_canonicalise_block on n bilinear lanes, then (d not null)
 * cnn_domain_block. */
CNN_CF_INLINE void cnn_cff_double_pass(int n, const struct cnn_domain* CNN_CF_RESTRICT d,
                                       const double* CNN_CF_RESTRICT in, double* CNN_CF_RESTRICT f,
                                       double* CNN_CF_RESTRICT info) {
  cnn_canonicalise_block(n, 0, in, f, 0, info);
  if (d != 0) cnn_domain_block(n, 0, d, f, 0, info);
}

/* The lanes of a block that cnn_cff_block left undecided (info row 4 not 0): the double pass on them,
 * gathered into a block of their own, its f rows and info rows written back. */
CNN_CF_INLINE void cnn_cff_redo(int n, const struct cnn_domain* CNN_CF_RESTRICT d,
                                const double* CNN_CF_RESTRICT in, double* CNN_CF_RESTRICT f,
                                double* CNN_CF_RESTRICT info) {
  double in2[15 * CNN_CFF_MAX_LANES], f2[8 * CNN_CFF_MAX_LANES], info2[CNN_CF_INFO_ROWS * CNN_CFF_MAX_LANES];
  int redo[CNN_CFF_MAX_LANES];
  int k, l, r, nr = 0;
  for (l = 0; l < n; ++l) {
    if (info[4 * n + l] != 0.0) redo[nr++] = l;
  }
  if (nr == 0) return;
  for (r = 0; r < nr; ++r) {
    for (k = 0; k < 15; ++k) in2[k * nr + r] = in[k * n + redo[r]];
  }
  cnn_cff_double_pass(nr, d, in2, f2, info2);
  for (r = 0; r < nr; ++r) {
    for (k = 0; k < 8; ++k) f[k * n + redo[r]] = f2[k * nr + r];
    for (k = 0; k < CNN_CF_INFO_ROWS; ++k) info[k * n + redo[r]] = info2[k * nr + r];
  }
}

/* True when the float pass would leave lane l of a block undecided, read from the double pass's outputs for
 * the block (f: 8 rows, info: CNN_CF_INFO_ROWS rows, cnn_canonicalise_block and cnn_domain_block, n lanes): a
 * status the float pass never decides (degenerate, invalid), a tie, |z_S| at most half the float features'
 * error bound delta (the float pass needs |z_S| above 2 delta; delta = 32 u (1 + R) / sin(angle at A) with R
 * >= 2 / sqrt(3) max |X - S|, X a node, in canonical units), or |AD| within 4 u of |AB| (the mirror test
 * needs |AD|^2 - |AB|^2 beyond 256 u max|x - S|^2, at least 21 u |AB|^2, and the float rounding of the two
 * squares stays within 168 u max|x - S|^2). Touching contact (slaves on the master's plane) and square
 * elements meet it on every lane: a caller that expects them can run the double pass first and skip the float
 * pass where every lane of the block meets it, with the same result as the float pass first. */
CNN_CF_INLINE int cnn_cff_leaves(int n, int l, const double* CNN_CF_RESTRICT f,
                                 const double* CNN_CF_RESTRICT info) {
  const double u = 5.9604644775390625e-8; /* 2^-24 */
  const double status = info[l], xc = f[l], yc = f[n + l], zc = f[2 * n + l], xd = f[3 * n + l],
               yd = f[4 * n + l];
  const double xs = f[5 * n + l], ys = f[6 * n + l], zs = f[7 * n + l];
  const double to_a = xs * xs + ys * ys + zs * zs, to_b = (xs - 1.0) * (xs - 1.0) + ys * ys + zs * zs;
  const double to_c = (xs - xc) * (xs - xc) + (ys - yc) * (ys - yc) + (zs - zc) * (zs - zc);
  const double to_d = (xs - xd) * (xs - xd) + (ys - yd) * (ys - yd) + zs * zs;
  const double reach = 2.0 * sqrt(cnn_cf_max(cnn_cf_max(to_a, to_b), cnn_cf_max(to_c, to_d)) / 3.0);
  const double ad_sq = xd * xd + yd * yd;
  /* |z_S| sin(angle at A) <= 16 u (1 + R), sin = yd / |AD| (yd > 0 in the frame) */
  const int on_plane = fabs(zs) * yd <= 16.0 * u * (1.0 + reach) * sqrt(ad_sq);
  return (status == (double)CNN_CF_STATUS_DEGENERATE) | (status == (double)CNN_CF_STATUS_INVALID) |
         (info[5 * n + l] != 0.0) | on_plane | (fabs(ad_sq - 1.0) <= 4.0 * u);
}

/* A block that left at least 1 / CNN_CFF_MANY_UNDECIDED of its lanes undecided redoes them at once rather
 * than gathering them from many blocks (lib/search's choice; measured there). */
#define CNN_CFF_MANY_UNDECIDED 4

/* cnn_cff_block_expecting with *expect set, a block of n > 1 lanes: the double pass, then the float pass
 * unless cnn_cff_leaves names every lane, its decided lanes replacing the double pass's. */
CNN_CF_OUTLINE void cnn_cff_double_first(int n, const struct cnn_domain* CNN_CF_RESTRICT d,
                                         const double* CNN_CF_RESTRICT in, double* CNN_CF_RESTRICT f,
                                         double* CNN_CF_RESTRICT info, int* CNN_CF_RESTRICT expect) {
  double f2[8 * CNN_CFF_MAX_LANES], info2[CNN_CF_INFO_ROWS * CNN_CFF_MAX_LANES];
  int k, l, leaves = 0;
  cnn_cff_double_pass(n, d, in, f, info);
  for (l = 0; l < n; ++l) leaves += cnn_cff_leaves(n, l, f, info);
  if (leaves == n) return;
  (void)cnn_cff_block(n, d, in, f2, info2);
  for (l = 0; l < n; ++l) {
    if (info2[4 * n + l] != 0.0) continue;
    for (k = 0; k < 8; ++k) f[k * n + l] = f2[k * n + l];
    for (k = 0; k < CNN_CF_INFO_ROWS; ++k) info[k * n + l] = info2[k * n + l];
  }
  *expect = 4 * leaves >= 3 * n;
}

/* The float pass of a block (n <= CNN_CFF_MAX_LANES lanes, d as cnn_cff_block) for a caller that runs blocks
 * in sequence and keeps *expect between them (0 to start with): what cnn_cff_block gives (the caller redoes
 * or defers the lanes left undecided), except that lanes it would leave undecided may come back decided by
 * the double pass (info row 4 = 0, as cnn_cff_redo leaves them); returns how many lanes are still undecided.
 * Real decks' contact pairs leave every lane to the double pass (slaves on the master's plane, square
 * elements), and a block of them paid the float pass for nothing. So: after a block that leaves 3 lanes in 4
 * or more undecided *expect is 1; while it is 1 the double pass runs first, the float pass only where
 * cnn_cff_leaves does not name every lane (its lanes then replace the double pass's), and *expect stays 1
 * while cnn_cff_leaves names 3 lanes in 4 or more (where fewer are, a block pays both passes: mixed data,
 * such as the paper's grid with 4 lanes in 10 undecided, goes back to the float pass first). Each lane gets
 * the bits it gets from cnn_cff_block and cnn_cff_redo: *expect changes the speed, never a result. */
CNN_CF_INLINE int cnn_cff_block_expecting(int n, const struct cnn_domain* CNN_CF_RESTRICT d,
                                          const double* CNN_CF_RESTRICT in, double* CNN_CF_RESTRICT f,
                                          double* CNN_CF_RESTRICT info, int* CNN_CF_RESTRICT expect) {
  int undecided;
  if (*expect) {
    if (n > 1) {
      cnn_cff_double_first(n, d, in, f, info, expect);
      return 0;
    }
    /* One lane: the double pass, which stands where the float pass would not decide the lane; otherwise the
     * float pass below, as without the expectation. */
    cnn_cff_double_pass(1, d, in, f, info);
    if (cnn_cff_leaves(1, 0, f, info)) return 0;
  }
  undecided = cnn_cff_block(n, d, in, f, info);
  *expect = 4 * undecided >= 3 * n;
  return undecided;
}

/* A cheap guess that the float pass will leave one query (15 values at in[k * is], SPEC 6 order) undecided:
 * the slave within 1e-5 of the plane of the caller's A, B, D, relative to its distance from A (touching
 * contact; a slave on node A too), or |AB|^2 and |AD|^2 equal to 1e-6 (a square element). A caller that runs
 * one query at a time and so carries no expectation from block to block can set *expect from it for
 * cnn_cff_block_expecting: only the order of the two passes depends on it, never a result. */
CNN_CF_INLINE int cnn_cff_looks_undecided(const double* CNN_CF_RESTRICT in, int is) {
  const double abx = in[3 * is] - in[0], aby = in[4 * is] - in[is], abz = in[5 * is] - in[2 * is];
  const double adx = in[9 * is] - in[0], ady = in[10 * is] - in[is], adz = in[11 * is] - in[2 * is];
  const double asx = in[12 * is] - in[0], asy = in[13 * is] - in[is], asz = in[14 * is] - in[2 * is];
  const double nx = aby * adz - abz * ady, ny = abz * adx - abx * adz, nz = abx * ady - aby * adx;
  const double h = nx * asx + ny * asy + nz * asz;
  const double ab2 = abx * abx + aby * aby + abz * abz, ad2 = adx * adx + ady * ady + adz * adz;
  return (h * h <= 1e-10 * (nx * nx + ny * ny + nz * nz) * (asx * asx + asy * asy + asz * asz)) |
         (fabs(ab2 - ad2) <= 1e-6 * ab2);
}

/* True when a float network's bilinear block can take the float pass: n <= CNN_CFF_MAX_LANES and no angle
 * bounds. */
CNN_CF_INLINE int cnn_cff_applies(int n, const struct cnn_domain* CNN_CF_RESTRICT d) {
  return n <= CNN_CFF_MAX_LANES && (d == 0 || !(d->check_lo || d->check_hi));
}

/* The block: what cnn_canonicalise_block and then (d not null) cnn_domain_block give for n bilinear lanes (f:
 * 8 rows; info: CNN_CF_INFO_ROWS rows, tie code 0 and row 4 = 0 on the lanes decided in float), the features
 * of the lanes decided in float in float precision, the others redone in double within the block. Where the
 * float pass does not apply (cnn_cff_applies), the double pass for every lane. `expect` not null: blocks in
 * sequence, *expect kept between them (cnn_cff_block_expecting; the same result, faster on touching contact).
 */
CNN_CF_INLINE void cnn_canonicalise_domain_block_fe(int n, const struct cnn_domain* CNN_CF_RESTRICT d,
                                                    const double* CNN_CF_RESTRICT in,
                                                    double* CNN_CF_RESTRICT f, double* CNN_CF_RESTRICT info,
                                                    int* CNN_CF_RESTRICT expect) {
  if (!cnn_cff_applies(n, d)) {
    cnn_cff_double_pass(n, d, in, f, info);
    return;
  }
  if ((expect == 0 ? cnn_cff_block(n, d, in, f, info) : cnn_cff_block_expecting(n, d, in, f, info, expect)) >
      0) {
    cnn_cff_redo(n, d, in, f, info);
  }
}

/* cnn_canonicalise_domain_block_fe for a block on its own (no expectation carried from block to block). */
CNN_CF_INLINE void cnn_canonicalise_domain_block_f(int n, const struct cnn_domain* CNN_CF_RESTRICT d,
                                                   const double* CNN_CF_RESTRICT in,
                                                   double* CNN_CF_RESTRICT f, double* CNN_CF_RESTRICT info) {
  cnn_canonicalise_domain_block_fe(n, d, in, f, info, 0);
}

#endif /* CONTACTNN_CANONICAL_FRAME_FLOAT_BLOCK_H */
