#include "search/network_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <type_traits>

#include "core/error.hpp"

namespace contactnn::search {

cnn_domain domain_bounds(const geometry::TrainingDomain& domain) {
  const int n = feature_count(domain.surface);
  CONTACTNN_REQUIRE_AS(
      InvalidArgument,
      static_cast<int>(domain.feature_min.size()) == n && static_cast<int>(domain.feature_max.size()) == n,
      "a " << to_string(domain.surface) << " training domain needs " << n << " feature ranges, got "
           << domain.feature_min.size() << " minima and " << domain.feature_max.size() << " maxima");
  const double tol = geometry::TrainingDomain::kRelativeTolerance;
  const geometry::DomainFilters& f = domain.filters;
  cnn_domain d{};
  for (int k = 0; k < 16; ++k) {
    d.lo[k] = -INFINITY;
    d.hi[k] = INFINITY;
  }
  // The same arithmetic as TrainingDomain::contains, so that a feature on a bound is decided alike.
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double slack = tol * std::max(1.0, domain.feature_max[i] - domain.feature_min[i]);
    d.lo[k] = domain.feature_min[i] - slack;
    d.hi[k] = domain.feature_max[i] + slack;
  }
  d.xy = f.xy_limit * (1.0 + tol);
  d.z = f.z_limit * (1.0 + tol);
  d.ad_bound = 1.0 + tol;
  d.inv_one_plus_tol = 1.0 / (1.0 + tol);
  d.tol = tol;
  d.tilt = f.max_normal_tilt_tangent;
  d.features = n;
  d.ad_not_longer = f.ad_not_longer_than_ab ? 1 : 0;
  d.nearest_a = f.nearest_node_a ? 1 : 0;
  d.segment_test = f.segment_test_a ? 1 : 0;
  d.convex = f.convex ? 1 : 0;
  if (f.min_angle_degrees > 0.0 || f.max_angle_degrees < 180.0) {
    // DomainFilters::accepts: angle >= min - 180 tol and angle <= max + 180 tol, in degrees.
    const double lo = f.min_angle_degrees - 180.0 * tol, hi = f.max_angle_degrees + 180.0 * tol;
    d.check_lo = lo > 0.0 ? 1 : 0;
    d.check_hi = hi < 180.0 ? 1 : 0;
    // A bound beyond 180 (or below 0) degrees rejects everything: a cosine no corner reaches.
    d.cos_lo = lo >= 180.0 ? -2.0 : std::cos(lo * std::numbers::pi / 180.0);
    d.cos_hi = hi <= 0.0 ? 2.0 : std::cos(hi * std::numbers::pi / 180.0);
  }
  return d;
}

template <class Real>
void NetworkModel::init(const mlp::Network<Real>& network, int inputs) {
  const int n_features = inputs >= 0 ? inputs : feature_count(domain_.surface);
  CONTACTNN_REQUIRE_AS(InvalidArgument, network.input_count() == n_features,
                       "a " << (inputs >= 0 ? std::string("face") : std::string(to_string(domain_.surface)))
                            << " network needs " << n_features << " inputs, got " << network.input_count());
  CONTACTNN_REQUIRE_AS(InvalidArgument, network.output_count() == 2,
                       "a local-search network has 2 outputs, got " << network.output_count());
  for (const int width : network.layer_sizes()) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, width <= kMaxWidth,
                         "layer width " << width << " exceeds NetworkModel::kMaxWidth = " << kMaxWidth);
  }
  if (inputs < 0) bounds_ = search::domain_bounds(domain_);
  is_float_ = std::is_same_v<Real, float>;
  sizes_ = network.layer_sizes();
  for (int l = 0; l < network.layer_count(); ++l) offsets_.push_back(network.weight_offset(l));
  const auto& p = network.parameters();
  std::vector<Real> transposed;
  for (int l = 0; l < network.layer_count(); ++l) {
    const auto n_in = static_cast<std::size_t>(sizes_[static_cast<std::size_t>(l)]);
    const auto n_out = static_cast<std::size_t>(sizes_[static_cast<std::size_t>(l) + 1]);
    const auto padded = static_cast<std::size_t>(padded_units(l));
    const std::size_t w = offsets_[static_cast<std::size_t>(l)], at = transposed.size();
    transposed_offsets_.push_back(at);
    transposed.resize(at + (n_in + 1) * padded, Real(0));
    for (std::size_t j = 0; j < n_out; ++j) {
      for (std::size_t i = 0; i < n_in; ++i) transposed[at + i * padded + j] = p[w + j * n_in + i];
      transposed[at + n_in * padded + j] = p[w + n_out * n_in + j];
    }
  }
  if constexpr (std::is_same_v<Real, float>) {
    params_f_.assign(p.begin(), p.end());
    transposed_f_ = std::move(transposed);
  } else {
    params_d_.assign(p.begin(), p.end());
    transposed_d_ = std::move(transposed);
  }
  gain_ = 2.0 / network.u0();
  const mlp::Scaling& s = network.scaling();
  input_min_ = s.input_min;
  input_gain_ = network.input_gains();
  output_min_ = s.output_min;
  for (const double g : network.output_gains()) output_inverse_gain_.push_back(1.0 / g);
  target_low_ = s.target_low;
  input_features_ = s.input_features;
}

NetworkModel::NetworkModel(const mlp::Network<float>& network, const geometry::TrainingDomain& domain)
    : domain_(domain) {
  init(network);
}

NetworkModel::NetworkModel(const mlp::Network<double>& network, const geometry::TrainingDomain& domain)
    : domain_(domain) {
  init(network);
}

NetworkModel::NetworkModel(const mlp::Network<float>& network, OtherFrame frame) {
  init(network, frame.inputs);
}

NetworkModel::NetworkModel(const mlp::Network<double>& network, OtherFrame frame) {
  init(network, frame.inputs);
}

template <class Real>
const Real* NetworkModel::weights(int layer) const {
  constexpr bool kFloat = std::is_same_v<Real, float>;
  CONTACTNN_REQUIRE(is_float_ == kFloat, "the network computes in " << (is_float_ ? "float" : "double"));
  CONTACTNN_REQUIRE(layer >= 0 && layer < layer_count(), "layer " << layer << " of " << layer_count());
  const auto offset = offsets_[static_cast<std::size_t>(layer)];
  if constexpr (std::is_same_v<Real, float>) {
    return params_f_.data() + offset;
  } else {
    return params_d_.data() + offset;
  }
}

template <class Real>
const Real* NetworkModel::thresholds(int layer) const {
  const auto l = static_cast<std::size_t>(layer);
  return weights<Real>(layer) + static_cast<std::size_t>(sizes_[l + 1]) * static_cast<std::size_t>(sizes_[l]);
}

template const float* NetworkModel::weights<float>(int) const;
template const double* NetworkModel::weights<double>(int) const;
template const float* NetworkModel::thresholds<float>(int) const;
template const double* NetworkModel::thresholds<double>(int) const;

}  // namespace contactnn::search
