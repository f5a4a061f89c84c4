/* canonical_frame_geometry.h (part of canonical_frame.h): the geometry that the double pass
 * (canonical_frame_lane.h) and the float pass (canonical_frame_float.h) share, written once and defined in
 * each precision: the choice of a node by the canonical rotation, the frame of SPEC 4 on the canonical A, B,
 * D with C, D and S in it, and the sides and corners of the canonical segment. Each is the same statements in
 * either precision (constants as (T)1, exact), always inlined into its lane: a lane rounds as it would with
 * the statements written out in it. */
#ifndef CONTACTNN_CANONICAL_FRAME_GEOMETRY_H
#define CONTACTNN_CANONICAL_FRAME_GEOMETRY_H

#include "search/canonical_frame_base.h"

/* The caller's node that is canonical node k when canonical A is the caller's node 0 (t0), 1 (t1), 2 (t2) or
 * else 3: x0..x3 are a quantity of the caller's nodes k, k + 1, k + 2, k + 3 (mod 4). Either precision. */
#define CNN_CF_PICK(t0, t1, t2, x0, x1, x2, x3) ((t0) ? (x0) : (t1) ? (x1) : (t2) ? (x2) : (x3))

/* The canonical relabelling of a lane: canonical A is the caller's node 0 (t0), 1 (t1), 2 (t2) or else 3
 * (rotation rot), mirrored when mir; the canonical segment's vectors from A, and scale = 1 / |AB|. Each
 * precision adds its own fields after these. */
#define CNN_CF_CANON_FIELDS(T)                                                                  \
  int t0, t1, t2, mir;                                                                          \
  T rot;                                                                                        \
  T abx, aby, abz, adx, ady, adz; /* B - A, D - A (canonical: B and D swap under the mirror) */ \
  T acx, acy, acz, asx, asy, asz; /* C - A, S - A */                                            \
  T scale

/* The four nodes' coordinates of a lane, quantity k at in[k * is], into QUERY's fields ax .. dz. */
#define CNN_CF_DEFINE_LOAD_NODES(NAME, QUERY, T)                                                  \
  CNN_CF_INLINE void NAME(const T* CNN_CF_RESTRICT in, int is, struct QUERY* CNN_CF_RESTRICT q) { \
    q->ax = in[0 * is];                                                                           \
    q->ay = in[1 * is];                                                                           \
    q->az = in[2 * is];                                                                           \
    q->bx = in[3 * is];                                                                           \
    q->by = in[4 * is];                                                                           \
    q->bz = in[5 * is];                                                                           \
    q->cx = in[6 * is];                                                                           \
    q->cy = in[7 * is];                                                                           \
    q->cz = in[8 * is];                                                                           \
    q->dx = in[9 * is];                                                                           \
    q->dy = in[10 * is];                                                                          \
    q->dz = in[11 * is];                                                                          \
  }

/* The caller's nodes from canonical A on (t0, t1, t2 as above; QUERY has the nodes' fields ax .. dz): A and
 * its edges to the next node, B, and to the previous one, D, before the mirror. */
#define CNN_CF_EDGES_FIELDS(T) T pax, pay, paz, e_bx, e_by, e_bz, e_dx, e_dy, e_dz

#define CNN_CF_DEFINE_ROTATE(NAME, QUERY, EDGES, T)                                      \
  CNN_CF_INLINE void NAME(const struct QUERY* CNN_CF_RESTRICT q, int t0, int t1, int t2, \
                          struct EDGES* CNN_CF_RESTRICT r) {                             \
    const T pax = CNN_CF_PICK(t0, t1, t2, q->ax, q->bx, q->cx, q->dx);                   \
    const T pay = CNN_CF_PICK(t0, t1, t2, q->ay, q->by, q->cy, q->dy);                   \
    const T paz = CNN_CF_PICK(t0, t1, t2, q->az, q->bz, q->cz, q->dz);                   \
    r->pax = pax;                                                                        \
    r->pay = pay;                                                                        \
    r->paz = paz;                                                                        \
    r->e_bx = CNN_CF_PICK(t0, t1, t2, q->bx, q->cx, q->dx, q->ax) - pax;                 \
    r->e_by = CNN_CF_PICK(t0, t1, t2, q->by, q->cy, q->dy, q->ay) - pay;                 \
    r->e_bz = CNN_CF_PICK(t0, t1, t2, q->bz, q->cz, q->dz, q->az) - paz;                 \
    r->e_dx = CNN_CF_PICK(t0, t1, t2, q->dx, q->ax, q->bx, q->cx) - pax;                 \
    r->e_dy = CNN_CF_PICK(t0, t1, t2, q->dy, q->ay, q->by, q->cy) - pay;                 \
    r->e_dz = CNN_CF_PICK(t0, t1, t2, q->dz, q->az, q->bz, q->cz) - paz;                 \
  }

