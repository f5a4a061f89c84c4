// The shipped networks (data/weights) for lib/search's tests, each read once per test program, and random
// untrained ones.
// CONTACTNN_SOURCE_DIR is the source tree (a compile definition of the tests).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "core/input_features.hpp"
#include "geometry/domain.hpp"
#include "io/network_file.hpp"
#include "mlp/network.hpp"

namespace contactnn::testing {

/// data/weights/<name> (a float network file), read on first use.
inline const io::TrainedNetwork<float>& shipped(const std::string& name) {
  static std::map<std::string, io::TrainedNetwork<float>> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    it = cache
             .emplace(name,
                      io::read_network<float>(std::string(CONTACTNN_SOURCE_DIR) + "/data/weights/" + name))
             .first;
  }
  return it->second;
}

/// A network of `hidden` layers in Real with random weights, scaled to the feature ranges of `domain`.
template <class Real>
inline mlp::Network<Real> random_network(const geometry::TrainingDomain& domain, std::vector<int> hidden,
                                         InputFeatures map, std::uint64_t seed) {
  const int n_in = feature_count(domain.surface);
  mlp::Scaling s;
  s.input_min.assign(static_cast<std::size_t>(n_in), -2.0);
  s.input_max.assign(static_cast<std::size_t>(n_in), 2.0);
  s.input_max[4] = s.input_min[4];  // a constant input: gain 0
  s.input_features = map;
  const ParamDomain range = param_domain(domain.surface);
  s.output_min.assign(2, range.lo);
  s.output_max.assign(2, range.hi);
  std::vector<int> sizes{n_in};
  sizes.insert(sizes.end(), hidden.begin(), hidden.end());
  sizes.push_back(2);
  mlp::Network<Real> net(sizes, 1.7, s);
  net.initialize(seed);
  return net;
}

}  // namespace contactnn::testing
