// A fully connected multi-layer network of sigmoid units (paper Section 3, Eqs 12-13), with the scaling
// that maps raw inputs and labels onto what the units see.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "mlp/scaling.hpp"

namespace contactnn::mlp {

/// Storage aligned for Eigen's widest SIMD packet (the batch kernels load packets from it).
template <class Real>
using AlignedVector = std::vector<Real, Eigen::aligned_allocator<Real>>;

template <class T>
using MatrixRM = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Layer sizes n_0 (inputs), n_1, ..., n_L (outputs); every unit of layers 1..L, the outputs included, is
///   U_j = sum_i W_ji I_i - theta_j   (Eq 13),   O_j = 1 / (1 + exp(-2 U_j / U0))   (Eq 12).
/// All parameters live in one flat vector (momentum buffers, gradients and checkpoints share its layout):
/// for l = 0..L-1, W_l (n_{l+1} x n_l, row-major, row j = unit j's incoming weights), then theta_l (n_{l+1}).
/// Real is float (the default for training: twice the SIMD width and half the memory traffic of double,
/// while the target accuracy, ~1e-3 in [0, 1], is far above float rounding) or double (gradient checks).
template <class Real>
class Network {
 public:
  /// All parameters zero. Throws InvalidArgument for fewer than 2 layer sizes, a size < 1, U0 <= 0 or
  /// a scaling whose sizes do not match the first and last layer.
  Network(std::vector<int> layer_sizes, double u0, Scaling scaling);

  [[nodiscard]] const std::vector<int>& layer_sizes() const { return sizes_; }
  [[nodiscard]] int layer_count() const { return static_cast<int>(sizes_.size()) - 1; }  ///< weight layers L
  [[nodiscard]] int input_count() const { return sizes_.front(); }
  [[nodiscard]] int output_count() const { return sizes_.back(); }
  [[nodiscard]] int max_width() const;  ///< largest layer size
  [[nodiscard]] double u0() const { return u0_; }
  /// 2 / U0: dO/dU = gain * O (1 - O).
  [[nodiscard]] Real gain() const { return static_cast<Real>(2.0 / u0_); }
  [[nodiscard]] const Scaling& scaling() const { return scaling_; }
  /// scaling().input_gain(i) and output_gain(k), computed once (the scaling is fixed at construction):
  /// predict() would otherwise pay a call and a division per input per query.
  [[nodiscard]] const std::vector<double>& input_gains() const { return input_gains_; }
  [[nodiscard]] const std::vector<double>& output_gains() const { return output_gains_; }

  [[nodiscard]] std::size_t parameter_count() const { return params_.size(); }
  [[nodiscard]] AlignedVector<Real>& parameters() { return params_; }
  [[nodiscard]] const AlignedVector<Real>& parameters() const { return params_; }
  [[nodiscard]] std::size_t weight_offset(int layer) const { return offsets_[layer]; }
  [[nodiscard]] std::size_t threshold_offset(int layer) const {
    return offsets_[layer] + static_cast<std::size_t>(sizes_[layer + 1]) * sizes_[layer];
  }
  /// W_l, n_{l+1} x n_l row-major.
  [[nodiscard]] Real* weights(int layer) { return params_.data() + weight_offset(layer); }
  [[nodiscard]] const Real* weights(int layer) const { return params_.data() + weight_offset(layer); }
  /// theta_l, n_{l+1}.
  [[nodiscard]] Real* thresholds(int layer) { return params_.data() + threshold_offset(layer); }
  [[nodiscard]] const Real* thresholds(int layer) const { return params_.data() + threshold_offset(layer); }

  /// Weights uniform in +-(U0/2) sqrt(6 / (n_in + n_out)) (Glorot's range, stretched by U0/2 so that
  /// 2U/U0 has Glorot's spread), thresholds uniform in +-0.1 (U0/2); drawn from Rng(seed) in
  /// parameter order, so a seed fixes every bit.
  void initialize(std::uint64_t seed);

  /// The same network in another precision (values rounded to nearest).
  template <class Other>
  [[nodiscard]] Network<Other> cast() const {
    Network<Other> out(sizes_, u0_, scaling_);
    for (std::size_t p = 0; p < params_.size(); ++p) out.parameters()[p] = static_cast<Other>(params_[p]);
    return out;
  }

 private:
  std::vector<int> sizes_;
  double u0_;
  Scaling scaling_;
  std::vector<double> input_gains_;
  std::vector<double> output_gains_;
  std::vector<std::size_t> offsets_;
  AlignedVector<Real> params_;
};

/// Buffers for one pattern's forward pass, sized once: no allocation per pattern.
template <class Real>
class ForwardPass {
 public:
  explicit ForwardPass(const Network<Real>& network);
  /// Forward pass of one scaled input (n_0 values); returns the n_L output activations (valid until the
  /// next call). activation(l) is layer l's output (l = 0 is the input copy).
  const Real* run(const Network<Real>& network, const Real* scaled_input);
  [[nodiscard]] const Real* activation(int layer) const { return activations_[layer].data(); }
  [[nodiscard]] Real* activation(int layer) { return activations_[layer].data(); }

 private:
  std::vector<AlignedVector<Real>> activations_;
};

/// Raw inputs (n_0 values, the units of the training features) -> raw outputs (n_L values, label units):
/// scaling, forward pass, inverse output scaling. No allocation. Scaled inputs are clamped to [-1e6, 1e6],
/// so any finite input gives a finite output (far outside the training range it is an extrapolation).
template <class Real>
void predict(const Network<Real>& network, const double* raw_input, double* raw_output,
             ForwardPass<Real>& pass);

/// Every row of `raw_inputs` (N x n_0) -> N x n_L raw outputs, rows in parallel (OpenMP).
template <class Real>
[[nodiscard]] MatrixRM<double> predict(const Network<Real>& network, const MatrixRM<double>& raw_inputs);

}  // namespace contactnn::mlp
