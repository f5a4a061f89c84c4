// Tests of lib/eval/histogram: counts, edge conventions, outliers, CSV.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "core/error.hpp"
#include "eval/histogram.hpp"
#include "io/csv.hpp"

namespace contactnn::eval {
namespace {

TEST(Histogram, KnownCountsEdgesAndOutliers) {
  // [-1, 1] in 4 bins of width 0.5: edges -1, -0.5, 0, 0.5, 1.
  const std::vector<double> v = {-1.0, -0.75, -0.5, -0.25, 0.0, 0.5, 0.9999, 1.0, 1.0001, -1.0001, -7.0, 3.0};
  const std::vector<std::uint8_t> failed(v.size(), 0);
  const Histogram h = make_histogram(v, failed, -1.0, 1.0, 4);
  // Inner edges -0.5, 0, 0.5 go to the bin on their right; -1 (= lo) to bin 0; 1 (= hi) to the last bin.
  ASSERT_EQ(h.bins(), 4);
  EXPECT_EQ(h.counts[0], 2);  // -1, -0.75
  EXPECT_EQ(h.counts[1], 2);  // -0.5, -0.25
  EXPECT_EQ(h.counts[2], 1);  // 0
  EXPECT_EQ(h.counts[3], 3);  // 0.5, 0.9999, 1.0
  EXPECT_EQ(h.underflow, 2);  // -1.0001, -7
  EXPECT_EQ(h.overflow, 2);   // 1.0001, 3
  EXPECT_EQ(h.excluded, 0);
  EXPECT_EQ(h.total(), static_cast<std::int64_t>(v.size()));
}

TEST(Histogram, FailuresAreExcludedAndCounted) {
  const std::vector<double> v = {0.1, std::numeric_limits<double>::quiet_NaN(), 5.0};
  const std::vector<std::uint8_t> failed = {0, 1, 1};
  const Histogram h = make_histogram(v, failed, -1.0, 1.0, 2);
  EXPECT_EQ(h.excluded, 2);
  EXPECT_EQ(h.total(), 1);
  EXPECT_EQ(h.counts[1], 1);
  EXPECT_EQ(h.overflow, 0);
}

TEST(Histogram, EveryEdgeValueGoesToTheBinOnItsRight) {
  // Edges lo + k w with w = 0.2/7 are not exact decimals: the division (x - lo) / w can round across an edge,
  // the rule must not.
  const Histogram h = make_histogram(std::vector<double>{}, std::vector<std::uint8_t>{}, -0.1, 0.1, 7);
  for (int k = 0; k < h.bins(); ++k) {
    EXPECT_EQ(h.bin_of(h.edge(k)), k) << "edge " << k << " = " << h.edge(k);
    EXPECT_EQ(h.bin_of(std::nextafter(h.edge(k + 1), -1.0)), k) << "just below edge " << k + 1;
  }
  EXPECT_EQ(h.edge(h.bins()), 0.1);  // exactly hi
  EXPECT_EQ(h.bin_of(0.1), h.bins() - 1);
  EXPECT_EQ(h.bin_of(std::nextafter(0.1, 1.0)), h.bins());
  EXPECT_EQ(h.bin_of(std::nextafter(-0.1, -1.0)), -1);
}

TEST(Histogram, CountsSumToNForManyValues) {
  std::vector<double> v;
  for (int i = -5000; i <= 5000; ++i) v.push_back(i * 1e-4 * 1.37);  // spans beyond [-0.5, 0.5]
  const std::vector<std::uint8_t> failed(v.size(), 0);
  const Histogram h = make_histogram(v, failed, -0.5, 0.5, 33);
  EXPECT_EQ(h.total(), static_cast<std::int64_t>(v.size()));
  EXPECT_GT(h.underflow, 0);
  EXPECT_GT(h.overflow, 0);
  EXPECT_EQ(h.underflow, h.overflow);  // symmetric data, symmetric range
}

TEST(Histogram, BadArgumentsThrow) {
  const std::vector<double> v = {0.0};
  const std::vector<std::uint8_t> failed = {0};
  EXPECT_THROW((void)make_histogram(v, failed, 1.0, 1.0, 4), InvalidArgument);
  EXPECT_THROW((void)make_histogram(v, failed, -1.0, 1.0, 0), InvalidArgument);
  const std::vector<double> nan = {std::numeric_limits<double>::quiet_NaN()};
  EXPECT_THROW((void)make_histogram(nan, failed, -1.0, 1.0, 4), NumericalError);
}

TEST(NiceCeil, OneTwoFiveTimesPowersOfTen) {
  EXPECT_DOUBLE_EQ(nice_ceil(0.0123), 0.02);
  EXPECT_DOUBLE_EQ(nice_ceil(0.02), 0.02);
  EXPECT_DOUBLE_EQ(nice_ceil(0.021), 0.05);
  EXPECT_DOUBLE_EQ(nice_ceil(0.051), 0.1);
  EXPECT_DOUBLE_EQ(nice_ceil(1.0), 1.0);
  EXPECT_DOUBLE_EQ(nice_ceil(7.0), 10.0);
  EXPECT_DOUBLE_EQ(nice_ceil(1e-3), 1e-3);
  EXPECT_DOUBLE_EQ(nice_ceil(-3.0), 1.0);
}

TEST(Histogram, CsvHasEveryBinAndTheOutlierRows) {
  const std::vector<double> v = {-2.0, 0.25, 0.75, 9.0};
  const std::vector<std::uint8_t> failed = {0, 0, 0, 1};
  const Histogram h = make_histogram(v, failed, 0.0, 1.0, 2);
  const io::CsvTable t = io::parse_csv(histogram_csv(h), "hist.csv");
  ASSERT_EQ(t.rows.size(), 5u);  // 2 bins + underflow + overflow + excluded
  EXPECT_EQ(t.header, (std::vector<std::string>{"bin", "lower_edge", "upper_edge", "count"}));
  EXPECT_EQ(t.rows[0][3], "1");
  EXPECT_EQ(t.rows[1][1], "0.5");
  EXPECT_EQ(t.rows[2][0], "underflow");
  EXPECT_EQ(t.rows[2][3], "1");
  EXPECT_EQ(t.rows[3][0], "overflow");
  EXPECT_EQ(t.rows[3][3], "0");
  EXPECT_EQ(t.rows[4][0], "excluded");
  EXPECT_EQ(t.rows[4][3], "1");
}

}  // namespace
}  // namespace contactnn::eval
