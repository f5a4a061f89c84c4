#include "mlp/pattern_backprop.hpp"

#include "mlp/simd_rows.hpp"

namespace contactnn::mlp {

template <class Real>
PatternBackprop<Real>::PatternBackprop(const Network<Real>& network) : pass_(network) {
  for (int l = 0; l < network.layer_count(); ++l) {
    deltas_.emplace_back(static_cast<std::size_t>(network.layer_sizes()[l + 1]), Real(0));
  }
}

template <class Real>
Real PatternBackprop<Real>::backpropagate(const Network<Real>& network, const Real* x, const Real* t) {
  const auto& sizes = network.layer_sizes();
  const int last = network.layer_count() - 1;
  const Real gain = network.gain();
  const Real* o = pass_.run(network, x);
  // Output layer: dE/dU_k = (O_k - T_k) f'(U_k), f' = gain O (1 - O) (Eqs 12, 14).
  Real error = 0;
  Real* d = deltas_[last].data();
  for (int k = 0; k < sizes.back(); ++k) {
    const Real e = o[k] - t[k];
    error += e * e;
    d[k] = e * gain * o[k] * (Real(1) - o[k]);
  }
  // Hidden layers: dE/dU_i = f'(U_i) sum_j W_ji dE/dU_j, with W of the layer above (axpys over its rows).
  for (int l = last; l > 0; --l) {
    const int n_in = sizes[l];
    const Real* w = network.weights(l);
    const Real* d_above = deltas_[l].data();
    Real* d_here = deltas_[l - 1].data();
    for (int i = 0; i < n_in; ++i) d_here[i] = 0;
    for (int j = 0; j < sizes[l + 1]; ++j)
      simd::axpy(d_above[j], w + static_cast<std::size_t>(j) * n_in, d_here, n_in);
    const Real* a = pass_.activation(l);
    for (int i = 0; i < n_in; ++i) d_here[i] *= gain * a[i] * (Real(1) - a[i]);
  }
  return Real(0.5) * error;
}

template <class Real>
void PatternBackprop<Real>::add_gradient(const Network<Real>& network, Real* gradient) const {
  const auto& sizes = network.layer_sizes();
  for (int l = 0; l < network.layer_count(); ++l) {
    const int n_in = sizes[l];
    const Real* a = pass_.activation(l);
    const Real* d = deltas_[l].data();
    Real* gw = gradient + network.weight_offset(l);
    Real* gt = gradient + network.threshold_offset(l);
    for (int j = 0; j < sizes[l + 1]; ++j) {
      Real* row = gw + static_cast<std::size_t>(j) * n_in;
      for (int i = 0; i < n_in; ++i) row[i] += d[j] * a[i];
      gt[j] -= d[j];
    }
  }
}

template <class Real>
void PatternBackprop<Real>::momentum_step(Network<Real>& network, Real learning_rate, Real momentum,
                                          Real* velocity) const {
  const auto& sizes = network.layer_sizes();
  for (int l = 0; l < network.layer_count(); ++l) {
    const int n_in = sizes[l];
    const Real* a = pass_.activation(l);
    const Real* d = deltas_[l].data();
    Real* w = network.weights(l);
    Real* vw = velocity + network.weight_offset(l);
    for (int j = 0; j < sizes[l + 1]; ++j) {
      const std::size_t row = static_cast<std::size_t>(j) * n_in;
      simd::momentum_row(momentum, learning_rate * d[j], a, vw + row, w + row,
                         n_in);  // dE/dW_ji = delta_j I_i
    }
    // dE/dtheta_j = -delta_j: the same update with input -1.
    Real* theta = network.thresholds(l);
    Real* vt = velocity + network.threshold_offset(l);
    for (int j = 0; j < sizes[l + 1]; ++j) {
      vt[j] = momentum * vt[j] + learning_rate * d[j];
      theta[j] += vt[j];
    }
  }
}

template class PatternBackprop<float>;
template class PatternBackprop<double>;

}  // namespace contactnn::mlp
