#include "search/face_network.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "search/face_network_block.hpp"

namespace contactnn::search {

bool face_canonical_form(FaceKind kind, const double* raw, double* features, int* order, double* base) {
  switch (kind) {
    case FaceKind::kTri3: {
      // A flat triangle's frame (for completeness): its corners' as a tri6 with mid-side nodes at the edges'
      // midpoints.
      double x[21];
      for (int k = 0; k < 9; ++k) x[k] = raw[k];
      for (int e = 0; e < 3; ++e) {
        for (int c = 0; c < 3; ++c) x[9 + 3 * e + c] = 0.5 * (raw[3 * e + c] + raw[3 * ((e + 1) % 3) + c]);
      }
      for (int c = 0; c < 3; ++c) x[18 + c] = raw[9 + c];
      return detail::face_canonical_lane<1>(x, features, order, base);
    }
    case FaceKind::kTri6: return detail::face_canonical_lane<1>(raw, features, order, base);
    case FaceKind::kQuad8: return detail::face_canonical_lane<2>(raw, features, order, base);
  }
  return false;
}

void face_param_to_canonical(FaceKind kind, const int* order, double& s, double& t) {
  if (kind == FaceKind::kQuad8) {
    detail::face_to_canonical<2>(order, s, t);
  } else {
    detail::face_to_canonical<1>(order, s, t);
  }
}

void face_param_to_caller(FaceKind kind, const int* order, double& s, double& t) {
  if (kind == FaceKind::kQuad8) {
    detail::face_to_caller<2>(order, s, t);
  } else {
    detail::face_to_caller<1>(order, s, t);
  }
}

namespace {

int checked_inputs(FaceKind kind) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, kind != FaceKind::kTri3,
                       "tri3 faces take no network: their closed form is exact (method closed_form)");
  return face_feature_count(kind);
}

}  // namespace

template <class Real>
FaceNetwork::FaceNetwork(FaceKind kind, const mlp::Network<Real>& network, std::vector<double> feature_min,
                         std::vector<double> feature_max)
    : kind_(kind),
      model_(network, NetworkModel::OtherFrame{checked_inputs(kind)}),
      min_(std::move(feature_min)),
      max_(std::move(feature_max)) {
  check_bounds();
}

template FaceNetwork::FaceNetwork(FaceKind, const mlp::Network<float>&, std::vector<double>,
                                  std::vector<double>);
template FaceNetwork::FaceNetwork(FaceKind, const mlp::Network<double>&, std::vector<double>,
                                  std::vector<double>);

void FaceNetwork::check_bounds() {
  const auto n = static_cast<std::size_t>(face_feature_count(kind_));
  CONTACTNN_REQUIRE_AS(InvalidArgument, min_.size() == n && max_.size() == n,
                       "a " << to_string(kind_) << " network's domain needs " << n << " feature ranges, got "
                            << min_.size() << " minima and " << max_.size() << " maxima");
  lo_.resize(n);
  hi_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    CONTACTNN_REQUIRE_AS(InvalidArgument,
                         std::isfinite(min_[k]) && std::isfinite(max_[k]) && min_[k] <= max_[k],
                         "feature " << k << " of the domain: [" << min_[k] << ", " << max_[k]
                                    << "], expected finite bounds with min <= max");
    const double slack = 1e-9 * std::max(1.0, max_[k] - min_[k]);
    lo_[k] = min_[k] - slack;
    hi_[k] = max_[k] + slack;
  }
}

}  // namespace contactnn::search
