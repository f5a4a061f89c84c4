#include <gtest/gtest.h>

#include "core/error.hpp"
#include "mlp/network.hpp"
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

// The forward pass picks, per layer, the widest SIMD packet no wider than the layer, then narrower ones for
// the rest (simd::sigmoid_rows_fitted). Every width from 1 to 40 in and out, so each packet width, each
// 4-row block and each scalar tail is reached, against Eqs 12-13 evaluated in long double.
template <class Real>
void check_forward_pass_widths(double tolerance) {
  Rng rng(5);
  for (int n_in = 1; n_in <= 40; ++n_in) {
    for (int n_out = 1; n_out <= 40; n_out += (n_out < 20 ? 1 : 7)) {
      const auto net =
          testing::make_network<Real>({n_in, n_out}, static_cast<std::uint64_t>(100 * n_in + n_out), 1.5);
      std::vector<Real> x(static_cast<std::size_t>(n_in));
      for (Real& v : x) v = static_cast<Real>(rng.uniform(-1.0, 1.0));
      ForwardPass<Real> pass(net);
      const Real* o = pass.run(net, x.data());
      for (int j = 0; j < n_out; ++j) {
        long double u = -static_cast<long double>(net.thresholds(0)[j]);
        for (int i = 0; i < n_in; ++i) {
          u += static_cast<long double>(net.weights(0)[j * n_in + i]) * static_cast<long double>(x[i]);
        }
        const long double expected = 1.0L / (1.0L + std::exp(-2.0L * u / 1.5L));
        ASSERT_NEAR(static_cast<double>(o[j]), static_cast<double>(expected), tolerance)
            << n_in << " inputs, " << n_out << " outputs, unit " << j;
      }
    }
  }
}

TEST(Network, ForwardPassMatchesTheEquationsAtEveryLayerWidthFloat) {
  check_forward_pass_widths<float>(2e-6);
}
TEST(Network, ForwardPassMatchesTheEquationsAtEveryLayerWidthDouble) {
  check_forward_pass_widths<double>(1e-13);
}

// predict() uses the gains the network computed once; they must be the scaling's own.
TEST(Network, PredictUsesTheScalingOfItsFile) {
  Scaling s;
  s.input_min = {-2.0, 0.5, 3.0};
  s.input_max = {2.0, 1.0, 3.0};  // a constant input: gain 0, always -1
  s.output_min = {-1.0, 0.0};
  s.output_max = {1.0, 4.0};
  s.target_low = 0.2;
  s.target_high = 0.7;
  Network<double> net({3, 4, 2}, 2.0, s);
  net.initialize(11);
  ForwardPass<double> pass(net);
  const double raw[3] = {1.5, 0.6, 12.0};
  double out[2] = {};
  predict(net, raw, out, pass);
  double scaled[3];
  for (int i = 0; i < 3; ++i) scaled[i] = s.scale_input(i, raw[i]);
  EXPECT_EQ(scaled[2], -1.0);
  ForwardPass<double> reference(net);
  const double* o = reference.run(net, scaled);
  for (int k = 0; k < 2; ++k) EXPECT_EQ(out[k], s.unscale_output(k, o[k])) << "output " << k;
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

TEST(Scaling, FromInputsMapsTheChosenOrderStatisticsToPlusMinusOne) {
  // Column 0: 0, 1, ..., 100 (shuffled); column 1: the same with one outlier 1e4 in place of 100.
  MatrixRM<double> x(101, 2);
  for (int r = 0; r < 101; ++r) {
    x(r, 0) = static_cast<double>((r * 37) % 101);
    x(r, 1) = x(r, 0) == 100.0 ? 1e4 : x(r, 0);
  }
  const Scaling all = Scaling::from_inputs(x, 2, -1.0, 1.0);
  EXPECT_EQ(all.input_min, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(all.input_max, (std::vector<double>{100.0, 1e4}));
  // q = 0.05: ranks 5 and 95 of 0..100.
  const Scaling central = Scaling::from_inputs(x, 2, -1.0, 1.0, 0.05);
  EXPECT_EQ(central.input_min, (std::vector<double>{5.0, 5.0}));
  EXPECT_EQ(central.input_max, (std::vector<double>{95.0, 95.0}));
  EXPECT_NEAR(central.scale_input(1, 50.0), 0.0, 1e-15);
  EXPECT_THROW((void)Scaling::from_inputs(x, 2, -1.0, 1.0, 0.5), InvalidArgument);
}

}  // namespace
}  // namespace contactnn::mlp
