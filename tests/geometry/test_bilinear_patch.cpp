#include <gtest/gtest.h>

#include <random>

#include "geometry/bilinear_patch.hpp"

namespace contactnn::geometry {
namespace {

// Central differences with h = 1e-6 on O(1) coordinates: truncation ~1e-12, rounding ~1e-10.
constexpr double kFiniteDifferenceTol = 1e-8;

BilinearPatch warped_patch() {
  return BilinearPatch({Vec3(0, 0, 0), Vec3(1, 0, 0.1), Vec3(1.3, 0.9, -0.25), Vec3(-0.2, 0.8, 0.2)});
}

TEST(BilinearPatch, InterpolatesCornersInSpecOrder) {
  const BilinearPatch p = warped_patch();
  // SPEC 1: A at (-1,-1), B at (1,-1), C at (1,1), D at (-1,1).
  const double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT((p.position(corners[i][0], corners[i][1]) - p.nodes()[i]).norm(), 1e-15) << "corner " << i;
  }
  // The centre is the mean of the nodes (all N_i = 1/4).
  const Vec3 mean = 0.25 * (p.nodes()[0] + p.nodes()[1] + p.nodes()[2] + p.nodes()[3]);
  EXPECT_LT((p.position(0, 0) - mean).norm(), 1e-15);
}

TEST(BilinearPatch, DerivativesMatchFiniteDifferences) {
  const BilinearPatch p = warped_patch();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const double h = 1e-6;
  for (int k = 0; k < 50; ++k) {
    const double xi = u(rng), eta = u(rng);
    const SurfacePoint sp = p.evaluate(xi, eta);
    const Vec3 d_xi = (p.position(xi + h, eta) - p.position(xi - h, eta)) / (2 * h);
    const Vec3 d_eta = (p.position(xi, eta + h) - p.position(xi, eta - h)) / (2 * h);
    EXPECT_LT((sp.d_s - d_xi).norm(), kFiniteDifferenceTol);
    EXPECT_LT((sp.d_t - d_eta).norm(), kFiniteDifferenceTol);
    const Vec3 d_st = (p.evaluate(xi + h, eta).d_t - p.evaluate(xi - h, eta).d_t) / (2 * h);
    EXPECT_LT((sp.d_st - d_st).norm(), kFiniteDifferenceTol);
    EXPECT_EQ(sp.d_ss, Vec3::Zero());
    EXPECT_EQ(sp.d_tt, Vec3::Zero());
  }
}

TEST(BilinearPatch, CharacteristicLengthIsLongestNodeDistance) {
  const BilinearPatch p({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)});
  EXPECT_DOUBLE_EQ(p.characteristic_length(), std::sqrt(5.0));
}

}  // namespace
}  // namespace contactnn::geometry
