// Internal to lib/search: a FaceNetwork's canonical form of a query (face_network.hpp) and its estimate for
// the W lanes of a block: the canonical frame lane by lane, the forward pass of network_block.hpp across the
// lanes, the map back to the caller's node order.
#pragma once

#include <cmath>

#include "search/closed_form_block.hpp"
#include "search/face_block.hpp"
#include "search/face_network.hpp"
#include "search/network_block.hpp"

namespace contactnn::search::detail {

/// The canonical form of one query: x holds its raw values (nodes in the caller's order, then S). Writes the
/// features, the caller's corner at each canonical slot and `base`, the corner facet's closed form of S in
/// the canonical parametrisation (what the network corrects); false where there is no frame (see
/// face_canonical_form).
template <int kFace>
CONTACTNN_SEARCH_INLINE bool face_canonical_lane(const double* x, double* features, int* order,
                                                 double* base) {
  using T = FaceTraits<kFace>;
  constexpr int kC = T::kTriangle ? 3 : 4;
  const double* s = x + 3 * T::kNodes;
  const auto node = [x](int i, int c) { return x[3 * i + c]; };
  const auto dist_sq = [&](int i, const double* p) {
    double d = 0.0;
    for (int c = 0; c < 3; ++c) d += (node(i, c) - p[c]) * (node(i, c) - p[c]);
    return d;
  };
  double check = 0.0;
  for (int k = 0; k < T::kStride; ++k) check += 0.0 * x[k];
  if (check != 0.0) return false;
  int rot = 0;
  double best = dist_sq(0, s);
  for (int j = 1; j < kC; ++j) {
    const double d = dist_sq(j, s);
    if (d < best) {
      best = d;
      rot = j;
    }
  }
  const double* a = x + 3 * rot;
  const bool mirror = dist_sq((rot + kC - 1) % kC, a) > dist_sq((rot + 1) % kC, a);
  for (int j = 0; j < kC; ++j) order[j] = mirror ? (rot - j + kC) % kC : (rot + j) % kC;
  // The mid-side node between canonical slots j and j + 1.
  const auto mid = [&](int j) { return kC + (mirror ? order[(j + 1) % kC] : order[j]); };
  double e1[3], e3[3];
  for (int c = 0; c < 3; ++c) {
    e1[c] = node(order[1], c) - a[c];
    e3[c] = node(order[kC - 1], c) - a[c];
  }
  const double n[3] = {e1[1] * e3[2] - e1[2] * e3[1], e1[2] * e3[0] - e1[0] * e3[2],
                       e1[0] * e3[1] - e1[1] * e3[0]};
  const double len1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  const double len3 = std::sqrt(e3[0] * e3[0] + e3[1] * e3[1] + e3[2] * e3[2]);
  const double len_n = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len1 > 0.0) || !(len_n > 1e-12 * len1 * len3) || !std::isfinite(len_n)) return false;
  const double inv = 1.0 / len1;
  double ex[3], ez[3], ey[3];
  for (int c = 0; c < 3; ++c) {
    ex[c] = e1[c] * inv;
    ez[c] = n[c] / len_n;
  }
  ey[0] = ez[1] * ex[2] - ez[2] * ex[1];
  ey[1] = ez[2] * ex[0] - ez[0] * ex[2];
  ey[2] = ez[0] * ex[1] - ez[1] * ex[0];
  // Every node in the frame (A at the origin, B at (1, 0, 0), the last corner in the xy-plane).
  const auto frame = [&](const double* p, double* out) {
    const double d[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    out[0] = (d[0] * ex[0] + d[1] * ex[1] + d[2] * ex[2]) * inv;
    out[1] = (d[0] * ey[0] + d[1] * ey[1] + d[2] * ey[2]) * inv;
    out[2] = (d[0] * ez[0] + d[1] * ez[1] + d[2] * ez[2]) * inv;
  };
  double corner[4][3], middle[4][3], slave[3];
  for (int j = 0; j < kC; ++j) frame(x + 3 * order[j], corner[j]);
  for (int j = 0; j < kC; ++j) frame(x + 3 * mid(j), middle[j]);
  frame(s, slave);
  // The corner facet's closed form of S: the triangle's (r, s) of S's projection on its plane, or the quad's
  // corners as a bilinear facet (closed_form_lane), in the canonical parametrisation.
  if constexpr (T::kTriangle) {
    const double yc = corner[2][1];
    base[1] = slave[1] / yc;
    base[0] = slave[0] - base[1] * corner[2][0];
  } else {
    double a0[3], a1[3], a2[3], a3[3];
    for (int c = 0; c < 3; ++c) {
      const double pa = corner[0][c] - slave[c], pb = corner[1][c] - slave[c], pc = corner[2][c] - slave[c],
                   pd = corner[3][c] - slave[c];
      a0[c] = 0.25 * (pa + pb + pc + pd);
      a1[c] = 0.25 * (-pa + pb + pc - pd);
      a2[c] = 0.25 * (-pa - pb + pc + pd);
      a3[c] = 0.25 * (pa - pb + pc - pd);
    }
    bool fold = false, degenerate = false;
    closed_form_lane(a0, a1, a2, a3, base[0], base[1], fold, degenerate);
    if (degenerate || !std::isfinite(base[0]) || !std::isfinite(base[1])) return false;
  }
  // Features: the corner shape (tri6: C's x, y; quad8: C's x, y, z and D's x, y), each mid-side node's offset
  // from its chord's midpoint, then the closed form's two coordinates and S's height over the corners' plane.
  int at = 0;
  if constexpr (T::kTriangle) {
    features[at++] = corner[2][0];
    features[at++] = corner[2][1];
  } else {
    for (int c = 0; c < 3; ++c) features[at++] = corner[2][c];
    features[at++] = corner[3][0];
    features[at++] = corner[3][1];
  }
  for (int j = 0; j < kC; ++j) {
    for (int c = 0; c < 3; ++c)
      features[at++] = middle[j][c] - 0.5 * (corner[j][c] + corner[(j + 1) % kC][c]);
  }
  features[at++] = base[0];
  features[at++] = base[1];
  features[at++] = slave[2];
  return true;
}

