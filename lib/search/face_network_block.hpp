// Internal to lib/search: a FaceNetwork's canonical form of a query (face_network.hpp) and its estimate for
// the W lanes of a block: the canonical frame lane by lane, the forward pass of network_block.hpp across the
// lanes, the map back to the caller's node order.
#pragma once

#include <cmath>

#include "search/face_block.hpp"
#include "search/face_network.hpp"
#include "search/network_block.hpp"

namespace contactnn::search::detail {

/// The canonical form of one query: x holds its raw values (nodes in the caller's order, then S). Writes the
/// features and the caller's corner at each canonical slot; false where there is no frame (see
/// face_canonical_form).
template <int kFace>
CONTACTNN_SEARCH_INLINE bool face_canonical_lane(const double* x, double* features, int* order) {
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
  const double n[3] = {e1[1] * e3[2] - e1[2] * e3[1], e1[2] * e3[0] - e1[0] * e3[2], e1[0] * e3[1] - e1[1] * e3[0]};
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
  const auto frame = [&](const double* p, double* out, int components) {
    const double d[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    const double* axes[3] = {ex, ey, ez};
    for (int k = 0; k < components; ++k) out[k] = (d[0] * axes[k][0] + d[1] * axes[k][1] + d[2] * axes[k][2]) * inv;
  };
  int at = 0;
  if constexpr (T::kTriangle) {
    frame(x + 3 * order[2], features, 2);
    at = 2;
  } else {
    frame(x + 3 * order[2], features, 3);
    frame(x + 3 * order[3], features + 3, 2);
    at = 5;
  }
  for (int j = 0; j < kC; ++j) {
    frame(x + 3 * mid(j), features + at, 3);
    at += 3;
  }
  frame(s, features + at, 3);
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

/// The network's estimate for the lanes still ok: status degenerate where the face has no frame (centre
/// reported), out_of_domain where a feature lies outside the network's box (check_domain; the estimate is still
/// reported), ok otherwise.
template <int kFace, int W>
static void face_network_estimate(const FaceNetwork& net, bool check_domain, const double (*raw)[W], LaneState<W>& s) {
  using T = FaceTraits<kFace>;
  constexpr int kF = kFace == 1 ? 14 : 20;
  constexpr int kC = T::kTriangle ? 3 : 4;
  alignas(64) double f[kF * W];
  alignas(64) double out[2 * W];
  int order[W][4];
  double framed[W];
  const double* lo = net.lo();
  const double* hi = net.hi();
  for (int l = 0; l < W; ++l) {
    double x[T::kStride], features[kF];
    for (int k = 0; k < T::kStride; ++k) x[k] = raw[k][l];
    const bool ok = face_canonical_lane<kFace>(x, features, order[l]);
    framed[l] = ok ? 1.0 : 0.0;
    bool inside = true;
    for (int k = 0; k < kF; ++k) {
      const double v = ok ? features[k] : 0.0;
      f[k * W + l] = v;
      inside = inside && v >= lo[k] && v <= hi[k];
    }
    const bool active = s.status[l] == kOk;
    s.status[l] = !active ? s.status[l] : (!ok ? kDegenerate : (check_domain && !inside ? kOutOfDomain : kOk));
  }
  if (net.model().is_float()) {
    forward_pass<float, W>(net.model(), f, out);
  } else {
    forward_pass<double, W>(net.model(), f, out);
  }
  for (int l = 0; l < W; ++l) {
    const bool use = framed[l] != 0.0 && (s.status[l] == kOk || s.status[l] == kOutOfDomain);
    double u = out[l], v = out[W + l];
    if (use) face_to_caller<kFace>(order[l], u, v);
    s.u[l] = use ? u : s.u[l];
    s.v[l] = use ? v : s.v[l];
  }
  (void)kC;
}

}  // namespace contactnn::search::detail
