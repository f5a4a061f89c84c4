// The affine maps between raw values and what the network sees: inputs to [-1, 1], labels into the
// sigmoid's open range. They belong to the network (and its file): a network is only meaningful with them.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/input_features.hpp"

namespace contactnn::mlp {

/// Features f -> inputs x = map_input_features(input_features, f), then
/// Input i:   x_s = (x - input_min[i]) * input_gain(i) - 1, input_gain = 2 / (input_max - input_min)
///            (0 for a constant input, which then always enters as -1).
/// Output k:  t_s = target_low + (t - output_min[k]) * (target_high - target_low) / (output_max -
/// output_min),
///            and its inverse for predictions. All in double; the network computes in its own Real.
struct Scaling {
  /// The features (SPEC 4) first go through this map (core/input_features.hpp); the ranges below are those
  /// of its outputs. kPaper: none.
  InputFeatures input_features = InputFeatures::kPaper;
  std::vector<double> input_min, input_max;    ///< per input: the range mapped to [-1, 1] (from_inputs)
  std::vector<double> output_min, output_max;  ///< per output: label range (the parameter domain)
  double target_low = 0.1;                     ///< sigmoid value output_min maps to (0 < low < high < 1)
  double target_high = 0.9;                    ///< sigmoid value output_max maps to

  /// Ranges from the rows of `inputs` (N x n_in, N >= 1) and the given label range, the same for every
  /// output. Input i's range runs from its `quantile` to its (1 - quantile) order statistic: 0 is the
  /// minimum and maximum; 0.005 maps the central 99% to [-1, 1], so that a few extreme values (Gregory
  /// normal slopes n_x/n_z reach +-77 on warped segments while most lie within +-0.3) do not squeeze the
  /// rest into a sliver of the units' input range. Values beyond reach past +-1 (linearly).
  /// Throws InvalidArgument for an empty or non-finite input, output_min >= output_max or a quantile
  /// outside [0, 0.5).
  static Scaling from_inputs(
      const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>& inputs,
      int output_count, double output_min, double output_max, double quantile = 0.0);

  [[nodiscard]] int input_count() const { return static_cast<int>(input_min.size()); }
  [[nodiscard]] int output_count() const { return static_cast<int>(output_min.size()); }
  [[nodiscard]] double input_gain(int i) const;
  [[nodiscard]] double output_gain(int k) const;  ///< (target_high - target_low) / (output_max - output_min)

  [[nodiscard]] double scale_input(int i, double x) const { return (x - input_min[i]) * input_gain(i) - 1.0; }
  [[nodiscard]] double scale_target(int k, double t) const {
    return target_low + (t - output_min[k]) * output_gain(k);
  }
  [[nodiscard]] double unscale_output(int k, double o) const {
    return output_min[k] + (o - target_low) / output_gain(k);
  }

  /// Throws InvalidArgument unless the sizes agree with (n_in, n_out), every bound is finite,
  /// min <= max for inputs, min < max for outputs and 0 < target_low < target_high < 1.
  void validate(int n_in, int n_out) const;
};

}  // namespace contactnn::mlp
