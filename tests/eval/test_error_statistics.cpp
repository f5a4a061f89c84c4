// Tests of lib/eval/error_statistics: known arrays written out in full.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/error.hpp"
#include "eval/error_statistics.hpp"

namespace contactnn::eval {
namespace {

// Hand-computed values below are exact decimals; the code's sums round at the last bit only.
constexpr double kTol = 1e-15;

TEST(ErrorStatistics, KnownArrayWithFailuresExcluded) {
  // Rows 2 and 5 are failures: their values (one absurd, one NaN) must neither enter nor poison the
  // statistics.
  const std::vector<double> e = {0.1, -0.3, 1e6, 0.2, -0.1, std::numeric_limits<double>::quiet_NaN(), 0.5};
  const std::vector<std::uint8_t> failed = {0, 0, 1, 0, 0, 1, 0};
  const ErrorStatistics s = summarize_errors(e, failed);
  // Used: 0.1, -0.3, 0.2, -0.1, 0.5 -> |e| = 0.1, 0.3, 0.2, 0.1, 0.5, sorted 0.1 0.1 0.2 0.3 0.5.
  EXPECT_EQ(s.rows, 7);
  EXPECT_EQ(s.n, 5);
  EXPECT_EQ(s.failures, 2);
  EXPECT_NEAR(s.mean_abs, 1.2 / 5, kTol);     // 0.24
  EXPECT_NEAR(s.mean_signed, 0.4 / 5, kTol);  // 0.08
  // std |e|: deviations -0.14 0.06 -0.04 -0.14 0.26 -> squares sum 0.0196+0.0036+0.0016+0.0196+0.0676 =
  // 0.112.
  EXPECT_NEAR(s.std_abs, std::sqrt(0.112 / 5), kTol);
  // std e: deviations 0.02 -0.38 0.12 -0.18 0.42 -> 0.0004+0.1444+0.0144+0.0324+0.1764 = 0.368.
  EXPECT_NEAR(s.std_signed, std::sqrt(0.368 / 5), kTol);
  EXPECT_NEAR(s.median_abs, 0.2, kTol);
  // p99: h = 4 * 0.99 = 3.96 -> 0.3 + 0.96 * (0.5 - 0.3) = 0.492.
  EXPECT_NEAR(s.p99_abs, 0.492, kTol);
  EXPECT_DOUBLE_EQ(s.max_abs, 0.5);
}

TEST(ErrorStatistics, EvenCountMedianIsMeanOfMiddleTwo) {
  const std::vector<double> e = {-4.0, 1.0, 3.0, -2.0};
  const std::vector<std::uint8_t> failed(4, 0);
  const ErrorStatistics s = summarize_errors(e, failed);
  EXPECT_DOUBLE_EQ(s.median_abs, 2.5);  // |e| sorted 1 2 3 4
  EXPECT_DOUBLE_EQ(s.max_abs, 4.0);
  EXPECT_DOUBLE_EQ(s.mean_abs, 2.5);
  EXPECT_DOUBLE_EQ(s.mean_signed, -0.5);
}

TEST(ErrorStatistics, AllFailedGivesZerosNotNaN) {
  const std::vector<double> e = {std::numeric_limits<double>::infinity(), 1.0};
  const std::vector<std::uint8_t> failed = {1, 1};
  const ErrorStatistics s = summarize_errors(e, failed);
  EXPECT_EQ(s.n, 0);
  EXPECT_EQ(s.failures, 2);
  EXPECT_EQ(s.mean_abs, 0.0);
  EXPECT_EQ(s.std_signed, 0.0);
  EXPECT_EQ(s.max_abs, 0.0);
}

TEST(ErrorStatistics, NonFiniteErrorInUsedRowThrows) {
  const std::vector<double> e = {0.1, std::numeric_limits<double>::quiet_NaN()};
  const std::vector<std::uint8_t> failed = {0, 0};
  EXPECT_THROW((void)summarize_errors(e, failed), NumericalError);
}

TEST(ErrorStatistics, MismatchedLengthsThrow) {
  const std::vector<double> e = {0.1, 0.2};
  const std::vector<std::uint8_t> failed = {0};
  EXPECT_THROW((void)summarize_errors(e, failed), InvalidArgument);
}

TEST(Percentile, LinearInterpolationBetweenOrderStatistics) {
  const std::vector<double> x = {1.0, 2.0, 4.0, 8.0, 16.0};
  EXPECT_DOUBLE_EQ(percentile(x, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(percentile(x, 100.0), 16.0);
  EXPECT_DOUBLE_EQ(percentile(x, 50.0), 4.0);
  EXPECT_DOUBLE_EQ(percentile(x, 25.0), 2.0);   // h = 1
  EXPECT_DOUBLE_EQ(percentile(x, 87.5), 12.0);  // h = 3.5 -> 8 + 0.5 * 8
  const std::vector<double> one = {7.0};
  EXPECT_DOUBLE_EQ(percentile(one, 99.0), 7.0);
  EXPECT_THROW((void)percentile(std::vector<double>{}, 50.0), InvalidArgument);
  EXPECT_THROW((void)percentile(x, 101.0), InvalidArgument);
}

}  // namespace
}  // namespace contactnn::eval
