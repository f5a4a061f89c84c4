/* canonical_frame.h: the canonical configuration of a node-segment query (contactnn SPEC 4) and the check
 * of a network's training domain, for blocks of queries, in C99 that is also valid C++.
 *
 * One source for the network's inputs: lib/search compiles it into its network methods, and the exported
 * C header of a network embeds this text verbatim. Self-contained (only <math.h> and <string.h>); the include
 * guard is fixed, so two exported headers in one translation unit share one copy. A float network on bilinear
 * segments takes the float pass at the end of this file (cnn_canonicalise_domain_block_f): the same
 * decisions, features in float.
 *
 * What it computes is geometry::normalise (lib/geometry/affine_frame.hpp), the reference, written branch-free
 * per lane so that a compiler vectorises the loop over the lanes of a block:
 *  - invalid (status 4) when a coordinate (or, Gregory, a normal component) is not finite;
 *  - the symmetry of the square: canonical A is the first node nearest S (distances within 1e-12 relative
 *    plus 16 eps max|x| are a tie), then the mirror when |AD| > |AB| (on a tie: when S is nearer the line
 * AD);
 *  - the frame of SPEC 4 on the canonical A, B, D; z oriented so that z_S > 0 (with S on the plane: z_C > 0),
 *    a height within 1e-12 + 16 eps max|x| / |AB| counting as 0 (both on the plane: a z tie, no flip);
 *  - a flag for the lanes on a tie (another node as near S, |AB| = |AD| with S on the diagonal, a z tie),
 * whose other canonical forms cnn_cf_forms lists afterwards (the scalar path of ties, below);
 *  - degenerate (status 3) when that frame does not exist, when the segment is collapsed
 *    (geometry::is_degenerate_segment with the coordinates' own rounding as noise), or when a Gregory node
 *    normal is zero, in the segment plane, or the normals lie on both sides. Where the reference falls back
 * to another corner (a straight angle at the canonical A), the features are not those a network was trained
 *    on: that is degenerate here too, as it is for the reference's network methods.
 * Differences from the reference, all at the rounding level: lengths are compared through their squares
 * (two square roots per query instead of seventeen), divisions by a length are multiplications by its
 * reciprocal, and a node normal is rotated before it is normalised (its slopes n_x/n_z do not need the
 * length). A decision can therefore differ only for a configuration within a few ulps of a threshold.
 * Coordinates whose magnitude lies outside [1e-50, 1e50] (and normals outside [1e-50, 1e50] in length) are
 * first scaled by a power of two, which is exact, in a scalar pass, so that no square under- or overflows;
 * there, a difference of two coordinates that overflows makes the query degenerate.
 *
 * The loops over lanes vectorise with GCC at -O3 given -fno-math-errno (sqrt) and -fno-trapping-math (selects
 * over comparisons); without them the code is the same, scalar. Both change no result.
 *
 * Layout of a block of n lanes (n >= 1), structure of arrays, lane l of quantity k at [k * n + l]:
 *   in:    k = 0..14: ax ay az bx by bz cx cy cz dx dy dz sx sy sz (SPEC 6 order, world coordinates),
 *          Gregory also k = 15..26: nax nay naz ... ndz (node normals, any positive length);
 *   f:     features xc yc zc xd yd xs ys zs (+ Gregory pa qa pb qb pc qc pd qd), 8 or 16 rows;
 *   nrm:   Gregory only (else may be 0): the canonical node normals A..D in the canonical frame, 12 rows,
 *          oriented to the +z side but not normalised;
 *   info:  CNN_CF_INFO_ROWS = 6 rows: status (0 ok, 3 degenerate, 4 invalid), symmetry (rotation + 4 *
 * mirror: canonical node i is the caller's node ((mirror ? (4 - i) % 4 : i) + rotation) % 4), orientation (+1
 *          or -1: the caller's gap is orientation * canonical gap / scale), scale (1 / |AB|, canonical AB),
 *          a work row, and the tie code (1: a symmetry tie, + 2: a z tie; cnn_cf_needs_forms reads it).
 * Where the status is not 0, f and nrm hold unspecified finite or non-finite values.
 */
#ifndef CONTACTNN_CANONICAL_FRAME_H
#define CONTACTNN_CANONICAL_FRAME_H

/* Raised whenever what this file computes or its interface changes: an exported header checks that the copy
 * in force (the first one included in a translation unit) is the one it was generated with. */
#define CNN_CANONICAL_FRAME_VERSION 4

#include <math.h>
#include <string.h>

#if defined(__cplusplus)
#define CNN_CF_RESTRICT __restrict
#else
#define CNN_CF_RESTRICT restrict
#endif

/* The lane functions must be inlined into the loops over lanes, or nothing vectorises. */
#if defined(__GNUC__)
#define CNN_CF_INLINE static inline __attribute__((always_inline))
#else
#define CNN_CF_INLINE static inline
#endif

/* Code off the hot path: kept out of the callers (a caller's loops are otherwise compiled around its arrays).
 */
#if defined(__GNUC__)
#define CNN_CF_OUTLINE static __attribute__((noinline, unused))
#else
#define CNN_CF_OUTLINE static inline
#endif

/* Lanes never alias one another: the loops over lanes carry no dependence. */
#if defined(__clang__)
#define CNN_CF_IVDEP _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define CNN_CF_IVDEP _Pragma("GCC ivdep")
#else
#define CNN_CF_IVDEP
#endif