/* c's vectors from A under the mirror `mir` (B and D swap; c's t0, t1, t2 set): AB, AD and C - A. */
#define CNN_CF_DEFINE_MIRROR(NAME, QUERY, EDGES, CANON)                                                 \
  CNN_CF_INLINE void NAME(const struct QUERY* CNN_CF_RESTRICT q, const struct EDGES* CNN_CF_RESTRICT e, \
                          int mir, struct CANON* CNN_CF_RESTRICT c) {                                   \
    c->mir = mir;                                                                                       \
    c->abx = mir ? e->e_dx : e->e_bx;                                                                   \
    c->aby = mir ? e->e_dy : e->e_by;                                                                   \
    c->abz = mir ? e->e_dz : e->e_bz;                                                                   \
    c->adx = mir ? e->e_bx : e->e_dx;                                                                   \
    c->ady = mir ? e->e_by : e->e_dy;                                                                   \
    c->adz = mir ? e->e_bz : e->e_dz;                                                                   \
    c->acx = CNN_CF_PICK(c->t0, c->t1, c->t2, q->cx, q->dx, q->ax, q->bx) - e->pax;                     \
    c->acy = CNN_CF_PICK(c->t0, c->t1, c->t2, q->cy, q->dy, q->ay, q->by) - e->pay;                     \
    c->acz = CNN_CF_PICK(c->t0, c->t1, c->t2, q->cz, q->dz, q->az, q->bz) - e->paz;                     \
  }

/* The frame (geometry::AffineFrame::from_nodes): e1 along AB, e3 the normal e1 x AD made orthogonal to e1 by
 * one Gram-Schmidt step (orthonormal for near-collinear A, B, D), e2 = e3 x e1; normal_sq = |e1 x AD|^2 =
 * (|AD| sin(angle at A))^2. C, D and S in it: scale * R (x - A), z not yet oriented. */
#define CNN_CF_FRAME_FIELDS(T)                   \
  T e1x, e1y, e1z, e2x, e2y, e2z, e3x, e3y, e3z; \
  T normal_sq;                                   \
  T xc, yc, zc0, xd, yd, xs, ys, zs0

#define CNN_CF_DEFINE_FRAME(NAME, CANON, FRAME, T, SQRT)                                            \
  CNN_CF_INLINE void NAME(const struct CANON* CNN_CF_RESTRICT c, struct FRAME* CNN_CF_RESTRICT r) { \
    const T scale = c->scale, adx = c->adx, ady = c->ady, adz = c->adz;                             \
    const T e1x = c->abx * scale, e1y = c->aby * scale, e1z = c->abz * scale;                       \
    const T nx = e1y * adz - e1z * ady, ny = e1z * adx - e1x * adz, nz = e1x * ady - e1y * adx;     \
    const T along = nx * e1x + ny * e1y + nz * e1z;                                                 \
    const T gx = nx - along * e1x, gy = ny - along * e1y, gz = nz - along * e1z;                    \
    const T inv_g = (T)1 / SQRT(gx * gx + gy * gy + gz * gz);                                       \
    const T e3x = gx * inv_g, e3y = gy * inv_g, e3z = gz * inv_g;                                   \
    const T e2x = e3y * e1z - e3z * e1y, e2y = e3z * e1x - e3x * e1z, e2z = e3x * e1y - e3y * e1x;  \
    r->normal_sq = nx * nx + ny * ny + nz * nz;                                                     \
    r->xc = scale * (e1x * c->acx + e1y * c->acy + e1z * c->acz);                                   \
    r->yc = scale * (e2x * c->acx + e2y * c->acy + e2z * c->acz);                                   \
    r->zc0 = scale * (e3x * c->acx + e3y * c->acy + e3z * c->acz);                                  \
    r->xd = scale * (e1x * adx + e1y * ady + e1z * adz);                                            \
    r->yd = scale * (e2x * adx + e2y * ady + e2z * adz);                                            \
    r->xs = scale * (e1x * c->asx + e1y * c->asy + e1z * c->asz);                                   \
    r->ys = scale * (e2x * c->asx + e2y * c->asy + e2z * c->asz);                                   \
    r->zs0 = scale * (e3x * c->asx + e3y * c->asy + e3z * c->asz);                                  \
    r->e1x = e1x;                                                                                   \
    r->e1y = e1y;                                                                                   \
    r->e1z = e1z;                                                                                   \
    r->e2x = e2x;                                                                                   \
    r->e2y = e2y;                                                                                   \
    r->e2z = e2z;                                                                                   \
    r->e3x = e3x;                                                                                   \
    r->e3y = e3y;                                                                                   \
    r->e3z = e3z;                                                                                   \
  }

