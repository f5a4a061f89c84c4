// A trained network made ready for lib/search's batched inference: its weights in the layout the block
// forward pass reads, its scaling with the gains computed once, and its training domain as the bounds the
// canonical-frame kernel tests (canonical_frame.h).
#pragma once

#include <cstddef>
#include <type_traits>
#include <vector>

#include "core/conventions.hpp"
#include "core/input_features.hpp"
#include "geometry/domain.hpp"
#include "mlp/network.hpp"
#include "search/canonical_frame.h"

namespace contactnn::search {

/// An inference-ready copy of an mlp::Network<float> or <double> and its geometry::TrainingDomain. The
/// forward pass runs in the network's own real type (float or double); the input map, scaling and the
/// canonical frame in double. Immutable after construction: one model serves any number of threads and
/// LocalSearch objects.
class NetworkModel {
 public:
  /// The widest layer the block forward pass supports (its buffers live on the stack, no allocation).
  static constexpr int kMaxWidth = 128;

  /// Throws InvalidArgument when the network's input count is not feature_count(domain.surface), it does not
  /// have 2 outputs, a layer is wider than kMaxWidth, or the domain's feature ranges have the wrong size.
  NetworkModel(const mlp::Network<float>& network, const geometry::TrainingDomain& domain);
  NetworkModel(const mlp::Network<double>& network, const geometry::TrainingDomain& domain);
  /// A network of `inputs` features of another frame than SPEC 4's (FaceNetwork's faces): the weights,
  /// scaling and forward pass alone; domain() and domain_bounds() are not set (the owner tests its own
  /// domain). Throws InvalidArgument when the input count is not `inputs` (at most kMaxWidth), it does not
  /// have 2 outputs, or a layer is wider than kMaxWidth.
  struct OtherFrame {
    int inputs;
  };
  NetworkModel(const mlp::Network<float>& network, OtherFrame frame);
  NetworkModel(const mlp::Network<double>& network, OtherFrame frame);

  [[nodiscard]] SurfaceKind surface() const { return domain_.surface; }
  /// True when the forward pass runs in float.
  [[nodiscard]] bool is_float() const { return is_float_; }
  [[nodiscard]] const std::vector<int>& layer_sizes() const { return sizes_; }
  [[nodiscard]] int layer_count() const { return static_cast<int>(sizes_.size()) - 1; }
  /// Weights and thresholds (including the output layer's) of the network.
  [[nodiscard]] std::size_t parameter_count() const {
    return is_float_ ? params_f_.size() : params_d_.size();
  }

  /// W_l (n_{l+1} x n_l, row-major) and theta_l in the network's real type: Real must be float when
  /// is_float() and double otherwise (InvalidArgument if not).
  template <class Real>
  [[nodiscard]] const Real* weights(int layer) const;
  template <class Real>
  [[nodiscard]] const Real* thresholds(int layer) const;
  /// All parameters in the network's real type (mlp::Network's layout), or nullptr when Real is not it: the
  /// unchecked access of the block forward pass, which runs where nothing may throw.
  template <class Real>
  [[nodiscard]] const Real* parameters() const noexcept {
    if constexpr (std::is_same_v<Real, float>) {
      return is_float_ ? params_f_.data() : nullptr;
    } else {
      return is_float_ ? nullptr : params_d_.data();
    }
  }
  /// Units of a layer the one-query forward pass computes together (a group's sums stay in registers).
  static constexpr int kUnitGroup = 16;
  static_assert(kMaxWidth % kUnitGroup == 0, "the forward pass's buffers hold the padded units");
  /// For the one-query forward pass, which runs a layer across its units (each unit's sum in the same order
  /// as a lane of the block pass): W_l transposed (n_l rows of padded_units(l) values, input-major), then
  /// theta_l, both padded with zeros to padded_units(l) units, a multiple of kUnitGroup. Real as
  /// parameters().
  template <class Real>
  [[nodiscard]] const Real* transposed_weights(int layer) const noexcept {
    const std::size_t at = transposed_offsets_[static_cast<std::size_t>(layer)];
    if constexpr (std::is_same_v<Real, float>) {
      return is_float_ ? transposed_f_.data() + at : nullptr;
    } else {
      return is_float_ ? nullptr : transposed_d_.data() + at;
    }
  }
  [[nodiscard]] int padded_units(int layer) const noexcept {
    const int n = sizes_[static_cast<std::size_t>(layer) + 1];
    return (n + kUnitGroup - 1) / kUnitGroup * kUnitGroup;
  }
  /// Offset of W_l in parameters(); theta_l follows W_l.
  [[nodiscard]] std::size_t weight_offset(int layer) const noexcept {
    return offsets_[static_cast<std::size_t>(layer)];
  }
  /// 2 / U0 in the network's real type.
  template <class Real>
  [[nodiscard]] Real gain() const {
    return static_cast<Real>(gain_);
  }

  /// Input scaling x_s = (x - input_min) * input_gain - 1 and output scaling t = output_min + (o -
  /// target_low) * output_inverse_gain, as mlp::predict computes them (the inverse gain instead of a
  /// division).
  [[nodiscard]] const std::vector<double>& input_min() const { return input_min_; }
  [[nodiscard]] const std::vector<double>& input_gain() const { return input_gain_; }
  [[nodiscard]] const std::vector<double>& output_min() const { return output_min_; }
  [[nodiscard]] const std::vector<double>& output_inverse_gain() const { return output_inverse_gain_; }
  [[nodiscard]] double target_low() const { return target_low_; }
  /// The map from the canonical features to the network's inputs (mlp::Scaling::input_features), applied
  /// before the input scaling.
  [[nodiscard]] InputFeatures input_features() const { return input_features_; }

  [[nodiscard]] const geometry::TrainingDomain& domain() const { return domain_; }
  /// The domain as canonical_frame.h's cnn_domain_lane tests it (TrainingDomain::kRelativeTolerance slack).
  [[nodiscard]] const cnn_domain& domain_bounds() const { return bounds_; }

 private:
  /// inputs < 0: feature_count(domain_.surface), and the domain's bounds computed.
  template <class Real>
  void init(const mlp::Network<Real>& network, int inputs = -1);

  geometry::TrainingDomain domain_;
  bool is_float_ = true;
  std::vector<int> sizes_;
  std::vector<std::size_t> offsets_;             ///< per layer: start of W_l; theta_l follows it
  std::vector<std::size_t> transposed_offsets_;  ///< per layer: start of W_l^T (padded) in transposed_*_
  std::vector<float> params_f_, transposed_f_;
  std::vector<double> params_d_, transposed_d_;
  double gain_ = 1.0;
  std::vector<double> input_min_, input_gain_, output_min_, output_inverse_gain_;
  double target_low_ = 0.1;
  InputFeatures input_features_ = InputFeatures::kPaper;
  cnn_domain bounds_{};
};

/// Fills a cnn_domain from a TrainingDomain (used by NetworkModel; exposed for the exported C header and
/// tests).
[[nodiscard]] cnn_domain domain_bounds(const geometry::TrainingDomain& domain);

}  // namespace contactnn::search
