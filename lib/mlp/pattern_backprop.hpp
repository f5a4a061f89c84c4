// Back-propagation of one pattern (the paper's ordinary BP, Section 3): the online trainer's step and the
// reference the batch kernel is tested against.
#pragma once

#include <vector>

#include "mlp/network.hpp"

namespace contactnn::mlp {

/// Buffers sized once for a network; no allocation per pattern.
template <class Real>
class PatternBackprop {
 public:
  explicit PatternBackprop(const Network<Real>& network);

  /// Forward pass of scaled input x (n_0) and back-propagation of E_p = 1/2 sum_k (T_k - O_k)^2 (Eq 14)
  /// against scaled target t (n_L). Afterwards delta(l) holds dE_p/dU for the units of layer l + 1.
  /// @return E_p.
  Real backpropagate(const Network<Real>& network, const Real* x, const Real* t);

  /// Adds dE_p/dparameter of the last backpropagate() to `gradient` (network.parameter_count() values,
  /// the network's parameter layout): dE/dW_ji = delta_j I_i, dE/dtheta_j = -delta_j (Eq 13).
  void add_gradient(const Network<Real>& network, Real* gradient) const;

  /// Gradient descent with momentum on the last backpropagate(), parameter by parameter:
  ///   dw = momentum * dw - learning_rate * dE_p/dw;   w += dw.
  /// `velocity` holds dw (network.parameter_count() values) and is updated in place.
  void momentum_step(Network<Real>& network, Real learning_rate, Real momentum, Real* velocity) const;

  [[nodiscard]] const Real* delta(int layer) const { return deltas_[layer].data(); }
  [[nodiscard]] const ForwardPass<Real>& forward() const { return pass_; }

 private:
  ForwardPass<Real> pass_;
  std::vector<AlignedVector<Real>> deltas_;
};

}  // namespace contactnn::mlp
