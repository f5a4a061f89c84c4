// The unit's activation (paper Eq 12) for scalars and SIMD packets: O = 1 / (1 + exp(-2U/U0)).
#pragma once

#include <Eigen/Core>
#include <type_traits>

namespace contactnn::mlp {

namespace detail {

/// Logistic 1 / (1 + exp(-x)) in float: Eigen's 9/10-degree rational interpolant of logistic(x) - 1/2
/// (Eigen/src/Core/functors/UnaryFunctors.h, scalar_logistic_op<float>), a couple of ulps on [-9, 18],
/// with x clamped to +-c, where the interpolant reaches exactly 0 and 1 (it is odd). Eigen's functor
/// switches to exp(x) below -9 for relative accuracy of tiny outputs, a branch on every packet that a
/// saturated unit takes; training needs absolute accuracy only (outputs and O (1 - O) in [0, 1]), which
/// the clamped interpolant keeps to ~6e-8 everywhere, without the branch.
template <class Packet>
inline Packet logistic_float(const Packet& x_in) {
  using namespace Eigen::internal;
#ifdef EIGEN_VECTORIZE_FMA
  const Packet cutoff = pset1<Packet>(15.7243833541870117f);
#else
  const Packet cutoff = pset1<Packet>(15.6437711715698242f);
#endif
  const Packet x = pmax(pmin(x_in, cutoff), pnegate(cutoff));
  const Packet x2 = pmul(x, x);
  Packet p = pmadd(x2, pset1<Packet>(4.37031012579801e-11f), pset1<Packet>(1.15627324459942e-07f));
  p = pmadd(x2, p, pset1<Packet>(6.08574864600143e-05f));
  p = pmadd(x2, p, pset1<Packet>(8.51377133304701e-03f));
  p = pmadd(x2, p, pset1<Packet>(2.48287947061529e-01f));
  p = pmul(x, p);
  Packet q = pmadd(x2, pset1<Packet>(6.10247389755681e-13f), pset1<Packet>(5.76102136993427e-09f));
  q = pmadd(x2, q, pset1<Packet>(6.29106785017040e-06f));
  q = pmadd(x2, q, pset1<Packet>(1.70198817374094e-03f));
  q = pmadd(x2, q, pset1<Packet>(1.16817656904453e-01f));
  q = pmadd(x2, q, pset1<Packet>(9.93151921023180e-01f));
  return padd(pdiv(p, q), pset1<Packet>(0.5f));
}

}  // namespace detail

/// f(U) = 1 / (1 + exp(-gain * U)) with gain = 2 / U0 (Eq 12). float: detail::logistic_float in both the
/// scalar and the packet form, so the online (scalar) and batch (SIMD) paths agree to rounding; double:
/// Eigen's 1 / (1 + exp(-x)). f'(U) = gain * O (1 - O).
template <class Real>
[[nodiscard]] inline Real sigmoid(Real u, Real gain) {
  if constexpr (std::is_same_v<Real, float>) {
    return detail::logistic_float(gain * u);
  } else {
    return Eigen::internal::scalar_logistic_op<Real>()(gain * u);
  }
}

template <class Packet>
[[nodiscard]] inline Packet sigmoid_packet(const Packet& u, const Packet& gain) {
  using Real = typename Eigen::internal::unpacket_traits<Packet>::type;
  if constexpr (std::is_same_v<Real, float>) {
    return detail::logistic_float(Eigen::internal::pmul(gain, u));
  } else {
    return Eigen::internal::scalar_logistic_op<Real>().packetOp(Eigen::internal::pmul(gain, u));
  }
}

}  // namespace contactnn::mlp
