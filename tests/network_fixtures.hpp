// Shared by the network file tests (tests/io, tests/mlp): a bilinear training domain and a small network
// scaled to it, initialised from a seed.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/domain.hpp"
#include "mlp/network.hpp"

namespace contactnn::testing {

/// The paper's bilinear domain, rounded: features within [-2, 2] (xy), [-0.3, 0.3] (z), D in [-1, 1] x [0,
/// 1].
inline geometry::TrainingDomain bilinear_domain() {
  geometry::TrainingDomain d;
  d.surface = SurfaceKind::kBilinear;
  d.feature_min = {-2, -2, -0.3, -1, 0, -2, -2, -0.3};
  d.feature_max = {2, 2, 0.3, 1, 1, 2, 2, 0.3};
  return d;
}

/// A network of `sizes` and `u0` whose inputs are scaled to bilinear_domain() and outputs to [-1, 1]^2,
/// its weights drawn from `seed`.
template <class Real>
mlp::Network<Real> bilinear_network(std::vector<int> sizes, double u0, std::uint64_t seed) {
  const geometry::TrainingDomain d = bilinear_domain();
  mlp::Scaling s;
  s.input_min = d.feature_min;
  s.input_max = d.feature_max;
  s.output_min = {-1, -1};
  s.output_max = {1, 1};
  mlp::Network<Real> net(std::move(sizes), u0, s);
  net.initialize(seed);
  return net;
}

}  // namespace contactnn::testing
