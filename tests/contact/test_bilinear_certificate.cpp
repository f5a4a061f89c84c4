// contact::BilinearCertificate: where it answers, the answer is the reference's
// (projection::closest_point_on_face, a grid of nine Newton starts) and no point of the facet is nearer (a
// dense sampling oracle); it answers for most slave nodes near mildly distorted facets and refuses where a
// facet is folded.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "contact/bilinear_certificate.hpp"
#include "projection/closest_point_on_face.hpp"
#include "projection/closest_point_oracle.hpp"

namespace contactnn::contact {
namespace {

/// A random facet: the unit square's corners moved by up to `distortion` in each direction, placed at
/// `offset`.
std::array<Vec3, 4> random_facet(std::mt19937_64& rng, double distortion, const Vec3& offset) {
  std::uniform_real_distribution<double> u(-distortion, distortion);
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  std::array<Vec3, 4> x;
  for (std::size_t k = 0; k < 4; ++k) x[k] = square[k] + Vec3(u(rng), u(rng), u(rng)) + offset;
  return x;
}

struct Tally {
  int answered = 0;
  int total = 0;
};

/// Random slave nodes within about one facet of `nodes`: each certified answer against the reference and a
/// sampling oracle.
Tally check_facet(const std::array<Vec3, 4>& nodes, std::mt19937_64& rng, int slaves, double height) {
  const BilinearCertificate certificate = BilinearCertificate::prepare(nodes);
  const geometry::BilinearPatch patch(nodes);
  const projection::ProjectionOptions options;
  std::uniform_real_distribution<double> u(-0.5, 1.5), w(-height, height);
  // Rounding of the world coordinates (the sampled points are not relative to the facet).
  const double rounding = 1e-12 * std::max(1.0, nodes[0].norm());
  Tally tally;
  for (int i = 0; i < slaves; ++i) {
    const Vec3 slave = nodes[0] + Vec3(u(rng), u(rng), w(rng));
    ++tally.total;
    const auto fast = certificate.closest_point(slave, options);
    if (!fast) continue;
    ++tally.answered;
    const projection::FaceClosestPoint reference = projection::closest_point_on_face(patch, slave, options);
    EXPECT_EQ(reference.status, Status::kOk);
    EXPECT_EQ(fast->status, Status::kOk);
    EXPECT_EQ(fast->location, reference.location) << "slave " << slave.transpose();
    EXPECT_EQ(fast->feature, reference.feature);
    EXPECT_LE((fast->point - reference.point).norm(), 1e-12) << "slave " << slave.transpose();
    EXPECT_NEAR(fast->distance, reference.distance, 1e-12);
    EXPECT_LE((fast->normal - reference.normal).norm(), 1e-9);
    // No sampled point of the facet is nearer (a 101 x 101 grid of the square).
    const double sampled = testing::sampled_distance(patch, slave, -1.0, 1.0, 101);
    EXPECT_LE(fast->distance, sampled + rounding);
    // An interior answer is the reference's report at its parameters, bit for bit (a run that ends on its
    // residual reports from its own last evaluation: it must be the one at those parameters).
    if (fast->location == Location::kFace) {
      const projection::FaceClosestPoint report = projection::nearest_of_interior_and_edges(
          certificate.patch, slave - certificate.origin, &fast->param, fast->iterations, nullptr, true);
      EXPECT_EQ(fast->point, Vec3(report.point + certificate.origin)) << "slave " << slave.transpose();
      EXPECT_EQ(fast->normal, report.normal);
      EXPECT_EQ(fast->distance, report.distance);
    }
  }
  return tally;
}

TEST(BilinearCertificate, EqualsTheReferenceOnMildFacets) {
  std::mt19937_64 rng(7);
  Tally all;
  for (int f = 0; f < 40; ++f) {
    const Tally t = check_facet(random_facet(rng, 0.1, Vec3(0, 0, 0)), rng, 40, 0.5);
    all.answered += t.answered;
    all.total += t.total;
  }
  // The certificate is for the common case: most slave nodes within half a facet of mildly distorted facets
  // (corners moved by up to a tenth of an edge in each direction) get it.
  EXPECT_GT(all.answered, all.total * 3 / 4) << all.answered << " of " << all.total;
  std::printf("certified: %d of %d\n", all.answered, all.total);
}

TEST(BilinearCertificate, EqualsTheReferenceOnDistortedFacetsFarFromTheOrigin) {
  std::mt19937_64 rng(8);
  Tally all;
  for (int f = 0; f < 40; ++f) {
    const Tally t = check_facet(random_facet(rng, 0.35, Vec3(1e4, -3e3, 7e2)), rng, 40, 1.0);
    all.answered += t.answered;
    all.total += t.total;
  }
  EXPECT_GT(all.answered, 0);
  std::printf("certified: %d of %d\n", all.answered, all.total);
}

TEST(BilinearCertificate, ExactWhereTheAnswerIsACornerOrAnEdge) {
  const std::array<Vec3, 4> nodes = {Vec3(0, 0, 0), Vec3(1, 0, 0.1), Vec3(1, 1, 0), Vec3(0, 1, -0.05)};
  const BilinearCertificate certificate = BilinearCertificate::prepare(nodes);
  const geometry::BilinearPatch patch(nodes);
  for (const Vec3& slave :
       {Vec3(-0.3, -0.2, 0.4), Vec3(0.5, -0.4, 0.2), Vec3(1.3, 0.5, -0.2), Vec3(1.2, 1.3, 0.1)}) {
    const auto fast = certificate.closest_point(slave, {});
    ASSERT_TRUE(fast.has_value()) << slave.transpose();
    const projection::FaceClosestPoint reference = projection::closest_point_on_face(patch, slave, {});
    EXPECT_NE(fast->location, Location::kFace);
    EXPECT_EQ(fast->location, reference.location);
    EXPECT_EQ(fast->feature, reference.feature);
    EXPECT_LE((fast->point - reference.point).norm(), 1e-12);
  }
}

TEST(BilinearCertificate, RefusesFoldedAndStronglyWarpedFacets) {
  // A bow tie (C and D swapped): its Jacobian changes sign on the square.
  const std::array<Vec3, 4> bow_tie = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  EXPECT_EQ(BilinearCertificate::prepare(bow_tie).lambda_floor, 0.0);
  EXPECT_FALSE(BilinearCertificate::prepare(bow_tie).closest_point(Vec3(0.5, 0.5, 1.0), {}).has_value());
  // A saddle with a unit twist: a slave node a unit above its centre sees two stationary points; no
  // certificate.
  const std::array<Vec3, 4> saddle = {Vec3(0, 0, 1), Vec3(1, 0, -1), Vec3(1, 1, 1), Vec3(0, 1, -1)};
  const BilinearCertificate certificate = BilinearCertificate::prepare(saddle);
  EXPECT_FALSE(certificate.convex_for(Vec3(0.5, 0.5, 1.0) - saddle[0]));
  // Non-finite nodes and slave nodes.
  const std::array<Vec3, 4> broken = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, std::nan("")), Vec3(0, 1, 0)};
  EXPECT_EQ(BilinearCertificate::prepare(broken).lambda_floor, 0.0);
  const std::array<Vec3, 4> flat = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  EXPECT_FALSE(BilinearCertificate::prepare(flat).closest_point(Vec3(0.5, std::nan(""), 0), {}).has_value());
}

