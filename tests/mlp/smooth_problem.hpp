// A small smooth regression problem shared by the lib/mlp tests: 3 inputs in [-1, 1], 2 targets in
// [0.2, 0.8] that a 3-8-2 sigmoid network can fit well.
#pragma once

#include <cmath>
#include <cstdint>

#include "mlp/network.hpp"
#include "mlp/random.hpp"

namespace contactnn::mlp::testing {

template <class Real>
struct Problem {
  MatrixRM<Real> inputs;
  MatrixRM<Real> targets;
};

template <class Real>
Problem<Real> smooth_problem(int rows, std::uint64_t seed) {
  Rng rng(seed);
  Problem<Real> p{MatrixRM<Real>(rows, 3), MatrixRM<Real>(rows, 2)};
  for (int r = 0; r < rows; ++r) {
    const double x = rng.uniform(-1, 1), y = rng.uniform(-1, 1), z = rng.uniform(-1, 1);
    p.inputs(r, 0) = static_cast<Real>(x);
    p.inputs(r, 1) = static_cast<Real>(y);
    p.inputs(r, 2) = static_cast<Real>(z);
    p.targets(r, 0) = static_cast<Real>(0.5 + 0.3 * std::sin(1.5 * x + 0.5 * y) * std::cos(0.7 * z));
    p.targets(r, 1) = static_cast<Real>(0.5 + 0.25 * std::tanh(x * y + z));
  }
  return p;
}

/// Identity-like scaling for already scaled data: inputs [-1, 1], outputs [0.1, 0.9] -> [0.1, 0.9].
inline Scaling unit_scaling(int n_in, int n_out) {
  Scaling s;
  s.input_min.assign(n_in, -1.0);
  s.input_max.assign(n_in, 1.0);
  s.output_min.assign(n_out, 0.1);
  s.output_max.assign(n_out, 0.9);
  return s;
}

template <class Real>
Network<Real> make_network(std::vector<int> sizes, std::uint64_t seed, double u0 = 2.0) {
  Network<Real> net(sizes, u0, unit_scaling(sizes.front(), sizes.back()));
  net.initialize(seed);
  return net;
}

}  // namespace contactnn::mlp::testing
