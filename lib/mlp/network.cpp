#include "mlp/network.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "mlp/activation.hpp"
#include "mlp/random.hpp"
#include "mlp/simd_rows.hpp"

namespace contactnn::mlp {

template <class Real>
Network<Real>::Network(std::vector<int> layer_sizes, double u0, Scaling scaling)
    : sizes_(std::move(layer_sizes)), u0_(u0), scaling_(std::move(scaling)) {
  CONTACTNN_REQUIRE(sizes_.size() >= 2, "a network needs an input and an output layer, got "
                                            << sizes_.size() << " layer size(s)");
  for (int n : sizes_) CONTACTNN_REQUIRE(n >= 1, "every layer needs at least one unit, got " << n);
  CONTACTNN_REQUIRE(std::isfinite(u0_) && u0_ > 0.0, "U0 must be positive and finite, got " << u0_);
  scaling_.validate(sizes_.front(), sizes_.back());
  for (int i = 0; i < sizes_.front(); ++i) input_gains_.push_back(scaling_.input_gain(i));
  for (int k = 0; k < sizes_.back(); ++k) output_gains_.push_back(scaling_.output_gain(k));
  std::size_t offset = 0;
  for (int l = 0; l < layer_count(); ++l) {
    offsets_.push_back(offset);
    offset += static_cast<std::size_t>(sizes_[l + 1]) * (sizes_[l] + 1);
  }
  params_.assign(offset, Real(0));
}

template <class Real>
int Network<Real>::max_width() const {
  return *std::max_element(sizes_.begin(), sizes_.end());
}

template <class Real>
void Network<Real>::initialize(std::uint64_t seed) {
  Rng rng(seed);
  const double stretch = u0_ / 2.0;
  for (int l = 0; l < layer_count(); ++l) {
    const double limit = stretch * std::sqrt(6.0 / (sizes_[l] + sizes_[l + 1]));
    Real* w = weights(l);
    for (std::size_t p = 0; p < static_cast<std::size_t>(sizes_[l + 1]) * sizes_[l]; ++p) {
      w[p] = static_cast<Real>(rng.uniform(-limit, limit));
    }
    Real* theta = thresholds(l);
    for (int j = 0; j < sizes_[l + 1]; ++j)
      theta[j] = static_cast<Real>(rng.uniform(-0.1 * stretch, 0.1 * stretch));
  }
}

template <class Real>
ForwardPass<Real>::ForwardPass(const Network<Real>& network) {
  for (int n : network.layer_sizes()) activations_.emplace_back(static_cast<std::size_t>(n), Real(0));
}

template <class Real>
const Real* ForwardPass<Real>::run(const Network<Real>& network, const Real* scaled_input) {
  const auto& sizes = network.layer_sizes();
  if (scaled_input != activations_[0].data())
    std::copy(scaled_input, scaled_input + sizes[0], activations_[0].data());
  const Real gain = network.gain();
  for (int l = 0; l < network.layer_count(); ++l) {
    // Eqs 13, 12, in packets no wider than the layer (an 8-wide layer in 8-float packets under AVX-512).
    simd::sigmoid_rows_fitted(network.weights(l), network.thresholds(l), activations_[l].data(), sizes[l + 1],
                              sizes[l], gain, activations_[l + 1].data());
  }
  return activations_.back().data();
}

template <class Real>
void predict(const Network<Real>& network, const double* raw_input, double* raw_output,
             ForwardPass<Real>& pass) {
  const Scaling& s = network.scaling();
  const double* input_gain = network.input_gains().data();
  const double* output_gain = network.output_gains().data();
  Real* x = pass.activation(0);
  // Inputs in the trained range scale to [-1, 1]; one far outside it (already out of domain) is clamped so
  // that a huge finite feature cannot become inf in float, and inf - inf NaN in the first layer.
  // The same arithmetic as Scaling::scale_input and unscale_output, with the gains computed once.
  constexpr double kInputClamp = 1e6;
  double mapped[16];
  const double* features = raw_input;
  if (s.input_features != InputFeatures::kPaper) {
    map_input_features(s.input_features,
                       network.input_count() == 8 ? SurfaceKind::kBilinear : SurfaceKind::kGregory, raw_input,
                       mapped);
    features = mapped;
  }
  for (int i = 0; i < network.input_count(); ++i) {
    const double scaled = (features[i] - s.input_min[i]) * input_gain[i] - 1.0;
    x[i] = static_cast<Real>(std::clamp(scaled, -kInputClamp, kInputClamp));
  }
  // Scaled straight into activation(0), which run() then leaves in place.
  const Real* o = pass.run(network, x);
  for (int k = 0; k < network.output_count(); ++k) {
    raw_output[k] = s.output_min[k] + (static_cast<double>(o[k]) - s.target_low) / output_gain[k];
  }
}

template <class Real>
MatrixRM<double> predict(const Network<Real>& network, const MatrixRM<double>& raw_inputs) {
  CONTACTNN_REQUIRE(raw_inputs.cols() == network.input_count(), "predict: expected " << network.input_count()
                                                                                     << " input columns, got "
                                                                                     << raw_inputs.cols());
  MatrixRM<double> out(raw_inputs.rows(), network.output_count());
  const Eigen::Index n = raw_inputs.rows();
#pragma omp parallel
  {
    ForwardPass<Real> pass(network);
#pragma omp for schedule(static)
    for (Eigen::Index r = 0; r < n; ++r) predict(network, raw_inputs.row(r).data(), out.row(r).data(), pass);
  }
  return out;
}

template class Network<float>;
template class Network<double>;
template class ForwardPass<float>;
template class ForwardPass<double>;
template void predict(const Network<float>&, const double*, double*, ForwardPass<float>&);
template void predict(const Network<double>&, const double*, double*, ForwardPass<double>&);
template MatrixRM<double> predict(const Network<float>&, const MatrixRM<double>&);
template MatrixRM<double> predict(const Network<double>&, const MatrixRM<double>&);

}  // namespace contactnn::mlp
