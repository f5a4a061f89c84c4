// Tests of lib/core/input_features: the paper's features and the affine frame of AB and AD.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "core/input_features.hpp"

namespace contactnn {
namespace {

TEST(InputFeatures, PaperIsTheIdentity) {
  const double paper[16] = {1.1, 0.9, 0.1, -0.1, 0.8, 0.2, 0.3, 0.05, 1, 2, 3, 4, 5, 6, 7, 8};
  double out[16] = {};
  map_input_features(InputFeatures::kPaper, SurfaceKind::kGregory, paper, out);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(out[i], paper[i]);
}

TEST(InputFeatures, AffineCoordinatesOfAParallelogramAreHalfTheLocalCoordinatesPlusAHalf) {
  // A = 0, B = (1, 0, 0), D = (0.3, 0.04, 0): a sheared segment of aspect 25, C = B + D. A point at
  // (xi, eta) of the facet is A + (xi + 1)/2 AB + (eta + 1)/2 AD, so alpha = (xi + 1)/2, beta = (eta + 1)/2
  // whatever the aspect ratio; heights scale by 1 / sqrt(|AB x AD|) = 1 / sqrt(0.04) = 5.
  const double xd = 0.3, yd = 0.04, xi = 0.4, eta = -0.7, z = 0.01;
  const double alpha = (xi + 1) / 2, beta = (eta + 1) / 2;
  const double paper[8] = {1 + xd, yd, 0.0, xd, yd, alpha + beta * xd, beta * yd, z};
  double out[8] = {};
  map_input_features(InputFeatures::kAffine, SurfaceKind::kBilinear, paper, out);
  EXPECT_NEAR(out[0], 1.0, 1e-15);  // C: alpha = beta = 1
  EXPECT_NEAR(out[1], 1.0, 1e-15);
  EXPECT_EQ(out[2], 0.0);
  EXPECT_NEAR(out[3], std::sqrt(xd * xd + yd * yd), 1e-15);       // |AD| / |AB|
  EXPECT_NEAR(out[4], xd / std::sqrt(xd * xd + yd * yd), 1e-15);  // cos(angle DAB)
  EXPECT_NEAR(out[5], alpha, 1e-15);
  EXPECT_NEAR(out[6], beta, 1e-14);
  EXPECT_NEAR(out[7], z * 5.0, 1e-15);
}

TEST(InputFeatures, AffineGregoryNormalsAreSlopesAlongAbAndAd) {
  // A node normal (p, q, 1): its slope along AB is p, along AD = (xd, yd)/rho it is (p xd + q yd)/rho.
  double paper[16] = {1, 1, 0, 0, 1, 0.2, 0.2, 0.1};
  for (int i = 0; i < 4; ++i) {
    paper[8 + 2 * i] = 0.1 * (i + 1);
    paper[9 + 2 * i] = -0.05 * (i + 1);
  }
  double out[16] = {};
  map_input_features(InputFeatures::kAffine, SurfaceKind::kGregory, paper, out);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(out[8 + 2 * i], paper[8 + 2 * i]);
    EXPECT_NEAR(out[9 + 2 * i], paper[9 + 2 * i], 1e-15);  // D = (0, 1): along AD is along y
  }
}

TEST(InputFeatures, NamesRoundTripAndUnknownIsRejected) {
  EXPECT_EQ(input_features_from_string(to_string(InputFeatures::kAffine)), InputFeatures::kAffine);
  EXPECT_EQ(input_features_from_string(to_string(InputFeatures::kPaper)), InputFeatures::kPaper);
  EXPECT_THROW((void)input_features_from_string("polar"), InvalidArgument);
}

}  // namespace
}  // namespace contactnn
