#include "mlp/online_backprop.hpp"

#include <algorithm>

#include "mlp/simd_rows.hpp"

namespace contactnn::mlp {

template <class Real>
OnlineBackprop<Real>::OnlineBackprop(const Network<Real>& network) {
  const auto& sizes = network.layer_sizes();
  w0t_.assign(static_cast<std::size_t>(sizes[0]) * sizes[1], Real(0));
  v0t_.assign(w0t_.size(), Real(0));
  for (int n : sizes) activations_.emplace_back(static_cast<std::size_t>(n), Real(0));
  for (std::size_t l = 1; l < sizes.size(); ++l)
    deltas_.emplace_back(static_cast<std::size_t>(sizes[l]), Real(0));
}

template <class Real>
void OnlineBackprop<Real>::load(const Network<Real>& network, const Real* velocity) {
  const int n_in = network.layer_sizes()[0], n_out = network.layer_sizes()[1];
  const Real* w = network.weights(0);
  const Real* v = velocity + network.weight_offset(0);
  for (int j = 0; j < n_out; ++j) {
    for (int i = 0; i < n_in; ++i) {
      w0t_[static_cast<std::size_t>(i) * n_out + j] = w[static_cast<std::size_t>(j) * n_in + i];
      v0t_[static_cast<std::size_t>(i) * n_out + j] = v[static_cast<std::size_t>(j) * n_in + i];
    }
  }
}

template <class Real>
void OnlineBackprop<Real>::store(Network<Real>& network, Real* velocity) const {
  const int n_in = network.layer_sizes()[0], n_out = network.layer_sizes()[1];
  Real* w = network.weights(0);
  Real* v = velocity + network.weight_offset(0);
  for (int j = 0; j < n_out; ++j) {
    for (int i = 0; i < n_in; ++i) {
      w[static_cast<std::size_t>(j) * n_in + i] = w0t_[static_cast<std::size_t>(i) * n_out + j];
      v[static_cast<std::size_t>(j) * n_in + i] = v0t_[static_cast<std::size_t>(i) * n_out + j];
    }
  }
}

template <class Real>
Real OnlineBackprop<Real>::train_pattern(Network<Real>& network, Real* velocity, const Real* x, const Real* t,
                                         Real learning_rate, Real momentum) {
  const auto& sizes = network.layer_sizes();
  const int n_layers = network.layer_count();
  const Real gain = network.gain();
  // Forward, layer 0 as axpys over the transposed weights (Eq 13), then the sigmoids (Eq 12).
  {
    const int n_in = sizes[0], n_out = sizes[1];
    Real* u = activations_[1].data();
    const Real* theta = network.thresholds(0);
    for (int j = 0; j < n_out; ++j) u[j] = -theta[j];
    simd::add_transposed_product(w0t_.data(), x, n_in, n_out, u);
    simd::sigmoid_inplace(u, n_out, gain);
  }
  for (int l = 1; l < n_layers; ++l) {
    simd::sigmoid_rows(network.weights(l), network.thresholds(l), activations_[l].data(), sizes[l + 1],
                       sizes[l], gain, activations_[l + 1].data());
  }
  // Output deltas (O - T) gain O (1 - O) and E_p (Eq 14).
  const Real* o = activations_[n_layers].data();
  Real* d = deltas_[n_layers - 1].data();
  Real error = 0;
  for (int k = 0; k < sizes.back(); ++k) {
    const Real e = o[k] - t[k];
    error += e * e;
    d[k] = e * gain * o[k] * (Real(1) - o[k]);
  }
  // Hidden deltas from the weights before this pattern's update.
  for (int l = n_layers - 1; l > 0; --l) {
    const int n_here = sizes[l];
    const Real* w = network.weights(l);
    const Real* d_above = deltas_[l].data();
    Real* d_here = deltas_[l - 1].data();
    std::fill(d_here, d_here + n_here, Real(0));
    for (int j = 0; j < sizes[l + 1]; ++j)
      simd::axpy(d_above[j], w + static_cast<std::size_t>(j) * n_here, d_here, n_here);
    const Real* a = activations_[l].data();
    for (int i = 0; i < n_here; ++i) d_here[i] *= gain * a[i] * (Real(1) - a[i]);
  }
  // Momentum updates. Layer 0 transposed: row i gets dw_.i = alpha dw_.i - (eta x_i) delta.
  {
    const int n_in = sizes[0], n_out = sizes[1];
    const Real* d0 = deltas_[0].data();
    for (int i = 0; i < n_in; ++i) {
      const std::size_t row = static_cast<std::size_t>(i) * n_out;
      simd::momentum_row(momentum, learning_rate * x[i], d0, v0t_.data() + row, w0t_.data() + row, n_out);
    }
  }
  for (int l = 1; l < n_layers; ++l) {
    const int n_in = sizes[l];
    const Real* a = activations_[l].data();
    const Real* dl = deltas_[l].data();
    Real* w = network.weights(l);
    Real* vw = velocity + network.weight_offset(l);
    for (int j = 0; j < sizes[l + 1]; ++j) {
      const std::size_t row = static_cast<std::size_t>(j) * n_in;
      simd::momentum_row(momentum, learning_rate * dl[j], a, vw + row, w + row, n_in);
    }
  }
  for (int l = 0; l < n_layers; ++l) {  // dE/dtheta_j = -delta_j
    const Real* dl = deltas_[l].data();
    Real* theta = network.thresholds(l);
    Real* vt = velocity + network.threshold_offset(l);
    for (int j = 0; j < sizes[l + 1]; ++j) {
      vt[j] = momentum * vt[j] + learning_rate * dl[j];
      theta[j] += vt[j];
    }
  }
  return Real(0.5) * error;
}

template class OnlineBackprop<float>;
template class OnlineBackprop<double>;

}  // namespace contactnn::mlp
