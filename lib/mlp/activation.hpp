// The unit's activation (paper Eq 12) for scalars and SIMD packets: O = 1 / (1 + exp(-2U/U0)).
#pragma once

#include <Eigen/Core>

namespace contactnn::mlp {

/// f(U) = 1 / (1 + exp(-gain * U)) with gain = 2 / U0 (Eq 12). Both the scalar and the packet form go
/// through Eigen's logistic functor, so the online (scalar) and batch (SIMD) paths round alike; for float
/// that functor is a rational approximation accurate to a few ulp, for double 1 / (1 + exp(-x)).
/// f'(U) = gain * O (1 - O).
template <class Real>
[[nodiscard]] inline Real sigmoid(Real u, Real gain) {
  return Eigen::internal::scalar_logistic_op<Real>()(gain * u);
}

template <class Packet>
[[nodiscard]] inline Packet sigmoid_packet(const Packet& u, const Packet& gain) {
  using Real = typename Eigen::internal::unpacket_traits<Packet>::type;
  return Eigen::internal::scalar_logistic_op<Real>().packetOp(Eigen::internal::pmul(gain, u));
}

}  // namespace contactnn::mlp
