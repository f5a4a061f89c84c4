#include <gtest/gtest.h>

#include "mlp/pattern_backprop.hpp"
#include "mlp/smooth_problem.hpp"

namespace contactnn::mlp {
namespace {

using testing::make_network;
using testing::smooth_problem;

// Central differences with h = 1e-6 on O(1) double quantities: truncation ~h^2 ~ 1e-12 and rounding
// ~eps/h ~ 1e-10, so 1e-7 relative to the largest gradient entry leaves room and still catches any
// wrong term (which is O(1) relative).
constexpr double kFiniteDifferenceTolerance = 1e-7;

double total_error(const Network<double>& net, const testing::Problem<double>& p) {
  PatternBackprop<double> bp(net);
  double e = 0;
  for (Eigen::Index r = 0; r < p.inputs.rows(); ++r)
    e += bp.backpropagate(net, p.inputs.row(r).data(), p.targets.row(r).data());
  return e;
}

void check_gradient(std::vector<int> sizes, double u0) {
  auto net = make_network<double>(sizes, 7, u0);
  testing::Problem<double> p = smooth_problem<double>(5, 3);
  if (sizes.front() != 3) {
    p.inputs = MatrixRM<double>::Random(5, sizes.front());
  }
  if (sizes.back() != 2) p.targets = MatrixRM<double>::Constant(5, sizes.back(), 0.3);
  PatternBackprop<double> bp(net);
  std::vector<double> grad(net.parameter_count(), 0.0);
  for (Eigen::Index r = 0; r < p.inputs.rows(); ++r) {
    bp.backpropagate(net, p.inputs.row(r).data(), p.targets.row(r).data());
    bp.add_gradient(net, grad.data());
  }
  double scale = 0;
  for (double g : grad) scale = std::max(scale, std::abs(g));
  ASSERT_GT(scale, 1e-6);
  const double h = 1e-6;
  for (std::size_t k = 0; k < net.parameter_count(); ++k) {
    const double saved = net.parameters()[k];
    net.parameters()[k] = saved + h;
    const double up = total_error(net, p);
    net.parameters()[k] = saved - h;
    const double down = total_error(net, p);
    net.parameters()[k] = saved;
    EXPECT_NEAR(grad[k], (up - down) / (2 * h), kFiniteDifferenceTolerance * scale) << "parameter " << k;
  }
}

TEST(PatternBackprop, GradientMatchesFiniteDifferencesOneHiddenLayer) { check_gradient({3, 8, 2}, 2.0); }

TEST(PatternBackprop, GradientMatchesFiniteDifferencesTwoHiddenLayersAndOtherU0) {
  check_gradient({4, 6, 5, 3}, 0.7);
}

TEST(PatternBackprop, ErrorIsHalfTheSquaredDifference) {
  auto net = make_network<double>({3, 4, 2}, 1);
  PatternBackprop<double> bp(net);
  const double x[3] = {0.1, -0.2, 0.3}, t[2] = {0.25, 0.75};
  const double e = bp.backpropagate(net, x, t);
  const double* o = bp.forward().activation(2);
  EXPECT_DOUBLE_EQ(e, 0.5 * ((t[0] - o[0]) * (t[0] - o[0]) + (t[1] - o[1]) * (t[1] - o[1])));
}

TEST(PatternBackprop, MomentumStepIsGradientDescentWithMomentum) {
  auto net = make_network<double>({3, 4, 2}, 5);
  auto before = net.parameters();
  PatternBackprop<double> bp(net);
  const double x[3] = {0.4, 0.1, -0.6}, t[2] = {0.2, 0.8};
  Eigen::VectorXd velocity =
      Eigen::VectorXd::Constant(static_cast<Eigen::Index>(net.parameter_count()), 0.01);
  Eigen::VectorXd grad = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(net.parameter_count()));
  bp.backpropagate(net, x, t);
  bp.add_gradient(net, grad.data());
  bp.momentum_step(net, 0.5, 0.9, velocity.data());
  for (Eigen::Index k = 0; k < grad.size(); ++k) {
    const double dw = 0.9 * 0.01 - 0.5 * grad[k];
    EXPECT_NEAR(velocity[k], dw, 1e-15) << k;
    EXPECT_NEAR(net.parameters()[static_cast<std::size_t>(k)], before[static_cast<std::size_t>(k)] + dw,
                1e-15)
        << k;
  }
}

}  // namespace
}  // namespace contactnn::mlp