/* The canonical segment's sides and corners, the local nodes A = 0, B = (1, 0, 0), C = (xc, yc, zc) and
 * D = (xd, yd, 0) (z oriented): the longest and shortest side or diagonal squared; at each corner X the
 * edges to the next and the previous node and their cross product (next - X) x (prev - X), which is
 * (0, 0, yd) at A and (0, -zc, yc) at B; wz, the z of (C - A) x (D - B), twice the area projected. */
#define CNN_CF_CORNERS_FIELDS(T)                                                             \
  T longest_sq, shortest_sq;                                                                 \
  T ncdx, ncdy, ncdz, pcbx, pcby, pcbz, kcx, kcy, kcz; /* at C: D - C, B - C, their cross */ \
  T pdcx, pdcy, pdcz, kdx, kdy, kdz;                   /* at D: C - D, and -D x (C - D) */   \
  T wz

#define CNN_CF_DEFINE_CORNERS(NAME, CORNERS, T, MAX, MIN)                                                   \
  CNN_CF_INLINE void NAME(T xc, T yc, T zc, T xd, T yd, struct CORNERS* CNN_CF_RESTRICT r) {                \
    const T n02 = xc * xc + yc * yc + zc * zc, n03 = xd * xd + yd * yd;                                     \
    const T n12 = (xc - (T)1) * (xc - (T)1) + yc * yc + zc * zc, n13 = (xd - (T)1) * (xd - (T)1) + yd * yd; \
    const T n23 = (xc - xd) * (xc - xd) + (yc - yd) * (yc - yd) + zc * zc;                                  \
    const T ncdx = xd - xc, ncdy = yd - yc, ncdz = -zc, pcbx = (T)1 - xc, pcby = -yc, pcbz = -zc;           \
    const T pdcx = xc - xd, pdcy = yc - yd, pdcz = zc;                                                      \
    r->longest_sq = MAX(MAX(MAX((T)1, n02), MAX(n03, n12)), MAX(n13, n23));                                 \
    r->shortest_sq = MIN(MIN(MIN((T)1, n02), MIN(n03, n12)), MIN(n13, n23));                                \
    r->ncdx = ncdx;                                                                                         \
    r->ncdy = ncdy;                                                                                         \
    r->ncdz = ncdz;                                                                                         \
    r->pcbx = pcbx;                                                                                         \
    r->pcby = pcby;                                                                                         \
    r->pcbz = pcbz;                                                                                         \
    r->kcx = ncdy * pcbz - ncdz * pcby;                                                                     \
    r->kcy = ncdz * pcbx - ncdx * pcbz;                                                                     \
    r->kcz = ncdx * pcby - ncdy * pcbx;                                                                     \
    r->pdcx = pdcx;                                                                                         \
    r->pdcy = pdcy;                                                                                         \
    r->pdcz = pdcz;                                                                                         \
    r->kdx = -yd * pdcz;                                                                                    \
    r->kdy = xd * pdcz;                                                                                     \
    r->kdz = -xd * pdcy + yd * pdcx;                                                                        \
    r->wz = xc * yd - yc * (xd - (T)1);                                                                     \
  }

struct cnn_cf_edges {
  CNN_CF_EDGES_FIELDS(double);
};
struct cnn_cff_edges {
  CNN_CF_EDGES_FIELDS(float);
};
struct cnn_cf_frame {
  CNN_CF_FRAME_FIELDS(double);
};
struct cnn_cff_frame {
  CNN_CF_FRAME_FIELDS(float);
};
struct cnn_cf_corners {
  CNN_CF_CORNERS_FIELDS(double);
};
struct cnn_cff_corners {
  CNN_CF_CORNERS_FIELDS(float);
};

#endif /* CONTACTNN_CANONICAL_FRAME_GEOMETRY_H */
