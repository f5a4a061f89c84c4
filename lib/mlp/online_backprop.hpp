// The online trainer's per-pattern step (the paper's ordinary BP with momentum), laid out for speed.
#pragma once

#include "mlp/network.hpp"

namespace contactnn::mlp {

/// One pattern: forward pass, back-propagation and the momentum update of every parameter, with no
/// allocation. The first layer's weights and momentum terms are held transposed (n_0 x n_1) between
/// load() and store(): its forward pass becomes n_0 SIMD axpys instead of n_1 dot products with
/// horizontal sums, and its update stays a row sweep; it needs no back-propagated delta. Results equal
/// PatternBackprop + momentum_step up to rounding order.
template <class Real>
class OnlineBackprop {
 public:
  explicit OnlineBackprop(const Network<Real>& network);

  /// Copies layer 0's weights and momentum terms (velocity: parameter layout) into the transposed buffers.
  void load(const Network<Real>& network, const Real* velocity);
  /// Copies them back. Between load() and store() the network's layer-0 weights and velocity are stale.
  void store(Network<Real>& network, Real* velocity) const;

  /// Trains on scaled pattern (x, t): dw = momentum dw - learning_rate dE_p/dw; w += dw. Returns E_p
  /// (Eq 14) before the update.
  Real train_pattern(Network<Real>& network, Real* velocity, const Real* x, const Real* t, Real learning_rate,
                     Real momentum);

 private:
  AlignedVector<Real> w0t_, v0t_;                 // n_0 x n_1
  std::vector<AlignedVector<Real>> activations_;  // per layer
  std::vector<AlignedVector<Real>> deltas_;       // dE/dU of layers 1..L
};

}  // namespace contactnn::mlp
