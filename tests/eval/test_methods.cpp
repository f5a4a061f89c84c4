// Tests of lib/eval/placement, methods and accuracy: world coordinates, the methods' statuses and the
// failure rules of compare_with_labels.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dataset/labeller.hpp"
#include "eval/accuracy.hpp"
#include "eval/placement.hpp"

namespace contactnn::eval {
namespace {

using geometry::Configuration;
using geometry::Vec3;

// Features of a mildly warped bilinear configuration well inside the paper's domain.
constexpr std::array<double, 16> kFeatures = {1.1, 0.9, 0.12, -0.1, 0.95, 0.3, 0.4, 0.2, 0, 0, 0, 0, 0, 0, 0, 0};
// Rounding of a similarity map with scale up to 1e2 and translation up to 1e3: ~1e-13 relative in the frame.
constexpr double kPlacementTol = 1e-11;
// Newton converges quadratically: 10 undamped steps from the centre reach the label to rounding here.
constexpr double kNewtonTol = 1e-12;

/// A predictor returning fixed coordinates: the study's interface without a trained network.
struct FixedPredictor {
  std::array<double, 2> value{0.25, -0.5};
  int calls = 0;
  void predict(const double*, double* out) {
    ++calls;
    out[0] = value[0];
    out[1] = value[1];
  }
};

geometry::TrainingDomain domain_around(const std::array<double, 16>& f, double half_width) {
  geometry::TrainingDomain d;
  d.surface = SurfaceKind::kBilinear;
  for (int i = 0; i < 8; ++i) {
    d.feature_min.push_back(f[static_cast<std::size_t>(i)] - half_width);
    d.feature_max.push_back(f[static_cast<std::size_t>(i)] + half_width);
  }
  return d;
}

TEST(Placement, FeaturesRoundTripThroughAnyPlacement) {
  const Configuration local = configuration_from_features(SurfaceKind::kBilinear, kFeatures.data());
  for (std::uint64_t row = 0; row < 20; ++row) {
    const Placement p = random_placement(7, row);
    EXPECT_NEAR(p.rotation.determinant(), 1.0, 1e-14);
    EXPECT_NEAR((p.rotation.transpose() * p.rotation - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-14);
    const geometry::NormaliseOutcome n = geometry::normalise(place(local, p), SurfaceKind::kBilinear);
    ASSERT_TRUE(n.value);
    for (int f = 0; f < 8; ++f) {
      EXPECT_NEAR(n.value->features[static_cast<std::size_t>(f)], kFeatures[static_cast<std::size_t>(f)],
                  kPlacementTol)
          << "row " << row << " feature " << f;
    }
  }
  // A pure function of (seed, index).
  EXPECT_EQ(random_placement(7, 3).translation, random_placement(7, 3).translation);
  EXPECT_NE(random_placement(7, 3).translation, random_placement(7, 4).translation);
}

TEST(Placement, GregoryNormalsComeBackFromTheirFeatures) {
  std::array<double, 16> f = kFeatures;
  const std::array<double, 8> pq = {0.05, -0.1, 0.0, 0.12, -0.08, 0.02, 0.1, 0.1};
  for (int i = 0; i < 8; ++i) f[static_cast<std::size_t>(8 + i)] = pq[static_cast<std::size_t>(i)];
  const Configuration c = configuration_from_features(SurfaceKind::kGregory, f.data());
  const geometry::NormaliseOutcome n = geometry::normalise(place(c, random_placement(1, 0)), SurfaceKind::kGregory);
  ASSERT_TRUE(n.value);
  for (int i = 8; i < 16; ++i) {
    EXPECT_NEAR(n.value->features[static_cast<std::size_t>(i)], f[static_cast<std::size_t>(i)], kPlacementTol);
  }
}

TEST(Methods, NewtonFromWorldCoordinatesMatchesTheLabel) {
  const Configuration local = configuration_from_features(SurfaceKind::kBilinear, kFeatures.data());
  const dataset::Label label = dataset::label_configuration(local, SurfaceKind::kBilinear);
  ASSERT_EQ(label.status, Status::kOk);
  const Configuration world = place(local, random_placement(3, 0));
  const Estimate fixed = newton_fixed_estimate(world, SurfaceKind::kBilinear, 10);
  EXPECT_NEAR(fixed.param[0], label.param[0], kNewtonTol);
  EXPECT_NEAR(fixed.param[1], label.param[1], kNewtonTol);
  const Estimate converged = newton_converged_estimate(world, SurfaceKind::kBilinear, {});
  EXPECT_EQ(converged.status, Status::kOk);
  EXPECT_NEAR(converged.param[0], label.param[0], kNewtonTol);
  EXPECT_GE(converged.iterations, 1);
  const Estimate reference = reference_estimate(world, SurfaceKind::kBilinear, {});
  EXPECT_EQ(reference.status, Status::kOk);
  EXPECT_NEAR(reference.param[1], label.param[1], kNewtonTol);
}

TEST(Methods, NetworkStatusesFromWorldCoordinates) {
  const Configuration local = configuration_from_features(SurfaceKind::kBilinear, kFeatures.data());
  FixedPredictor p;
  geometry::TrainingDomain domain = domain_around(kFeatures, 0.05);
  domain.filters.convex = true;
  const Estimate inside = network_estimate(place(local, random_placement(5, 1)), SurfaceKind::kBilinear, p, &domain);
  EXPECT_EQ(inside.status, Status::kOk);
  EXPECT_EQ(inside.param, p.value);

  Configuration far = local;
  far.slave.z() = 1.5;  // outside z_limit and the feature range
  const Estimate out = network_estimate(far, SurfaceKind::kBilinear, p, &domain);
  EXPECT_EQ(out.status, Status::kOutOfDomain);
  EXPECT_EQ(out.param, p.value);  // the prediction is still made

  Configuration nan = local;
  nan.nodes[2].x() = std::numeric_limits<double>::quiet_NaN();
  const int calls = p.calls;
  EXPECT_EQ(network_estimate(nan, SurfaceKind::kBilinear, p, &domain).status, Status::kInvalid);

  Configuration flat = local;
  flat.nodes[3] = Vec3(2.0, 0.0, 0.0);  // D on the line AB: no frame
  EXPECT_EQ(network_estimate(flat, SurfaceKind::kBilinear, p, &domain).status, Status::kDegenerate);
  EXPECT_EQ(p.calls, calls);  // no prediction without a frame
}

TEST(CompareWithLabels, FailureRulesAndStatistics) {
  Estimates e;
  e.method = Method{Method::Kind::kNewtonFixed, 3};
  e.resize(6);
  dataset::MatrixRM<double> labels(6, 2);
  std::vector<Status> label_status(6, Status::kOk);
  for (int r = 0; r < 6; ++r) {
    labels(r, 0) = 0.1 * r;
    labels(r, 1) = -0.1 * r;
    e.param[static_cast<std::size_t>(r)] = {0.1 * r + 0.01, -0.1 * r};
  }
  label_status[1] = Status::kNoConvergence;                              // reference failure
  e.param[2] = {std::numeric_limits<double>::quiet_NaN(), 0.0};          // non-finite estimate
  e.param[3] = {2.0 + 1e-9, 0.0};                                        // beyond the box [-2, 2]
  e.status[4] = Status::kOutOfDomain;                                    // network-style failure
  e.param[5] = {1.5, -0.5};                                              // outside the domain, inside the box
  const MethodErrors m = compare_with_labels(e, labels, label_status, SurfaceKind::kBilinear, 0.5);
  EXPECT_EQ(m.failures_reference, 1);
  EXPECT_EQ(m.failures_method, 3);
  EXPECT_EQ(m.stats[0].n, 2);  // rows 0 and 5
  EXPECT_EQ(m.stats[0].failures, 4);
  EXPECT_EQ(m.outside_domain, 1);
  EXPECT_EQ(m.status_counts[static_cast<std::size_t>(Status::kOutOfDomain)], 1);
  // Row 0: error 0.01; row 5: 1.5 - 0.5 = 1.0.
  EXPECT_NEAR(m.stats[0].mean_abs, (0.01 + 1.0) / 2, 1e-15);
  EXPECT_NEAR(m.stats[1].max_abs, 0.0, 1e-15);
}

TEST(Methods, ErrorTableListsNetworkNewtonKAndConverged) {
  const std::vector<Method> m = error_table_methods(10);
  ASSERT_EQ(m.size(), 12u);
  EXPECT_EQ(m.front().name(), "network");
  EXPECT_EQ(m[1].name(), "newton_1");
  EXPECT_EQ(m[10].name(), "newton_10");
  EXPECT_EQ(m.back().name(), "newton_converged");
}

TEST(CountValues, LastBinTakesTheRest) {
  const std::vector<int> v = {0, 3, 3, 5, 99, -1, 4};
  const std::vector<bool> include = {true, true, true, true, true, true, false};
  EXPECT_EQ(count_values(v, include, 5), (std::vector<std::int64_t>{2, 0, 0, 2, 2}));
}

}  // namespace
}  // namespace contactnn::eval
