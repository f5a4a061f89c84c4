#include <gtest/gtest.h>

#include <numeric>

#include "mlp/batch_gradient.hpp"
#include "mlp/pattern_backprop.hpp"
#include "mlp/smooth_problem.hpp"

namespace contactnn::mlp {
namespace {

using testing::make_network;

// The batch kernel sums the same terms in another order (per lane, per tile, per slot): in double the
// difference is rounding of ~1e3 O(1) terms, far below 1e-10 relative.
constexpr double kDoubleSumTolerance = 1e-10;
// In float the same reordering costs ~sqrt(N) eps ~ 1e-6 relative to the largest entry.
constexpr double kFloatSumTolerance = 2e-5;

template <class Real>
void compare_with_pattern_sum(std::vector<int> sizes, int rows, double tolerance) {
  auto net = make_network<Real>(sizes, 11);
  MatrixRM<Real> x = MatrixRM<double>::Random(rows, sizes.front()).template cast<Real>();
  MatrixRM<Real> t =
      (0.5 * MatrixRM<double>::Random(rows, sizes.back()).array() + 0.5).matrix().template cast<Real>();
  PatternBackprop<Real> bp(net);
  std::vector<Real> expected(net.parameter_count(), Real(0));
  double expected_loss = 0;
  for (int r = 0; r < rows; ++r) {
    expected_loss += static_cast<double>(bp.backpropagate(net, x.row(r).data(), t.row(r).data()));
    bp.add_gradient(net, expected.data());
  }
  std::vector<std::uint32_t> order(rows);
  std::iota(order.begin(), order.end(), 0u);
  PanelPatterns<Real> panels(sizes.front(), sizes.back());
  panels.assign(x, t, order.data(), order.size(), order.size());
  BatchGradient<Real> kernel(net, 2);
  std::vector<Real> got(net.parameter_count());
  const double loss = kernel.compute(net, panels, 0, got.data());
  double scale = 0;
  for (Real g : expected) scale = std::max(scale, std::abs(static_cast<double>(g)));
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_NEAR(static_cast<double>(got[k]), static_cast<double>(expected[k]), tolerance * scale)
        << "parameter " << k;
  }
  EXPECT_NEAR(loss, expected_loss, tolerance * expected_loss);
  EXPECT_NEAR(kernel.loss(net, panels, 0), expected_loss, tolerance * expected_loss);
}

TEST(BatchGradient, EqualsSumOfPatternGradientsDouble) {
  compare_with_pattern_sum<double>({3, 8, 2}, 1000, kDoubleSumTolerance);
}
TEST(BatchGradient, EqualsSumOfPatternGradientsDeepOddSizesDouble) {
  // Sizes that exercise every row and column remainder of the register blocks, and a partial panel.
  compare_with_pattern_sum<double>({5, 13, 7, 3}, 333, kDoubleSumTolerance);
}
TEST(BatchGradient, EqualsSumOfPatternGradientsFloat) {
  compare_with_pattern_sum<float>({16, 48, 2}, 2000, kFloatSumTolerance);
}

TEST(BatchGradient, BitIdenticalForAnyThreadCount) {
  auto net = make_network<float>({16, 48, 2}, 3);
  const int rows = 5000;
  MatrixRM<float> x = MatrixRM<float>::Random(rows, 16);
  MatrixRM<float> t = (0.5f * MatrixRM<float>::Random(rows, 2).array() + 0.5f).matrix();
  std::vector<std::uint32_t> order(rows);
  std::iota(order.begin(), order.end(), 0u);
  PanelPatterns<float> panels(16, 2);
  panels.assign(x, t, order.data(), order.size(), order.size());
  std::vector<float> g1(net.parameter_count()), g2(net.parameter_count()), g3(net.parameter_count());
  BatchGradient<float> k1(net, 1), k2(net, 2), k3(net, 3);
  const double l1 = k1.compute(net, panels, 0, g1.data());
  const double l2 = k2.compute(net, panels, 0, g2.data());
  const double l3 = k3.compute(net, panels, 0, g3.data());
  EXPECT_EQ(l1, l2);
  EXPECT_EQ(l1, l3);
  EXPECT_EQ(g1, g2);
  EXPECT_EQ(g1, g3);
}

TEST(PanelPatterns, SegmentsStartOnPanelsAndPadWithZeroMask) {
  MatrixRM<float> x = MatrixRM<float>::Random(100, 3);
  MatrixRM<float> t = MatrixRM<float>::Random(100, 2);
  std::vector<std::uint32_t> order(100);
  std::iota(order.rbegin(), order.rend(), 0u);  // reversed
  PanelPatterns<float> panels(3, 2);
  panels.assign(x, t, order.data(), 100, 30);
  constexpr int PW = kPanelWidth<float>;
  ASSERT_EQ(panels.segments().size(), 4u);
  EXPECT_EQ(panels.segments()[3].pattern_count, 10u);
  const auto& seg = panels.segments()[1];  // patterns 30..59 of the order: rows 69..40
  EXPECT_EQ(panels.inputs(seg.panel_begin)[0 * PW + 0], x(69, 0));
  EXPECT_EQ(panels.inputs(seg.panel_begin)[2 * PW + 1], x(68, 2));
  EXPECT_EQ(panels.targets(seg.panel_begin)[1 * PW + 2], t(67, 1));
  const std::size_t last_panel = seg.panel_end - 1;
  const int last_lane = static_cast<int>((30 - 1) % PW);
  EXPECT_EQ(panels.mask(last_panel)[last_lane], 1.0f);
  if (last_lane + 1 < PW) {
    EXPECT_EQ(panels.mask(last_panel)[last_lane + 1], 0.0f);
  }
}

}  // namespace
}  // namespace contactnn::mlp