TEST(BilinearCertificate, WhereAFacetHasSeveralStationaryPointsItAnswersOnlyWithTheNearest) {
  // Hyperbolic paraboloids z = k s t: above the centre, the centre is a saddle of |S - P| (a Newton run from
  // the centre stops there at once) and the nearest points lie along a diagonal. Every answer given is the
  // reference's; the certificate must refuse the slave nodes with a saddle in reach.
  std::mt19937_64 rng(10);
  int refused = 0;
  for (const double k : {0.2, 0.5, 1.0}) {
    const std::array<Vec3, 4> nodes = {Vec3(0, 0, k), Vec3(2, 0, -k), Vec3(2, 2, k), Vec3(0, 2, -k)};
    const Tally t = check_facet(nodes, rng, 200, 3.0);
    refused += t.total - t.answered;
    const auto centre = BilinearCertificate::prepare(nodes).closest_point(Vec3(1, 1, 2.0), {});
    if (centre) {
      const auto reference =
          projection::closest_point_on_face(geometry::BilinearPatch(nodes), Vec3(1, 1, 2.0), {});
      EXPECT_LE((centre->point - reference.point).norm(), 1e-12) << "k " << k;
    }
  }
  EXPECT_GT(refused, 0);
}

TEST(BilinearCertificate, AWarmStartGivesTheSameAnswer) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> start(-1.0, 1.0), u(-0.3, 1.3);
  for (int f = 0; f < 20; ++f) {
    const auto nodes = random_facet(rng, 0.1, Vec3(0, 0, 0));
    const BilinearCertificate certificate = BilinearCertificate::prepare(nodes);
    for (int i = 0; i < 20; ++i) {
      const Vec3 slave(u(rng), u(rng), 0.3 * start(rng));
      const std::array<double, 2> from = {start(rng), start(rng)};
      const auto cold = certificate.closest_point(slave, {});
      const auto warm = certificate.closest_point(slave, {}, &from);
      if (!cold || !warm) continue;
      EXPECT_EQ(cold->location, warm->location);
      EXPECT_LE((cold->point - warm->point).norm(), 1e-12);
    }
  }
}

}  // namespace
}  // namespace contactnn::contact
