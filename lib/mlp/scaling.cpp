#include "mlp/scaling.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace contactnn::mlp {

Scaling Scaling::from_inputs(
    const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>& inputs,
    int output_count, double out_min, double out_max, double quantile) {
  CONTACTNN_REQUIRE(quantile >= 0.0 && quantile < 0.5,
                    "scaling quantile must be in [0, 0.5), got " << quantile);
  CONTACTNN_REQUIRE(inputs.rows() > 0 && inputs.cols() > 0,
                    "scaling needs at least one pattern, got " << inputs.rows() << " x " << inputs.cols());
  CONTACTNN_REQUIRE(inputs.allFinite(), "scaling: the training inputs contain a non-finite value");
  Scaling s;
  const auto n_in = static_cast<std::size_t>(inputs.cols());
  s.input_min.resize(n_in);
  s.input_max.resize(n_in);
  std::vector<double> column(static_cast<std::size_t>(inputs.rows()));
  for (Eigen::Index i = 0; i < inputs.cols(); ++i) {
    for (Eigen::Index r = 0; r < inputs.rows(); ++r) column[static_cast<std::size_t>(r)] = inputs(r, i);
    std::sort(column.begin(), column.end());
    // Order statistics at q and 1 - q (nearest rank): q = 0 gives the minimum and the maximum.
    const auto last = static_cast<double>(column.size() - 1);
    s.input_min[i] = column[static_cast<std::size_t>(std::llround(quantile * last))];
    s.input_max[i] = column[static_cast<std::size_t>(std::llround((1.0 - quantile) * last))];
  }
  s.output_min.assign(output_count, out_min);
  s.output_max.assign(output_count, out_max);
  s.validate(static_cast<int>(n_in), output_count);
  return s;
}

double Scaling::input_gain(int i) const {
  const double range = input_max[i] - input_min[i];
  return range > 0.0 ? 2.0 / range : 0.0;
}

double Scaling::output_gain(int k) const {
  return (target_high - target_low) / (output_max[k] - output_min[k]);
}

void Scaling::validate(int n_in, int n_out) const {
  CONTACTNN_REQUIRE(
      input_features == InputFeatures::kPaper || n_in == 8 || n_in == 16,
      "scaling: " << to_string(input_features) << " input features need 8 or 16 inputs, got " << n_in);
  CONTACTNN_REQUIRE(input_count() == n_in && static_cast<int>(input_max.size()) == n_in,
                    "scaling: expected " << n_in << " input ranges, got " << input_min.size()
                                         << " minima and " << input_max.size() << " maxima");
  CONTACTNN_REQUIRE(output_count() == n_out && static_cast<int>(output_max.size()) == n_out,
                    "scaling: expected " << n_out << " output ranges, got " << output_min.size()
                                         << " minima and " << output_max.size() << " maxima");
  for (int i = 0; i < n_in; ++i) {
    CONTACTNN_REQUIRE(
        std::isfinite(input_min[i]) && std::isfinite(input_max[i]) && input_min[i] <= input_max[i],
        "scaling: input " << i << " range [" << input_min[i] << ", " << input_max[i]
                          << "] is not a finite interval");
  }
  for (int k = 0; k < n_out; ++k) {
    CONTACTNN_REQUIRE(
        std::isfinite(output_min[k]) && std::isfinite(output_max[k]) && output_min[k] < output_max[k],
        "scaling: output " << k << " range [" << output_min[k] << ", " << output_max[k]
                           << "] is not a finite interval of positive length");
  }
  CONTACTNN_REQUIRE(
      0.0 < target_low && target_low < target_high && target_high < 1.0,
      "scaling: targets must satisfy 0 < low < high < 1, got [" << target_low << ", " << target_high << "]");
}

}  // namespace contactnn::mlp
