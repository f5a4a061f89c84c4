// The trained network (lib/mlp) as the FeaturePredictor the study and evaluate-net use.
#pragma once

#include "mlp/network.hpp"

namespace contactnn::eval {

/// Normalised features (feature_count values) -> the two local coordinates, through mlp::predict (input
/// scaling, forward pass in Real, inverse output scaling). Holds a pointer to the network, which must
/// outlive it, and its own forward-pass buffers: copy it per thread. No allocation per prediction.
template <class Real>
class NetworkPredictor {
 public:
  explicit NetworkPredictor(const mlp::Network<Real>& network) : network_(&network), pass_(network) {}
  void predict(const double* features, double* out) { mlp::predict(*network_, features, out, pass_); }
  [[nodiscard]] const mlp::Network<Real>& network() const { return *network_; }

 private:
  const mlp::Network<Real>* network_;
  mlp::ForwardPass<Real> pass_;
};

}  // namespace contactnn::eval
