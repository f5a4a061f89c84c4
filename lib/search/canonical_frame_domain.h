/* canonical_frame_domain.h (part of canonical_frame.h): the test of a network's training domain on the
 * canonical features, for blocks of lanes. */
#ifndef CONTACTNN_CANONICAL_FRAME_DOMAIN_H
#define CONTACTNN_CANONICAL_FRAME_DOMAIN_H

#include "search/canonical_frame_base.h"

/* ---- The training domain (geometry::TrainingDomain::contains) ---- */

/* Precomputed from a TrainingDomain with relative tolerance tol = 1e-9 (cnn_domain_init fills it). */
/* Exported headers initialise it positionally, in this order (export_c_header.cpp). */
struct cnn_domain {
  double lo[16], hi[16];   /* feature_min - slack, feature_max + slack */
  double xy, z;            /* xy_limit (1 + tol), z_limit (1 + tol) */
  double ad_bound;         /* 1 + tol: |AD|^2 <= (1 + tol) |AB|^2, |AB| = 1 */
  double inv_one_plus_tol; /* 1 / (1 + tol) */
  double tol;
  double cos_lo, cos_hi; /* cosines of the relaxed angle bounds */
  double tilt;           /* max_normal_tilt_tangent */
  int features;          /* 8 or 16 */
  int ad_not_longer, nearest_a, segment_test, convex;
  int check_lo, check_hi; /* angle bounds to test: 0 when the relaxed bound is outside (0, 180) degrees */
};

/* One lane: the status row code[0] becomes out_of_domain (5) where it is ok (0) and the configuration lies
 * outside the domain. Every test is written as a violation, gathered by max into `loose` (the configuration
 * fails when it is > 0: a non-strict inequality of the reference) or `strict` (fails when >= 0: a strict
 * one), so that the lane is straight-line floating-point code. `angles` (0 or 1) says whether the domain
 * bounds the interior angles (cnn_domain_block passes it as a constant). Angles are compared through their
 * cosines, which agrees with the reference's atan2 form except within a few ulps of the relaxed bound. */