/// The corner parameters of the caller's parametrisation: quad (-1,-1), (1,-1), (1,1), (-1,1); triangles by
/// barycentric weights.
template <int kFace>
CONTACTNN_SEARCH_INLINE void face_to_caller(const int* order, double& s, double& t) {
  if constexpr (FaceTraits<kFace>::kTriangle) {
    const double w[3] = {1.0 - s - t, s, t};
    double caller[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < 3; ++j) caller[order[j]] = w[j];
    s = caller[1];
    t = caller[2];
  } else {
    constexpr double kX[4] = {-1, 1, 1, -1}, kY[4] = {-1, -1, 1, 1};
    const double w[4] = {0.25 * (1 - s) * (1 - t), 0.25 * (1 + s) * (1 - t), 0.25 * (1 + s) * (1 + t),
                         0.25 * (1 - s) * (1 + t)};
    double u = 0.0, v = 0.0;
    for (int j = 0; j < 4; ++j) {
      u += w[j] * kX[order[j]];
      v += w[j] * kY[order[j]];
    }
    s = u;
    t = v;
  }
}

template <int kFace>
CONTACTNN_SEARCH_INLINE void face_to_canonical(const int* order, double& s, double& t) {
  if constexpr (FaceTraits<kFace>::kTriangle) {
    const double caller[3] = {1.0 - s - t, s, t};
    s = caller[order[1]];
    t = caller[order[2]];
  } else {
    constexpr double kX[4] = {-1, 1, 1, -1}, kY[4] = {-1, -1, 1, 1};
    const double w[4] = {0.25 * (1 - s) * (1 - t), 0.25 * (1 + s) * (1 - t), 0.25 * (1 + s) * (1 + t),
                         0.25 * (1 - s) * (1 + t)};
    double u = 0.0, v = 0.0;
    for (int j = 0; j < 4; ++j) {  // caller corner order[j] sits at canonical slot j
      u += w[order[j]] * kX[j];
      v += w[order[j]] * kY[j];
    }
    s = u;
    t = v;
  }
}

/// face_canonical_lane for the per-lane loop of face_network_estimate: out of line, with internal linkage (a
/// copy in every kernel file, none shared across instruction sets) and never vectorised, in the block kernels
/// as in the one-lane kernel (which is compiled without auto-vectorisation): GCC contracted the frame's
/// multiply-adds differently when it vectorised that loop, and a quad8 network query's last bits depended on
/// its place in the batch (test_lane_bits, each kernel variant in a process of its own).
#if defined(__GNUC__) && !defined(__clang__)
#define CONTACTNN_SCALAR_LANE [[gnu::noinline, gnu::optimize("no-tree-vectorize", "no-tree-slp-vectorize")]]
#else
#define CONTACTNN_SCALAR_LANE \
  [[gnu::noinline]]  // Clang has no optimize attribute (GCC builds the kernels here)
#endif
template <int kFace>
CONTACTNN_SCALAR_LANE static bool face_canonical_scalar(const double* x, double* features, int* order,
                                                        double* base) {
  return face_canonical_lane<kFace>(x, features, order, base);
}

/// The network's estimate for the lanes still ok: status degenerate where the face has no frame (centre
/// reported), out_of_domain where a feature lies outside the network's box (check_domain; the estimate is
/// still reported), ok otherwise.
template <int kFace, int W>
static void face_network_estimate(const FaceNetwork& net, bool check_domain, const double (*raw)[W],
                                  LaneState<W>& s) {
  using T = FaceTraits<kFace>;
  constexpr int kF = kFace == 1 ? 14 : 20;
  alignas(64) double f[kF * W];
  alignas(64) double out[2 * W];
  int order[W][4];
  double framed[W], base[W][2];
  const double* lo = net.lo();
  const double* hi = net.hi();
  for (int l = 0; l < W; ++l) {
    double x[T::kStride], features[kF];
    for (int k = 0; k < T::kStride; ++k) x[k] = raw[k][l];
    const bool ok = face_canonical_scalar<kFace>(x, features, order[l], base[l]);
    framed[l] = ok ? 1.0 : 0.0;
    bool inside = true;
    for (int k = 0; k < kF; ++k) {
      const double v = ok ? features[k] : 0.0;
      f[k * W + l] = v;
      inside = inside && v >= lo[k] && v <= hi[k];
    }
    const bool active = s.status[l] == kOk;
    s.status[l] =
        !active ? s.status[l] : (!ok ? kDegenerate : (check_domain && !inside ? kOutOfDomain : kOk));
  }
  if (net.model().is_float()) {
    forward_pass<float, W>(net.model(), f, out);
  } else {
    forward_pass<double, W>(net.model(), f, out);
  }
  for (int l = 0; l < W; ++l) {
    const bool use = framed[l] != 0.0 && (s.status[l] == kOk || s.status[l] == kOutOfDomain);
    // The network's output is the correction to the corner facet's closed form.
    double u = out[l] + base[l][0], v = out[W + l] + base[l][1];
    if (use) face_to_caller<kFace>(order[l], u, v);
    s.u[l] = use ? u : s.u[l];
    s.v[l] = use ? v : s.v[l];
  }
}

}  // namespace contactnn::search::detail