/* Short loops inside a lane must be unrolled before the loop over lanes can vectorise. */
#if defined(__clang__)
#define CNN_CF_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define CNN_CF_UNROLL _Pragma("GCC unroll 16")
#else
#define CNN_CF_UNROLL
#endif

#define CNN_CF_STATUS_OK 0
#define CNN_CF_STATUS_DEGENERATE 3
#define CNN_CF_STATUS_INVALID 4
#define CNN_CF_STATUS_OUT_OF_DOMAIN 5

/* Rows of `info` per lane, and the most canonical forms a query can have (4 tied nodes x 2 mirrors, x 2
 * orientations of z; geometry::kMaxCanonicalForms). */
#define CNN_CF_INFO_ROWS 6
#define CNN_CF_MAX_FORMS 16

/* std::max / std::min semantics (the first argument when the comparison is false). */
CNN_CF_INLINE double cnn_cf_max(double a, double b) { return a < b ? b : a; }
CNN_CF_INLINE double cnn_cf_min(double a, double b) { return b < a ? b : a; }

/* One lane. Reads quantity k at in[k * is], writes at f[k * os], nrm[k * os], info[k * os] (CNN_CF_INFO_ROWS
 * rows; row 4 receives 1 when the lane must be redone by cnn_cf_lane_scaled). `forced` 0: the canonical form
 * (form 0); 1: the form of symmetry `forced_sym` (rotation + 4 * mirror) with the other orientation of z on a
 * z tie when `other_z` (cnn_cf_forms). The loops over lanes pass forced = 0, a constant. */
