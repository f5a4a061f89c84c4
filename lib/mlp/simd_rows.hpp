// Row kernels of the one-pattern paths (online training; the forward pass of a query), written on Eigen's
// SIMD packets. Rows are short (8 to 48 values), so Eigen's general expressions spend more on alignment
// peeling per row than on arithmetic; these use unaligned packet loads and a scalar tail, and no allocation.
#pragma once

#include <Eigen/Core>

#include "mlp/activation.hpp"

namespace contactnn::mlp::simd {

template <class Real>
using Packet = typename Eigen::internal::packet_traits<Real>::type;
template <class Real>
inline constexpr int kWidth = Eigen::internal::unpacket_traits<Packet<Real>>::size;

/// u[j] = sigmoid(u[j], gain) for j < n, in packets: the rational approximation is a long dependent chain
/// per value, which packets overlap.
template <class Real>
inline void sigmoid_inplace(Real* u, int n, Real gain) {
  using namespace Eigen::internal;
  using P = Packet<Real>;
  constexpr int L = kWidth<Real>;
  const P gv = pset1<P>(gain);
  int j = 0;
  for (; j + L <= n; j += L) pstoreu(u + j, sigmoid_packet(ploadu<P>(u + j), gv));
  for (; j < n; ++j) u[j] = sigmoid(u[j], gain);
}

/// u[j] = sum_i w[j][i] x[i] - theta[j] for j < rows (w row-major rows x cols), Eq 13, on packets of type P
/// (the widest one, or a narrower one for short rows): four rows at a time, a scalar tail over columns.
template <class Real, class P>
inline void affine_rows(const Real* w, const Real* theta, const Real* x, int rows, int cols, Real* out) {
  using namespace Eigen::internal;
  constexpr int L = unpacket_traits<P>::size;
  const int full = cols - cols % L;
  int j = 0;
  for (; j + 4 <= rows; j += 4) {
    const Real* w0 = w + static_cast<std::size_t>(j) * cols;
    const Real* w1 = w0 + cols;
    const Real* w2 = w1 + cols;
    const Real* w3 = w2 + cols;
    P a0 = pset1<P>(Real(0)), a1 = a0, a2 = a0, a3 = a0;
    for (int i = 0; i < full; i += L) {
      const P xv = ploadu<P>(x + i);
      a0 = pmadd(ploadu<P>(w0 + i), xv, a0);
      a1 = pmadd(ploadu<P>(w1 + i), xv, a1);
      a2 = pmadd(ploadu<P>(w2 + i), xv, a2);
      a3 = pmadd(ploadu<P>(w3 + i), xv, a3);
    }
    Real u0 = predux(a0) - theta[j], u1 = predux(a1) - theta[j + 1];
    Real u2 = predux(a2) - theta[j + 2], u3 = predux(a3) - theta[j + 3];
    for (int i = full; i < cols; ++i) {
      u0 += w0[i] * x[i];
      u1 += w1[i] * x[i];
      u2 += w2[i] * x[i];
      u3 += w3[i] * x[i];
    }
    out[j] = u0;
    out[j + 1] = u1;
    out[j + 2] = u2;
    out[j + 3] = u3;
  }
  for (; j < rows; ++j) {
    const Real* wj = w + static_cast<std::size_t>(j) * cols;
    P a = pset1<P>(Real(0));
    for (int i = 0; i < full; i += L) a = pmadd(ploadu<P>(wj + i), ploadu<P>(x + i), a);
    Real u = predux(a) - theta[j];
    for (int i = full; i < cols; ++i) u += wj[i] * x[i];
    out[j] = u;
  }
}

/// out[j] = sigmoid(sum_i w[j][i] x[i] - theta[j], gain) for j < rows (w row-major rows x cols), Eqs 12-13,
/// on the widest packets only: the online trainer's kernel (its rounding is what the shipped weights were
/// trained with; a row shorter than a packet is summed in scalars).
template <class Real>
inline void sigmoid_rows(const Real* w, const Real* theta, const Real* x, int rows, int cols, Real gain,
                         Real* out) {
  affine_rows<Real, Packet<Real>>(w, theta, x, rows, cols, out);
  sigmoid_inplace(out, rows, gain);
}

template <class P>
using HalfPacket = typename Eigen::internal::unpacket_traits<P>::half;
/// True when P has a narrower half packet (the narrowest packet's half is itself). Compared by width, not
/// std::is_same: the packets are vector types whose attributes std templates would drop (a GCC warning).
template <class P>
inline constexpr bool kHasHalf =
    Eigen::internal::unpacket_traits<HalfPacket<P>>::size < Eigen::internal::unpacket_traits<P>::size;

/// sigmoid_inplace on packets of P, then the rest on P's half packets, and so on down to the narrowest
/// (whose half is itself), then scalars: 8 values under AVX-512 float are one 8-float packet, not 8 scalars.
template <class Real, class P>
inline void sigmoid_inplace_fitted(Real* u, int n, Real gain) {
  using namespace Eigen::internal;
  constexpr int L = unpacket_traits<P>::size;
  const P gv = pset1<P>(gain);
  int j = 0;
  for (; j + L <= n; j += L) pstoreu(u + j, sigmoid_packet(ploadu<P>(u + j), gv));
  if constexpr (kHasHalf<P>) {
    if (j < n) sigmoid_inplace_fitted<Real, HalfPacket<P>>(u + j, n - j, gain);
  } else {
    for (; j < n; ++j) u[j] = sigmoid(u[j], gain);
  }
}

/// The widest packet type no wider than `cols` (or the narrowest there is) runs affine_rows.
template <class Real, class P>
inline void affine_rows_fitted(const Real* w, const Real* theta, const Real* x, int rows, int cols,
                               Real* out) {
  if constexpr (kHasHalf<P>) {
    if (cols < Eigen::internal::unpacket_traits<P>::size) {
      affine_rows_fitted<Real, HalfPacket<P>>(w, theta, x, rows, cols, out);
      return;
    }
  }
  affine_rows<Real, P>(w, theta, x, rows, cols, out);
}

/// sigmoid_rows on packets fitted to the layer: the inference kernel (ForwardPass). For the paper's 8-8-2
/// under AVX-512 float, whose rows are all shorter than one 16-float packet, it runs in 8-float packets
/// where sigmoid_rows runs scalars. Results agree with sigmoid_rows to float rounding (the order of the
/// sums differs), not bit for bit.
template <class Real>
inline void sigmoid_rows_fitted(const Real* w, const Real* theta, const Real* x, int rows, int cols,
                                Real gain, Real* out) {
  affine_rows_fitted<Real, Packet<Real>>(w, theta, x, rows, cols, out);
  sigmoid_inplace_fitted<Real, Packet<Real>>(out, rows, gain);
}

/// NP packets of columns from j: u[j..] += sum_i x[i] wt[i][j..], accumulated in registers.
template <class Real, int NP>
inline void add_transposed_block(const Real* wt, const Real* x, int rows, int cols, int j, Real* u) {
  using namespace Eigen::internal;
  using P = Packet<Real>;
  constexpr int L = kWidth<Real>;
  P a[NP];
  for (int k = 0; k < NP; ++k) a[k] = ploadu<P>(u + j + k * L);
  for (int i = 0; i < rows; ++i) {
    const P xi = pset1<P>(x[i]);
    const Real* w = wt + static_cast<std::size_t>(i) * cols + j;
    for (int k = 0; k < NP; ++k) a[k] = pmadd(xi, ploadu<P>(w + k * L), a[k]);
  }
  for (int k = 0; k < NP; ++k) pstoreu(u + j + k * L, a[k]);
}

/// u[j] += sum_i x[i] wt[i][j] for j < cols (wt row-major rows x cols): a product with a transposed weight
/// matrix, summed in registers over i in blocks of up to 4 packets, so that no store-to-load chain runs
/// through u and several FMA chains overlap.
template <class Real>
inline void add_transposed_product(const Real* wt, const Real* x, int rows, int cols, Real* u) {
  constexpr int L = kWidth<Real>;
  int j = 0;
  for (; j + 4 * L <= cols; j += 4 * L) add_transposed_block<Real, 4>(wt, x, rows, cols, j, u);
  switch ((cols - j) / L) {
    case 3:
      add_transposed_block<Real, 3>(wt, x, rows, cols, j, u);
      j += 3 * L;
      break;
    case 2:
      add_transposed_block<Real, 2>(wt, x, rows, cols, j, u);
      j += 2 * L;
      break;
    case 1:
      add_transposed_block<Real, 1>(wt, x, rows, cols, j, u);
      j += L;
      break;
    default: break;
  }
  for (; j < cols; ++j) {
    Real a = u[j];
    for (int i = 0; i < rows; ++i) a += x[i] * wt[static_cast<std::size_t>(i) * cols + j];
    u[j] = a;
  }
}

/// y[i] += s * x[i] for i < n.
template <class Real>
inline void axpy(Real s, const Real* x, Real* y, int n) {
  using namespace Eigen::internal;
  using P = Packet<Real>;
  constexpr int L = kWidth<Real>;
  const P sv = pset1<P>(s);
  int i = 0;
  for (; i + L <= n; i += L) pstoreu(y + i, pmadd(sv, ploadu<P>(x + i), ploadu<P>(y + i)));
  for (; i < n; ++i) y[i] += s * x[i];
}

/// v[i] = alpha v[i] - step a[i];  w[i] += v[i]  for i < n (one row of a momentum update).
template <class Real>
inline void momentum_row(Real alpha, Real step, const Real* a, Real* v, Real* w, int n) {
  using namespace Eigen::internal;
  using P = Packet<Real>;
  constexpr int L = kWidth<Real>;
  const P av = pset1<P>(alpha), sv = pset1<P>(step);
  int i = 0;
  for (; i + L <= n; i += L) {
    const P vv = psub(pmul(av, ploadu<P>(v + i)), pmul(sv, ploadu<P>(a + i)));
    pstoreu(v + i, vv);
    pstoreu(w + i, padd(ploadu<P>(w + i), vv));
  }
  for (; i < n; ++i) {
    const Real vi = alpha * v[i] - step * a[i];
    v[i] = vi;
    w[i] += vi;
  }
}

}  // namespace contactnn::mlp::simd
