#include "mlp/network.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "mlp/random.hpp"
#include "mlp/smooth_problem.hpp"

namespace contactnn::mlp {
namespace {

TEST(Network, SameSeedGivesBitIdenticalParametersOtherSeedDoesNot) {
  const auto a = testing::make_network<float>({16, 48, 2}, 42);
  const auto b = testing::make_network<float>({16, 48, 2}, 42);
  const auto c = testing::make_network<float>({16, 48, 2}, 43);
  EXPECT_EQ(a.parameters(), b.parameters());
  EXPECT_NE(a.parameters(), c.parameters());
}

TEST(Network, ParameterLayoutIsWeightsThenThresholdsPerLayer) {
  const Network<double> net({3, 5, 4, 2}, 2.0, testing::unit_scaling(3, 2));
  EXPECT_EQ(net.layer_count(), 3);
  EXPECT_EQ(net.weight_offset(0), 0u);
  EXPECT_EQ(net.threshold_offset(0), 15u);
  EXPECT_EQ(net.weight_offset(1), 20u);
  EXPECT_EQ(net.threshold_offset(1), 40u);
  EXPECT_EQ(net.weight_offset(2), 44u);
  EXPECT_EQ(net.parameter_count(), 44u + 8u + 2u);
}

TEST(Network, ForwardPassIsEquations12And13) {
  auto net = testing::make_network<double>({2, 1}, 9, 0.5);
  net.weights(0)[0] = 0.3;
  net.weights(0)[1] = -0.7;
  net.thresholds(0)[0] = 0.1;
  ForwardPass<double> pass(net);
  const double x[2] = {0.5, 0.25};
  const double u = 0.3 * 0.5 - 0.7 * 0.25 - 0.1;
  EXPECT_NEAR(pass.run(net, x)[0], 1.0 / (1.0 + std::exp(-2.0 * u / 0.5)), 1e-15);
}

TEST(Network, PredictScalesInputsAndUnscalesOutputs) {
  Scaling s;
  s.input_min = {-2.0, 0.0};
  s.input_max = {2.0, 1.0};
  s.output_min = {-1.0};
  s.output_max = {1.0};
  EXPECT_DOUBLE_EQ(s.scale_input(0, -2.0), -1.0);
  EXPECT_DOUBLE_EQ(s.scale_input(1, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(s.scale_target(0, -1.0), 0.1);
  EXPECT_DOUBLE_EQ(s.scale_target(0, 1.0), 0.9);
  // All parameters zero: O = 1/2, which is the middle of [0.1, 0.9], i.e. label 0.
  const Network<double> net({2, 3, 1}, 2.0, s);
  ForwardPass<double> pass(net);
  const double raw[2] = {1.5, 0.2};
  double out = -7;
  predict(net, raw, &out, pass);
  EXPECT_NEAR(out, 0.0, 1e-15);
}

TEST(Network, HugeFiniteInputsGiveFiniteOutputs) {
  // 1e39 exceeds float's range: unclamped, the scaled inputs became +-inf and inf - inf NaN in layer 1
  // (evaluate-net then refused the whole file). Any finite input must give a finite prediction.
  const auto net = testing::make_network<float>({8, 8, 2}, 5);
  ForwardPass<float> pass(net);
  const double raw[8] = {1e39, -1e39, 1e39, -1e39, 1e300, -1e300, 0.5, 1e39};
  double out[2] = {NAN, NAN};
  predict(net, raw, out, pass);
  EXPECT_TRUE(std::isfinite(out[0]) && std::isfinite(out[1])) << out[0] << " " << out[1];
}

TEST(Network, RejectsBadArchitectureAndScaling) {
  EXPECT_THROW(Network<float>({3}, 2.0, testing::unit_scaling(3, 3)), InvalidArgument);
  EXPECT_THROW(Network<float>({3, 0, 2}, 2.0, testing::unit_scaling(3, 2)), InvalidArgument);
  EXPECT_THROW(Network<float>({3, 4, 2}, 0.0, testing::unit_scaling(3, 2)), InvalidArgument);
  EXPECT_THROW(Network<float>({3, 4, 2}, 2.0, testing::unit_scaling(4, 2)), InvalidArgument);
}

TEST(Rng, StateRestoresTheSequence) {
  Rng a(5);
  for (int i = 0; i < 10; ++i) a.next();
  Rng b = Rng::from_state(a.state());
  for (int i = 0; i < 10; ++i) EXPECT_EQ(a.next(), b.next());
}

}  // namespace
}  // namespace contactnn::mlp