CNN_CF_INLINE void cnn_domain_lane(const struct cnn_domain* CNN_CF_RESTRICT d, int gregory, int angles,
                                   const double* CNN_CF_RESTRICT f, const double* CNN_CF_RESTRICT nrm, int s,
                                   double* CNN_CF_RESTRICT code) {
  /* Every field read up front: a load under a lane-dependent condition would not vectorise. */
  const double tol = d->tol, xy = d->xy, zl = d->z, inv_1tol = d->inv_one_plus_tol;
  const double cos_lo = d->cos_lo, cos_hi = d->cos_hi, tilt = d->tilt;
  /* A filter that is off adds a violation that never fails. */
  const double ad_off = d->ad_not_longer ? 0.0 : -1e300, nearest_off = d->nearest_a ? 0.0 : -1e300;
  const double segment_off = d->segment_test ? 0.0 : -1e300, convex_off = d->convex ? 0.0 : -1e300;
  const double lo_off = d->check_lo ? 0.0 : -1e300, hi_off = d->check_hi ? 0.0 : -1e300;
  const double xc = f[0 * s], yc = f[1 * s], zc = f[2 * s], xd = f[3 * s], yd = f[4 * s];
  const double xs = f[5 * s], ys = f[6 * s], zs = f[7 * s];
  double loose = -1.0, strict = -1.0;
  int k;
  CNN_CF_UNROLL
  for (k = 0; k < 8; ++k) loose = cnn_cf_max(loose, cnn_cf_max(d->lo[k] - f[k * s], f[k * s] - d->hi[k]));
  if (gregory) {
    CNN_CF_UNROLL
    for (k = 8; k < 16; ++k) loose = cnn_cf_max(loose, cnn_cf_max(d->lo[k] - f[k * s], f[k * s] - d->hi[k]));
  }
  /* |x|, |y| of C, D, S below xy_limit (1 + tol); |z| of C and S below z_limit (1 + tol): strict. */
  strict =
      cnn_cf_max(strict, cnn_cf_max(cnn_cf_max(fabs(xc), fabs(yc)), cnn_cf_max(fabs(xd), fabs(yd))) - xy);
  strict = cnn_cf_max(strict, cnn_cf_max(fabs(xs), fabs(ys)) - xy);
  strict = cnn_cf_max(strict, cnn_cf_max(fabs(zc), fabs(zs)) - zl);
  /* |AD|^2 <= (1 + tol) |AB|^2 = 1 + tol. */
  loose = cnn_cf_max(loose, (xd * xd + yd * yd - d->ad_bound) + ad_off);
  {
    /* A nearest: |S - A|^2 / (1 + tol) <= |S - X|^2 for X = B, C, D. */
    const double to_a = (xs * xs + ys * ys + zs * zs) * inv_1tol;
    const double to_b = (xs - 1.0) * (xs - 1.0) + ys * ys + zs * zs;
    const double to_c = (xs - xc) * (xs - xc) + (ys - yc) * (ys - yc) + (zs - zc) * (zs - zc);
    const double to_d = (xs - xd) * (xs - xd) + (ys - yd) * (ys - yd) + zs * zs;
    loose = cnn_cf_max(loose, (to_a - cnn_cf_min(cnn_cf_min(to_b, to_c), to_d)) + nearest_off);
  }
  {
    /* Eqs 3-6 at A with c1 = B - A = (1,0,0), c2 = D - A = (xd, yd, 0): r = (xs, ys, 0); strict (> -slack).
     */
    const double r_len = sqrt(xs * xs + ys * ys);
    const double lengths = r_len * sqrt(xd * xd + yd * yd);
    strict = cnn_cf_max(strict, -fabs(yd) + segment_off);
    strict = cnn_cf_max(strict, (-(ys * yd) - tol * lengths) + segment_off);
    strict = cnn_cf_max(strict, (-(ys * (xs * yd - ys * xd)) - tol * lengths * r_len) + segment_off);
  }
  {
    /* Corners of A (0,0,0), B (1,0,0), C, D (z = 0): next - X and prev - X. */
    const double nx_[4] = {1.0, xc - 1.0, xd - xc, -xd}, ny_[4] = {0.0, yc, yd - yc, -yd},
                 nz_[4] = {0.0, zc, -zc, 0.0};
    const double px_[4] = {xd, -1.0, 1.0 - xc, xc - xd}, py_[4] = {yd, 0.0, -yc, yc - yd},
                 pz_[4] = {0.0, 0.0, -zc, zc};
    const double ref_sq = yd * yd; /* (B - A) x (D - A) = (0, 0, yd) */
    int i;
    CNN_CF_UNROLL
    for (i = 0; i < 4; ++i) {
      const double kx = ny_[i] * pz_[i] - nz_[i] * py_[i], ky = nz_[i] * px_[i] - nx_[i] * pz_[i],
                   kz = nx_[i] * py_[i] - ny_[i] * px_[i];
      const double next_sq = nx_[i] * nx_[i] + ny_[i] * ny_[i] + nz_[i] * nz_[i];
      const double prev_sq = px_[i] * px_[i] + py_[i] * py_[i] + pz_[i] * pz_[i];
      const double cross_sq = kx * kx + ky * ky + kz * kz;
      {
        /* (next x prev) . reference > -tol |next| |prev| |reference|: fails when along <= 0 and along^2 >=
         * the slack squared. */
        const double along = kz * yd;
        strict = cnn_cf_max(
            strict, cnn_cf_min(-along, along * along - tol * tol * next_sq * prev_sq * ref_sq) + convex_off);
      }
      if (angles) {
        /* cos(angle) = dot / h, h = |next| |prev| = sqrt(cross^2 + dot^2): angle >= lo <=> dot <= cos_lo h
         * and angle <= hi <=> dot >= cos_hi h. */
        const double dot = nx_[i] * px_[i] + ny_[i] * py_[i] + nz_[i] * pz_[i];
        const double h = sqrt(cross_sq + dot * dot);
        loose = cnn_cf_max(loose, (dot - cos_lo * h) + lo_off);
        loose = cnn_cf_max(loose, (cos_hi * h - dot) + hi_off);
      }
      if (gregory) {
        /* tan(angle(node normal, corner normal)) < tilt: corner . n > 0 and |corner x n| < tilt (corner . n)
         * + tol |corner| |n|. */
        const double mx = nrm[(3 * i) * s], my = nrm[(3 * i + 1) * s], mz = nrm[(3 * i + 2) * s];
        const double cos_part = kx * mx + ky * my + kz * mz;
        const double sx_ = ky * mz - kz * my, sy_ = kz * mx - kx * mz, sz_ = kx * my - ky * mx;
        const double bound = tilt * cos_part + tol * sqrt(cross_sq * (mx * mx + my * my + mz * mz));
        strict =
            cnn_cf_max(strict, cnn_cf_max(-cos_part, (sx_ * sx_ + sy_ * sy_ + sz_ * sz_) - bound * bound));
      }
    }
  }
  code[0] = (code[0] == (double)CNN_CF_STATUS_OK && !(loose <= 0.0 && strict < 0.0))
                ? (double)CNN_CF_STATUS_OUT_OF_DOMAIN
                : code[0];
}

/* The block: status row `code` (n lanes) updated for every lane. */
CNN_CF_INLINE void cnn_domain_block(int n, int gregory, const struct cnn_domain* CNN_CF_RESTRICT d,
                                    const double* CNN_CF_RESTRICT f, const double* CNN_CF_RESTRICT nrm,
                                    double* CNN_CF_RESTRICT code) {
  int l;
  if (d->check_lo || d->check_hi) {
    CNN_CF_IVDEP
    for (l = 0; l < n; ++l) cnn_domain_lane(d, gregory, 1, f + l, nrm + l, n, code + l);
  } else {
    CNN_CF_IVDEP
    for (l = 0; l < n; ++l) cnn_domain_lane(d, gregory, 0, f + l, nrm + l, n, code + l);
  }
}
#endif /* CONTACTNN_CANONICAL_FRAME_DOMAIN_H */