CNN_CF_INLINE void cnn_cf_lane(const double* CNN_CF_RESTRICT in, int is, int gregory, int forced,
                               int forced_sym, int other_z, double* CNN_CF_RESTRICT f,
                               double* CNN_CF_RESTRICT nrm, double* CNN_CF_RESTRICT info, int os) {
  const double eps = 2.220446049250313e-16;
  const double ax = in[0 * is], ay = in[1 * is], az = in[2 * is];
  const double bx = in[3 * is], by = in[4 * is], bz = in[5 * is];
  const double cx = in[6 * is], cy = in[7 * is], cz = in[8 * is];
  const double dx = in[9 * is], dy = in[10 * is], dz = in[11 * is];
  const double sx = in[12 * is], sy = in[13 * is], sz = in[14 * is];
  double nax = 0.0, nay = 0.0, naz = 1.0, nbx = 0.0, nby = 0.0, nbz = 1.0;
  double ncx = 0.0, ncy = 0.0, ncz = 1.0, ndx = 0.0, ndy = 0.0, ndz = 1.0;
  double finite, big_nodes, big, bad, rescale;
  if (gregory) {
    nax = in[15 * is];
    nay = in[16 * is];
    naz = in[17 * is];
    nbx = in[18 * is];
    nby = in[19 * is];
    nbz = in[20 * is];
    ncx = in[21 * is];
    ncy = in[22 * is];
    ncz = in[23 * is];
    ndx = in[24 * is];
    ndy = in[25 * is];
    ndz = in[26 * is];
  }

  /* 1. Finite: the sum of the values is finite exactly when every value is, as long as no sum overflows; a
   *    lane with a magnitude beyond 1e50 (coordinates) or a normal beyond it goes through cnn_cf_lane_scaled,
   *    whose values are scaled first, so the sum cannot overflow here. `finite` is 0 when finite. */
  finite = (ax + ay + az + bx + by + bz + cx + cy + cz + dx + dy + dz + sx + sy + sz + nax + nay + naz + nbx +
            nby + nbz + ncx + ncy + ncz + ndx + ndy + ndz) *
           0.0;
  big_nodes = cnn_cf_max(cnn_cf_max(cnn_cf_max(fabs(ax), fabs(ay)), cnn_cf_max(fabs(az), fabs(bx))),
                         cnn_cf_max(cnn_cf_max(fabs(by), fabs(bz)), cnn_cf_max(fabs(cx), fabs(cy))));
  big_nodes =
      cnn_cf_max(big_nodes, cnn_cf_max(cnn_cf_max(fabs(cz), fabs(dx)), cnn_cf_max(fabs(dy), fabs(dz))));
  big = cnn_cf_max(big_nodes, cnn_cf_max(fabs(sx), cnn_cf_max(fabs(sy), fabs(sz))));
  rescale = ((big > 1e50) | (big < 1e-50)) ? 1.0 : 0.0;

  {
    /* 2. The symmetry (geometry::canonical_symmetry). S - X for each node X. */
    const double s0x = sx - ax, s0y = sy - ay, s0z = sz - az;
    const double s1x = sx - bx, s1y = sy - by, s1z = sz - bz;
    const double s2x = sx - cx, s2y = sy - cy, s2z = sz - cz;
    const double s3x = sx - dx, s3y = sy - dy, s3z = sz - dz;
    const double q0 = s0x * s0x + s0y * s0y + s0z * s0z, q1 = s1x * s1x + s1y * s1y + s1z * s1z;
    const double q2 = s2x * s2x + s2y * s2y + s2z * s2z, q3 = s3x * s3x + s3y * s3y + s3z * s3z;
    const double tie_noise = 16.0 * eps * big;
    /* dist_i ties the nearest when dist_i (1 - 1e-12) <= nearest + noise; compared squared. */
    const double nearest_plus = sqrt(cnn_cf_min(cnn_cf_min(q0, q1), cnn_cf_min(q2, q3))) + tie_noise;
    const double reach = nearest_plus * nearest_plus;
    const double shrink = (1.0 - 1e-12) * (1.0 - 1e-12);
    const int n0 = q0 * shrink <= reach, n1 = q1 * shrink <= reach, n2 = q2 * shrink <= reach,
              n3 = q3 * shrink <= reach;
    const int fr = forced_sym & 3;
    const int t0 = forced ? fr == 0 : n0, t1 = forced ? fr == 1 : n1, t2 = forced ? fr == 2 : n2;
    /* Canonical A, and the caller's nodes that follow it counter-clockwise (rotation r: A = node r). */
    const double rot = t0 ? 0.0 : t1 ? 1.0 : t2 ? 2.0 : 3.0;
    const double pax = t0   ? ax
                       : t1 ? bx
                       : t2 ? cx
                            : dx,
                 pay = t0   ? ay
                       : t1 ? by
                       : t2 ? cy
                            : dy,
                 paz = t0   ? az
                       : t1 ? bz
                       : t2 ? cz
                            : dz;
    const double p1x = t0   ? bx
                       : t1 ? cx
                       : t2 ? dx
                            : ax,
                 p1y = t0   ? by
                       : t1 ? cy
                       : t2 ? dy
                            : ay,
                 p1z = t0   ? bz
                       : t1 ? cz
                       : t2 ? dz
                            : az;
    const double p2x = t0   ? cx
                       : t1 ? dx
                       : t2 ? ax
                            : bx,
                 p2y = t0   ? cy
                       : t1 ? dy
                       : t2 ? ay
                            : by,
                 p2z = t0   ? cz
                       : t1 ? dz
                       : t2 ? az
                            : bz;
    const double p3x = t0   ? dx
                       : t1 ? ax
                       : t2 ? bx
                            : cx,
                 p3y = t0   ? dy
                       : t1 ? ay
                       : t2 ? by
                            : cy,
                 p3z = t0   ? dz
                       : t1 ? az
                       : t2 ? bz
                            : cz;
    const double sax = t0   ? s0x
                       : t1 ? s1x
                       : t2 ? s2x
                            : s3x,
                 say = t0   ? s0y
                       : t1 ? s1y
                       : t2 ? s2y
                            : s3y,
                 saz = t0   ? s0z
                       : t1 ? s1z
                       : t2 ? s2z
                            : s3z;
    /* Its two edges; the mirror when |AD| > |AB| (a tie: S nearer the line AD than the line AB). */
    const double e_bx = p1x - pax, e_by = p1y - pay, e_bz = p1z - paz;
    const double e_dx = p3x - pax, e_dy = p3y - pay, e_dz = p3z - paz;
    const double len_b = sqrt(e_bx * e_bx + e_by * e_by + e_bz * e_bz);
    const double len_d = sqrt(e_dx * e_dx + e_dy * e_dy + e_dz * e_dz);
    const double inv_b = 1.0 / len_b, inv_d = 1.0 / len_d;
    const int lengths_tie = fabs(len_d - len_b) <= 1e-12 * cnn_cf_max(len_d, len_b) + tie_noise;
    const double xbx = say * e_bz - saz * e_by, xby = saz * e_bx - sax * e_bz, xbz = sax * e_by - say * e_bx;
    const double xdx = say * e_dz - saz * e_dy, xdy = saz * e_dx - sax * e_dz, xdz = sax * e_dy - say * e_dx;
    const double to_b = sqrt(xbx * xbx + xby * xby + xbz * xbz) * inv_b;
    const double to_d = sqrt(xdx * xdx + xdy * xdy + xdz * xdz) * inv_d;
    const int line_tie = fabs(to_d - to_b) <= 1e-12 * cnn_cf_max(to_d, to_b) + tie_noise;
    const double mirror = forced        ? (double)(forced_sym >> 2)
                          : lengths_tie ? ((!line_tie & (to_d < to_b)) ? 1.0 : 0.0)
                                        : (len_d > len_b ? 1.0 : 0.0);
    const int mir = mirror != 0.0;
    /* Another canonical form exists: another node as near S, or |AD| = |AB| with S on the diagonal. */
    const int sym_tie = (n0 + n1 + n2 + n3 > 1) | (lengths_tie & line_tie);

    /* 3. The frame on the canonical A, B, D (geometry::AffineFrame::from_nodes): B and D swap under the
     * mirror. */
    const double abx = mir ? e_dx : e_bx, aby = mir ? e_dy : e_by, abz = mir ? e_dz : e_bz;
    const double adx = mir ? e_bx : e_dx, ady = mir ? e_by : e_dy, adz = mir ? e_bz : e_dz;
    const double length_ab = mir ? len_d : len_b, length_ad = mir ? len_b : len_d;
    const double scale = mir ? inv_d : inv_b;
    const double e1x = abx * scale, e1y = aby * scale, e1z = abz * scale;
    /* normal = e1 x AD; |normal| = |AD| sin(angle at A). */
    const double nx = e1y * adz - e1z * ady, ny = e1z * adx - e1x * adz, nz = e1x * ady - e1y * adx;
    const double normal_sq = nx * nx + ny * ny + nz * nz;
    const double min_normal = 1e-12 * cnn_cf_max(length_ad, length_ab);
    const int frame_ok = (length_ab > 0.0) & (length_ab <= 1.7976931348623157e308) &
                         !(length_ab <= 1e-12 * length_ad) & (normal_sq > min_normal * min_normal);
    /* One Gram-Schmidt step keeps the frame orthonormal for near-collinear A, B, D. */
    const double along = nx * e1x + ny * e1y + nz * e1z;
    const double gx = nx - along * e1x, gy = ny - along * e1y, gz = nz - along * e1z;
    const double inv_g = 1.0 / sqrt(gx * gx + gy * gy + gz * gz);
    const double e3x = gx * inv_g, e3y = gy * inv_g, e3z = gz * inv_g;
    const double e2x = e3y * e1z - e3z * e1y, e2y = e3z * e1x - e3x * e1z, e2z = e3x * e1y - e3y * e1x;

    /* 4. C, D and S in the frame: scale * R (x - A). */
    const double vcx = p2x - pax, vcy = p2y - pay, vcz = p2z - paz;
    const double xc = scale * (e1x * vcx + e1y * vcy + e1z * vcz);
    const double yc = scale * (e2x * vcx + e2y * vcy + e2z * vcz);
    const double zc0 = scale * (e3x * vcx + e3y * vcy + e3z * vcz);
    const double xd = scale * (e1x * adx + e1y * ady + e1z * adz);
    const double yd = scale * (e2x * adx + e2y * ady + e2z * adz);
    const double xs = scale * (e1x * sax + e1y * say + e1z * saz);
    const double ys = scale * (e2x * sax + e2y * say + e2z * saz);
    const double zs0 = scale * (e3x * sax + e3y * say + e3z * saz);
    /* z oriented so that S (on the plane: C) is on its + side; a height within 1e-12 plus the rounding of the
     * world coordinates counts as 0, so that the orientation does not depend on where the query is placed.
     * Both on the plane: a z tie, no flip (the other orientation is the form with other_z). */
    const double z_tol = 1e-12 + 16.0 * eps * big * scale;
    const int s_on = fabs(zs0) <= z_tol, z_tie = s_on & (fabs(zc0) <= z_tol);
    const int flip = z_tie ? other_z : (s_on ? zc0 < 0.0 : zs0 < 0.0);
    const double zsign = flip ? -1.0 : 1.0;
    const double zc = zsign * zc0, zs = zsign * zs0;

    /* 5. A collapsed segment, judged against the world coordinates' rounding (geometry::is_degenerate_segment
     *    on the local nodes 0, (1,0,0), C, D with noise eps * max|node| * scale), in squared form. */
    const double noise16 = 16.0 * (eps * big_nodes * scale);
    const double n01 = 1.0, n02 = xc * xc + yc * yc + zc * zc, n03 = xd * xd + yd * yd;
    const double n12 = (xc - 1.0) * (xc - 1.0) + yc * yc + zc * zc, n13 = (xd - 1.0) * (xd - 1.0) + yd * yd;
    const double n23 = (xc - xd) * (xc - xd) + (yc - yd) * (yc - yd) + zc * zc;
    const double longest_sq =
        cnn_cf_max(cnn_cf_max(cnn_cf_max(n01, n02), cnn_cf_max(n03, n12)), cnn_cf_max(n13, n23));
    const double shortest_sq =
        cnn_cf_min(cnn_cf_min(cnn_cf_min(n01, n02), cnn_cf_min(n03, n12)), cnn_cf_min(n13, n23));
    const double noise_sq = noise16 * noise16;
    const double coincident_sq = cnn_cf_max(1e-20 * longest_sq, noise_sq);
    const double flat_sq = cnn_cf_max(1e-24 * longest_sq, noise_sq) * longest_sq;
    /* Twice the area: |(C - A) x (D - B)|. */
    const double wx = yc * 0.0 - zc * yd, wy = zc * (xd - 1.0) - xc * 0.0, wz = xc * yd - yc * (xd - 1.0);
    /* A corner of zero angle: next . prev > 0 and next x prev ~ 0. At A: next B = (1,0,0), prev D. */
    const int fold_a = (xd > 0.0) & !(yd * yd > flat_sq);
    /* At B: next C - B, prev A - B = (-1, 0, 0). */
    const int fold_b = (-(xc - 1.0) > 0.0) & !(zc * zc + yc * yc > flat_sq);
    /* At C: next D - C, prev B - C. */
    const double ncdx = xd - xc, ncdy = yd - yc, ncdz = -zc, pcbx = 1.0 - xc, pcby = -yc, pcbz = -zc;
    const double kcx = ncdy * pcbz - ncdz * pcby, kcy = ncdz * pcbx - ncdx * pcbz,
                 kcz = ncdx * pcby - ncdy * pcbx;
    const int fold_c =
        (ncdx * pcbx + ncdy * pcby + ncdz * pcbz > 0.0) & !(kcx * kcx + kcy * kcy + kcz * kcz > flat_sq);
    /* At D: next A - D = -D, prev C - D. */
    const double pdcx = xc - xd, pdcy = yc - yd, pdcz = zc;
    const double kdx = -yd * pdcz, kdy = xd * pdcz, kdz = -xd * pdcy + yd * pdcx;
    const int fold_d = (-xd * pdcx - yd * pdcy > 0.0) & !(kdx * kdx + kdy * kdy + kdz * kdz > flat_sq);
    const int collapsed = !(longest_sq > 0.0) | !(shortest_sq > coincident_sq) |
                          !(0.25 * (wx * wx + wy * wy + wz * wz) > flat_sq) | fold_a | fold_b | fold_c |
                          fold_d;

    double status;
    bad = (frame_ok & !collapsed) ? 0.0 : 1.0;
    f[0 * os] = xc;
    f[1 * os] = yc;
    f[2 * os] = zc;
    f[3 * os] = xd;
    f[4 * os] = yd;
    f[5 * os] = xs;
    f[6 * os] = ys;
    f[7 * os] = zs;
    if (gregory) {
      /* 6. Node normals in the canonical order, rotated into the (oriented) frame. Front: n_z > max(1e-12,
       * noise) for the unit normal, i.e. w_z > min_nz |n| for the rotated one; all on the back side: all
       * reversed. */
      const double min_nz = cnn_cf_max(1e-12, noise16);
      const double m_nz = min_nz * min_nz;
      const double f3x = zsign * e3x, f3y = zsign * e3y, f3z = zsign * e3z;
      const double c0x = t0   ? nax
                         : t1 ? nbx
                         : t2 ? ncx
                              : ndx,
                   c0y = t0   ? nay
                         : t1 ? nby
                         : t2 ? ncy
                              : ndy,
                   c0z = t0   ? naz
                         : t1 ? nbz
                         : t2 ? ncz
                              : ndz;
      const double r1x = t0   ? nbx
                         : t1 ? ncx
                         : t2 ? ndx
                              : nax,
                   r1y = t0   ? nby
                         : t1 ? ncy
                         : t2 ? ndy
                              : nay,
                   r1z = t0   ? nbz
                         : t1 ? ncz
                         : t2 ? ndz
                              : naz;
      const double c2x = t0   ? ncx
                         : t1 ? ndx
                         : t2 ? nax
                              : nbx,
                   c2y = t0   ? ncy
                         : t1 ? ndy
                         : t2 ? nay
                              : nby,
                   c2z = t0   ? ncz
                         : t1 ? ndz
                         : t2 ? naz
                              : nbz;
      const double r3x = t0   ? ndx
                         : t1 ? nax
                         : t2 ? nbx
                              : ncx,
                   r3y = t0   ? ndy
                         : t1 ? nay
                         : t2 ? nby
                              : ncy,
                   r3z = t0   ? ndz
                         : t1 ? naz
                         : t2 ? nbz
                              : ncz;
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
      bad = (front | back) ? bad : 1.0;
      bad = ((l0 > 0.0) & (l1 > 0.0) & (l2 > 0.0) & (l3 > 0.0)) ? bad : 1.0;
      rescale = ((l0 > 1e-100) & (l0 < 1e100) & (l1 > 1e-100) & (l1 < 1e100) & (l2 > 1e-100) & (l2 < 1e100) &
                 (l3 > 1e-100) & (l3 < 1e100))
                    ? rescale
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
    status = finite == 0.0 ? (bad != 0.0 ? (double)CNN_CF_STATUS_DEGENERATE : (double)CNN_CF_STATUS_OK)
                           : (double)CNN_CF_STATUS_INVALID;
    info[0 * os] = status;
    info[1 * os] = rot + 4.0 * mirror;
    info[2 * os] = (mir ? -1.0 : 1.0) * zsign;
    info[3 * os] = scale;
    info[4 * os] = rescale;
    info[5 * os] = (double)(sym_tie + 2 * z_tie);
  }
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

/* cnn_cf_max and cnn_cf_min in float (fmaxf and fminf do not vectorise: their NaN rule is not the
 * instruction's). */
CNN_CF_INLINE float cnn_cff_max(float a, float b) { return a < b ? b : a; }
CNN_CF_INLINE float cnn_cff_min(float a, float b) { return b < a ? b : a; }

/* One lane. rel: 12 rows at rel[k * s]: A - S, B - S, C - S, D - S (x, y, z each), scaled by a power of two.
 * Writes ff[k * s], 8 feature rows, and fi[k * s]: 0 symmetry code, 1 orientation, 2 scale (1 / |AB|), 3
 * status (0 or 5), 4 redo (1: the double pass decides this lane). `domain` 0: no domain test (d unused). */
CNN_CF_INLINE void cnn_cff_lane(const float* CNN_CF_RESTRICT rel, int s,
                                const struct cnn_domain* CNN_CF_RESTRICT d, int domain,
                                float* CNN_CF_RESTRICT ff, float* CNN_CF_RESTRICT fi) {
  const float u = 5.9604645e-8f; /* 2^-24 */
  /* The nodes relative to S: the same values whatever the caller's node order, so the lane's arithmetic
   * (which takes differences of these after the canonical relabelling) gives the same bits for all 8 orders.
   */
  const float ax = rel[0 * s], ay = rel[1 * s], az = rel[2 * s];
  const float bx = rel[3 * s], by = rel[4 * s], bz = rel[5 * s];
  const float cx = rel[6 * s], cy = rel[7 * s], cz = rel[8 * s];
  const float dx = rel[9 * s], dy = rel[10 * s], dz = rel[11 * s];
  float redo;
  /* Magnitudes; a NaN or infinity fails every comparison below and sends the lane to the double pass. */
  const float m_ab = cnn_cff_max(cnn_cff_max(fabsf(ax), fabsf(ay)), cnn_cff_max(fabsf(az), fabsf(bx)));
  const float m_bc = cnn_cff_max(cnn_cff_max(fabsf(by), fabsf(bz)), cnn_cff_max(fabsf(cx), fabsf(cy)));
  const float m_cd = cnn_cff_max(cnn_cff_max(fabsf(cz), fabsf(dx)), cnn_cff_max(fabsf(dy), fabsf(dz)));
  const float m = cnn_cff_max(cnn_cff_max(m_ab, m_bc), m_cd);
  const float mq = 256.0f * u * m * m;
  /* Their sum times 0: NaN when a value is not finite (or the scaled values overflowed float). */
  const float finite = (ax + ay + az + bx + by + bz + cx + cy + cz + dx + dy + dz) * 0.0f;
  redo = ((finite == 0.0f) & (m >= 1e-12f) & (m <= 1e12f)) ? 0.0f : 1.0f;
  {
    /* The nearest node: one, by a margin. */
    const float q0 = ax * ax + ay * ay + az * az, q1 = bx * bx + by * by + bz * bz;
    const float q2 = cx * cx + cy * cy + cz * cz, q3 = dx * dx + dy * dy + dz * dz;
    const float reach = cnn_cff_min(cnn_cff_min(q0, q1), cnn_cff_min(q2, q3)) + mq;
    const int t0 = q0 <= reach, t1 = q1 <= reach, t2 = q2 <= reach, t3 = q3 <= reach;
    const float rot = t0 ? 0.0f : t1 ? 1.0f : t2 ? 2.0f : 3.0f;
    const float pax = t0   ? ax
                      : t1 ? bx
                      : t2 ? cx
                           : dx,
                pay = t0   ? ay
                      : t1 ? by
                      : t2 ? cy
                           : dy,
                paz = t0   ? az
                      : t1 ? bz
                      : t2 ? cz
                           : dz;
    const float p1x = t0   ? bx
                      : t1 ? cx
                      : t2 ? dx
                           : ax,
                p1y = t0   ? by
                      : t1 ? cy
                      : t2 ? dy
                           : ay,
                p1z = t0   ? bz
                      : t1 ? cz
                      : t2 ? dz
                           : az;
    const float p2x = t0   ? cx
                      : t1 ? dx
                      : t2 ? ax
                           : bx,
                p2y = t0   ? cy
                      : t1 ? dy
                      : t2 ? ay
                           : by,
                p2z = t0   ? cz
                      : t1 ? dz
                      : t2 ? az
                           : bz;
    const float p3x = t0   ? dx
                      : t1 ? ax
                      : t2 ? bx
                           : cx,
                p3y = t0   ? dy
                      : t1 ? ay
                      : t2 ? by
                           : cy,
                p3z = t0   ? dz
                      : t1 ? az
                      : t2 ? bz
                           : cz;
    const float sax = -pax, say = -pay, saz = -paz; /* S - A */
    const float e_bx = p1x - pax, e_by = p1y - pay, e_bz = p1z - paz;
    const float e_dx = p3x - pax, e_dy = p3y - pay, e_dz = p3z - paz;
    const float lb2 = e_bx * e_bx + e_by * e_by + e_bz * e_bz, ld2 = e_dx * e_dx + e_dy * e_dy + e_dz * e_dz;
    /* The mirror when |AD| > |AB|, by a margin. */
    const int mir = ld2 > lb2;
    const float abx = mir ? e_dx : e_bx, aby = mir ? e_dy : e_by, abz = mir ? e_dz : e_bz;
    const float adx = mir ? e_bx : e_dx, ady = mir ? e_by : e_dy, adz = mir ? e_bz : e_dz;
    const float lab2 = mir ? ld2 : lb2, lad2 = mir ? lb2 : ld2;
    const float scale = 1.0f / sqrtf(lab2);
    const float e1x = abx * scale, e1y = aby * scale, e1z = abz * scale;
    const float nx = e1y * adz - e1z * ady, ny = e1z * adx - e1x * adz, nz = e1x * ady - e1y * adx;
    const float normal_sq = nx * nx + ny * ny + nz * nz;
    const float along = nx * e1x + ny * e1y + nz * e1z;
    const float gx = nx - along * e1x, gy = ny - along * e1y, gz = nz - along * e1z;
    const float inv_g = 1.0f / sqrtf(gx * gx + gy * gy + gz * gz);
    const float e3x = gx * inv_g, e3y = gy * inv_g, e3z = gz * inv_g;
    const float e2x = e3y * e1z - e3z * e1y, e2y = e3z * e1x - e3x * e1z, e2z = e3x * e1y - e3y * e1x;
    const float vcx = p2x - pax, vcy = p2y - pay, vcz = p2z - paz;
    const float xc = scale * (e1x * vcx + e1y * vcy + e1z * vcz);
    const float yc = scale * (e2x * vcx + e2y * vcy + e2z * vcz);
    const float zc0 = scale * (e3x * vcx + e3y * vcy + e3z * vcz);
    const float xd = scale * (e1x * adx + e1y * ady + e1z * adz);
    const float yd = scale * (e2x * adx + e2y * ady + e2z * adz);
    const float xs = scale * (e1x * sax + e1y * say + e1z * saz);
    const float ys = scale * (e2x * sax + e2y * say + e2z * saz);
    const float zs0 = scale * (e3x * sax + e3y * say + e3z * saz);
    /* The features' error bound delta: 32 u (1 + R) over sin(angle at A) (its square >= 1e-4 is required
     * below), R the query's extent over |AB| (every node within m of S, so within 2 m of A). */
    const float extent = 2.0f * m * scale;
    const float amp = sqrtf(lad2 / cnn_cff_max(normal_sq, 1e-30f));
    const float delta = 32.0f * u * (1.0f + extent) * amp;
    /* z oriented so that S is on its + side; S decidedly off the plane. */
    const float zsign = zs0 < 0.0f ? -1.0f : 1.0f;
    const float zc = zsign * zc0, zs = zsign * zs0;
    /* The segment far from collapsed: sides and diagonals (squared, canonical units), and each corner's cross
     * product, beyond the error bound. */
    const float n02 = xc * xc + yc * yc + zc * zc, n03 = xd * xd + yd * yd;
    const float n12 = (xc - 1.0f) * (xc - 1.0f) + yc * yc + zc * zc,
                n13 = (xd - 1.0f) * (xd - 1.0f) + yd * yd;
    const float n23 = (xc - xd) * (xc - xd) + (yc - yd) * (yc - yd) + zc * zc;
    const float longest =
        cnn_cff_max(cnn_cff_max(cnn_cff_max(1.0f, n02), cnn_cff_max(n03, n12)), cnn_cff_max(n13, n23));
    const float shortest =
        cnn_cff_min(cnn_cff_min(cnn_cff_min(1.0f, n02), cnn_cff_min(n03, n12)), cnn_cff_min(n13, n23));
    const float side_err = 4.0f * delta * (1.0f + longest);
    /* A corner is folded when its cross product is below max(1e-12 longest, the double pass's noise, at most
     * 3.6e-9 longest here); decided unfolded above 1e-7 longest plus its error bound, twice the sum of the
     * edges' components times delta (at A and B 4 delta). */
    const float fold0 = 1e-7f * longest;
    /* Corner cross products (next - X) x (prev - X): A (0, 0, yd); B; C; D (as cnn_cf_lane's fold tests). */
    const float kb_sq = zc * zc + yc * yc; /* at B: (0, -z_C, y_C) */
    const float ncdx = xd - xc, ncdy = yd - yc, ncdz = -zc, pcbx = 1.0f - xc, pcby = -yc, pcbz = -zc;
    const float kcx = ncdy * pcbz - ncdz * pcby, kcy = ncdz * pcbx - ncdx * pcbz,
                kcz = ncdx * pcby - ncdy * pcbx;
    const float pdcx = xc - xd, pdcy = yc - yd, pdcz = zc;
    const float kdx = -yd * pdcz, kdy = xd * pdcz, kdz = -xd * pdcy + yd * pdcx;
    const float wz = xc * yd - yc * (xd - 1.0f);
    const float fold_ab = fold0 + 4.0f * delta;
    const float fold_c =
        fold0 +
        4.0f * delta * (fabsf(ncdx) + fabsf(ncdy) + fabsf(ncdz) + fabsf(pcbx) + fabsf(pcby) + fabsf(pcbz));
    const float fold_d =
        fold0 + 4.0f * delta * (fabsf(xd) + fabsf(yd) + fabsf(pdcx) + fabsf(pdcy) + fabsf(pdcz));
    const float fold_w = fold0 + 4.0f * delta * (fabsf(xc) + fabsf(yc) + fabsf(xd - 1.0f) + fabsf(yd));
    const int unfolded = (yd > fold_ab) & (kb_sq > fold_ab * fold_ab) &
                         (kcx * kcx + kcy * kcy + kcz * kcz > fold_c * fold_c) &
                         (kdx * kdx + kdy * kdy + kdz * kdz > fold_d * fold_d) & (wz * wz > fold_w * fold_w);
    /* The double pass's noise terms (16 eps max |x|, x the world coordinates; scaled, max |x| <= 1 + m since
     * |S| scaled is below 1) far below the margins: |AB| >= 1e-6 (1 + m). */
    const int quiet = (1.0f + m) * (1.0f + m) <= 1e12f * lab2;
    const int decided = (t0 + t1 + t2 + t3 == 1) & quiet & (fabsf(ld2 - lb2) > mq) & (lab2 > mq) &
                        (lad2 >= 1e-6f * lab2) & (normal_sq >= 1e-4f * lad2) & (extent < 1e4f) &
                        (fabsf(zs0) > 2.0f * delta + 4e-9f * (1.0f + extent)) &
                        (shortest > 1e-6f * longest + side_err) & unfolded;
    redo = decided ? redo : 1.0f;
    ff[0 * s] = xc;
    ff[1 * s] = yc;
    ff[2 * s] = zc;
    ff[3 * s] = xd;
    ff[4 * s] = yd;
    ff[5 * s] = xs;
    ff[6 * s] = ys;
    ff[7 * s] = zs;
    fi[0 * s] = rot + (mir ? 4.0f : 0.0f);
    fi[1 * s] = (mir ? -1.0f : 1.0f) * zsign;
    fi[2 * s] = scale;
    fi[3 * s] = 0.0f;
    if (domain) {
      /* cnn_domain_lane's tests, each as a violation v (the test fails when v > 0, or >= 0 if strict) with a
       * bound m on its error: failed when v - m > 0, undecided when v + m >= 0 and none failed. */
      const float xy = (float)d->xy, zl = (float)d->z, adb = (float)d->ad_bound;
      const float inv_1tol = (float)d->inv_one_plus_tol, tol = (float)d->tol;
      const float big =
          1.0f +
          cnn_cff_max(cnn_cff_max(cnn_cff_max(fabsf(xc), fabsf(yc)), cnn_cff_max(fabsf(zc), fabsf(xd))),
                      cnn_cff_max(cnn_cff_max(fabsf(yd), fabsf(xs)), cnn_cff_max(fabsf(ys), fabsf(zs))));
      /* Error bounds, twice the sum of the test's partial derivatives (in `big`) times delta, plus rounding.
       */
      const float m1 = 2.0f * delta + 8.0f * u * big;
      const float m_ad = 8.0f * big * delta + 8.0f * u * big * big;
      const float off_ad = d->ad_not_longer ? 0.0f : -1e30f, off_near = d->nearest_a ? 0.0f : -1e30f;
      const float off_seg = d->segment_test ? 0.0f : -1e30f, off_convex = d->convex ? 0.0f : -1e30f;
      float fail = -1.0f, unsure = -1.0f; /* max of v - m and of v + m */
      int k;
      CNN_CF_UNROLL
      for (k = 0; k < 8; ++k) {
        const float fk = ff[k * s];
        const float lo = (float)d->lo[k], hi = (float)d->hi[k];
        const float mk = m1 + 4.0f * u * (fabsf(lo) + fabsf(hi));
        const float v = cnn_cff_max(lo - fk, fk - hi);
        fail = cnn_cff_max(fail, v - mk);
        unsure = cnn_cff_max(unsure, v + mk);
      }
      {
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
        /* Error bounds of the segment and nearest tests from their partial derivatives. */
        const float m_seg2 = 2.0f * (fabsf(ys) + fabsf(yd)) * delta + 8.0f * u * big * big;
        const float m_seg3 =
            2.0f * (fabsf(xs * yd) + 2.0f * fabsf(ys * xd) + fabsf(ys * yd) + fabsf(ys * xs) + ys * ys) *
                delta +
            16.0f * u * big * big * big;
        const float m_near = 4.0f * delta *
                                 (2.0f * (fabsf(xs) + fabsf(ys) + fabsf(zs)) + 2.0f + fabsf(xc) + fabsf(yc) +
                                  fabsf(zc) + fabsf(xd) + fabsf(yd)) +
                             16.0f * u * big * big;
        const float vseg1 = -fabsf(yd) + off_seg;
        const float vseg2 = (-(ys * yd) - tol * lengths) + off_seg;
        const float vseg3 = (-(ys * (xs * yd - ys * xd)) - tol * lengths * sqrtf(r_sq)) + off_seg;
        fail = cnn_cff_max(
            fail, cnn_cff_max(cnn_cff_max(vxy - mxy, vz - mz), cnn_cff_max(vad - m_ad, vnear - m_near)));
        unsure = cnn_cff_max(
            unsure, cnn_cff_max(cnn_cff_max(vxy + mxy, vz + mz), cnn_cff_max(vad + m_ad, vnear + m_near)));
        fail = cnn_cff_max(fail, cnn_cff_max(vseg1 - m1, cnn_cff_max(vseg2 - m_seg2, vseg3 - m_seg3)));
        unsure = cnn_cff_max(unsure, cnn_cff_max(vseg1 + m1, cnn_cff_max(vseg2 + m_seg2, vseg3 + m_seg3)));
      }
      {
        /* Convexity: a corner fails when (next x prev) . (0, 0, yd) <= -tol |next| |prev| yd, i.e. (yd > 0 in
         * the frame) when the cross product's z, kz, is <= -tol |next| |prev|: kz = yd, yc, kcz, kdz at A, B,
         * C, D, each with the error bound of its fold test (tol's term, below 2 tol longest, added). */
        const float mt = 8.0f * u * longest + 2.0f * tol * longest;
        const float va = -yd + off_convex, vb = -yc + off_convex, vc = -kcz + off_convex,
                    vd = -kdz + off_convex;
        fail = cnn_cff_max(fail, cnn_cff_max(cnn_cff_max(va - fold_ab - mt, vb - fold_ab - mt),
                                             cnn_cff_max(vc - fold_c - mt, vd - fold_d - mt)));
        unsure = cnn_cff_max(unsure, cnn_cff_max(cnn_cff_max(va + fold_ab + mt, vb + fold_ab + mt),
                                                 cnn_cff_max(vc + fold_c + mt, vd + fold_d + mt)));
      }
      fi[3 * s] = fail > 0.0f ? (float)CNN_CF_STATUS_OUT_OF_DOMAIN : 0.0f;
      redo = ((fail > 0.0f) | !(unsure >= 0.0f)) ? redo : 1.0f;
    }
    fi[4 * s] = redo;
  }
}

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

#endif /* CONTACTNN_CANONICAL_FRAME_H */
