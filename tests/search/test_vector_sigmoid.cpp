// lib/search/vector_sigmoid.h against the C library: exp and expf to ~1 ulp over their whole range, the
// sigmoid of Eq 12 against 1 / (1 + std::exp(-gain u)), its clamped tails, and the C99 compilation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "search/vector_sigmoid.h"

extern "C" double contactnn_sigmoid_c99(double u, double gain);
extern "C" float contactnn_sigmoidf_c99(float u, float gain);

namespace contactnn::search {
namespace {

/// |got - want| in units of the last place of want (want's own ulp).
double ulps(double got, double want) {
  return std::abs(got - want) / (std::nextafter(want, std::numeric_limits<double>::infinity()) - want);
}
double ulps_float(double got, double want) {
  const auto w = static_cast<float>(want);
  return std::abs(got - want) /
         static_cast<double>(std::nextafter(w, std::numeric_limits<float>::infinity()) - w);
}

// Range reduction, a polynomial of ~5e-18 (double) or ~4e-9 (float) relative error, and a handful of
// roundings: within 2 ulps of the correctly rounded value (the library's exp rounds correctly to < 1 ulp).
constexpr double kMaxUlps = 2.0;

TEST(VectorSigmoid, ExpIsWithinTwoUlpsOfTheLibraryOnItsWholeRange) {
  double worst = 0.0;
  for (int i = 0; i <= 400000; ++i) {
    const double x = -699.99 + 1399.98 * i / 400000.0 + 1e-7 * (i % 7);
    worst = std::max(worst, ulps(cnn_exp(x), std::exp(x)));
  }
  EXPECT_LE(worst, kMaxUlps);
  EXPECT_EQ(cnn_exp(0.0), 1.0);
  // Clamped, never overflowing: the bound's value beyond it.
  EXPECT_EQ(cnn_exp(1e4), cnn_exp(700.0));
  EXPECT_EQ(cnn_exp(-1e4), cnn_exp(-700.0));
  EXPECT_TRUE(std::isfinite(cnn_exp(std::numeric_limits<double>::max())));
}

TEST(VectorSigmoid, ExpfIsWithinTwoUlpsOfTheExactValueOnItsWholeRange) {
  double worst = 0.0;
  for (int i = 0; i <= 400000; ++i) {
    const auto x = static_cast<float>(-87.0 + 175.0 * i / 400000.0);
    worst = std::max(worst, ulps_float(static_cast<double>(cnn_expf(x)), std::exp(static_cast<double>(x))));
  }
  EXPECT_LE(worst, kMaxUlps);
  EXPECT_EQ(cnn_expf(0.0f), 1.0f);
  EXPECT_TRUE(std::isfinite(cnn_expf(1e30f)));
}

TEST(VectorSigmoid, SigmoidIsEquation12) {
  for (const double gain : {1.0, 0.5, 2.0}) {
    for (int i = 0; i <= 20000; ++i) {
      const double u = -300.0 + 600.0 * i / 20000.0;
      const double want = 1.0 / (1.0 + std::exp(-gain * u));
      // Relative, down to the clamp at gain u = -700 (outputs ~1e-304).
      EXPECT_LE(std::abs(cnn_sigmoid(u, gain) - want), 4e-16 * want) << "u " << u;
      const auto uf = static_cast<float>(u), gf = static_cast<float>(gain);
      const double want_f = 1.0 / (1.0 + std::exp(-static_cast<double>(gf) * static_cast<double>(uf)));
      if (gf * uf > -80.0f) {
        EXPECT_LE(std::abs(static_cast<double>(cnn_sigmoidf(uf, gf)) - want_f), 4e-7 * want_f) << "u " << u;
      }
    }
  }
  // The clamped tails: tiny but positive, 1 at the top, never NaN for infinite arguments.
  EXPECT_GT(cnn_sigmoidf(-1e30f, 1.0f), 0.0f);
  EXPECT_LT(cnn_sigmoidf(-1e30f, 1.0f), 2e-35f);
  EXPECT_EQ(cnn_sigmoidf(1e30f, 1.0f), 1.0f);
  EXPECT_EQ(cnn_sigmoid(std::numeric_limits<double>::infinity(), 1.0), 1.0);
  EXPECT_GT(cnn_sigmoid(-std::numeric_limits<double>::infinity(), 1.0), 0.0);
}

TEST(VectorSigmoid, TheC99CompilationAgreesWithTheCxxOne) {
  for (int i = 0; i <= 1000; ++i) {
    const double u = -40.0 + 80.0 * i / 1000.0;
    // Contraction into FMA may differ between the two compilations: a few ulps.
    EXPECT_NEAR(contactnn_sigmoid_c99(u, 1.0), cnn_sigmoid(u, 1.0), 1e-15);
    EXPECT_NEAR(contactnn_sigmoidf_c99(static_cast<float>(u), 1.0f),
                cnn_sigmoidf(static_cast<float>(u), 1.0f), 1e-6f);
  }
}

}  // namespace
}  // namespace contactnn::search
