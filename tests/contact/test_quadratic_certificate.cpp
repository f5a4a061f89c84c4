// contact::QuadraticCertificate: where it answers for a quad8 or tri6 face, the answer is the reference's
// (projection::closest_point_on_serendipity_quad / closest_point_on_quadratic_triangle, Newton from sampled
// starts); it answers for most slave nodes near mildly curved faces, and refuses where f is not convex (a
// slave beyond the centre of curvature of a strongly curved face) or the face is folded.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "contact/quadratic_certificate.hpp"
#include "projection/closest_point_on_quadratic_face.hpp"
#include "projection/closest_point_oracle.hpp"

namespace contactnn::contact {
namespace {

/// The mid-side node of the edge x-y: its midpoint moved off the chord by up to `bulge` x the edge's length
/// across the face (z) and a quarter of that along it (a curved edge, its node a little off its middle).
Vec3 mid_side(std::mt19937_64& rng, const Vec3& x, const Vec3& y, double bulge) {
  std::uniform_real_distribution<double> u(-bulge, bulge);
  return 0.5 * (x + y) + (y - x).norm() * Vec3(0.25 * u(rng), 0.25 * u(rng), u(rng));
}

/// A random quad8: the unit square's corners moved by up to `distortion`, mid-side nodes off their chords by
/// up to `bulge` of the edge, placed at `offset`.
geometry::SerendipityQuad random_quad8(std::mt19937_64& rng, double distortion, double bulge,
                                       const Vec3& offset) {
  std::uniform_real_distribution<double> u(-distortion, distortion);
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  std::array<Vec3, 8> x;
  for (std::size_t k = 0; k < 4; ++k) x[k] = square[k] + Vec3(u(rng), u(rng), u(rng)) + offset;
  for (std::size_t k = 0; k < 4; ++k) x[4 + k] = mid_side(rng, x[k], x[(k + 1) % 4], bulge);
  return geometry::SerendipityQuad(x);
}

geometry::QuadraticTriangle random_tri6(std::mt19937_64& rng, double distortion, double bulge,
                                        const Vec3& offset) {
  std::uniform_real_distribution<double> u(-distortion, distortion);
  const std::array<Vec3, 3> corners = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  std::array<Vec3, 6> x;
  for (std::size_t k = 0; k < 3; ++k) x[k] = corners[k] + Vec3(u(rng), u(rng), u(rng)) + offset;
  for (std::size_t k = 0; k < 3; ++k) x[3 + k] = mid_side(rng, x[k], x[(k + 1) % 3], bulge);
  return geometry::QuadraticTriangle(x);
}

projection::FaceClosestPoint reference(const geometry::SerendipityQuad& face, const Vec3& slave,
                                       const projection::ProjectionOptions& options) {
  return projection::closest_point_on_serendipity_quad(face, slave, options);
}
projection::FaceClosestPoint reference(const geometry::QuadraticTriangle& face, const Vec3& slave,
                                       const projection::ProjectionOptions& options) {
  return projection::closest_point_on_quadratic_triangle(face, slave, options);
}

struct Tally {
  int answered = 0;
  int total = 0;
  int mismatched = 0;
};

/// Random slave nodes around the face (parameters a little beyond it, heights up to `height`), from the
/// centre and from a warm start: each certified answer against the reference.
template <class Face>
Tally check_face(const Face& face, std::mt19937_64& rng, int slaves, double height) {
  const QuadraticCertificate certificate = QuadraticCertificate::prepare(face);
  const projection::ProjectionOptions options;
  const bool triangle = certificate.triangle;
  std::uniform_real_distribution<double> u(triangle ? -0.3 : -1.3, triangle ? 1.3 : 1.3), w(-height, height);
  const double size = face.characteristic_length();
  Tally tally;
  for (int i = 0; i < slaves; ++i) {
    const double a = u(rng), b = u(rng);
    const geometry::SurfacePoint sp = face.evaluate(a, b);
    const Vec3 n = sp.d_s.cross(sp.d_t).normalized();
    const Vec3 slave = sp.position + w(rng) * n;
    const std::array<double, 2> warm = {std::clamp(a, triangle ? 0.0 : -1.0, 1.0),
                                        std::clamp(b, triangle ? 0.0 : -1.0, 1.0)};
    for (const std::array<double, 2>* start : {static_cast<const std::array<double, 2>*>(nullptr), &warm}) {
      ++tally.total;
      const auto fast = certificate.closest_point(slave, options, start);
      if (!fast) continue;
      ++tally.answered;
      const projection::FaceClosestPoint want = reference(face, slave, options);
      const bool same = want.status == fast->status && want.location == fast->location &&
                        want.feature == fast->feature && (fast->point - want.point).norm() <= 1e-10 * size &&
                        std::abs(fast->param[0] - want.param[0]) <= 1e-10 &&
                        std::abs(fast->param[1] - want.param[1]) <= 1e-10 &&
                        std::abs(fast->distance - want.distance) <= 1e-10 * size &&
                        (fast->normal - want.normal).norm() <= 1e-8;
      if (!same) ++tally.mismatched;
      EXPECT_TRUE(same) << "slave " << slave.transpose() << " location " << static_cast<int>(fast->location)
                        << " / " << static_cast<int>(want.location) << " param " << fast->param[0] << " "
                        << fast->param[1] << " / " << want.param[0] << " " << want.param[1] << " distance "
                        << fast->distance << " / " << want.distance;
    }
  }
  return tally;
}

template <class Make>
void check_faces(Make&& make, double bulge, double height, double fraction, const char* name) {
  std::mt19937_64 rng(1234);
  Tally all;
  for (int face = 0; face < 60; ++face) {
    const Vec3 offset = face % 3 == 0 ? Vec3(1e3, -2e3, 5e2) : Vec3::Zero();
    const auto f = make(rng, 0.1, bulge, offset);
    const Tally t = check_face(f, rng, 100, height);
    all.answered += t.answered;
    all.total += t.total;
    all.mismatched += t.mismatched;
  }
  std::printf("%s bulge %.2f height %.2f: certified %d of %d\n", name, bulge, height, all.answered,
              all.total);
  EXPECT_EQ(all.mismatched, 0);
  EXPECT_GE(all.answered, fraction * all.total) << name;
}

TEST(QuadraticCertificate, Quad8AnswersAsTheReference) {
  // Mildly curved faces, slaves near: most answered. Strongly curved, and far: checked where answered.
  check_faces(random_quad8, 0.05, 0.3, 0.5, "quad8");  // 60 % seen: random saddles and twists
  check_faces(random_quad8, 0.2, 0.5, 0.0, "quad8");
  check_faces(random_quad8, 0.1, 3.0, 0.0, "quad8");
}

TEST(QuadraticCertificate, Tri6AnswersAsTheReference) {
  check_faces(random_tri6, 0.05, 0.3, 0.85, "tri6");  // 91 % seen
  check_faces(random_tri6, 0.2, 0.5, 0.0, "tri6");
  check_faces(random_tri6, 0.1, 3.0, 0.0, "tri6");
}

TEST(QuadraticCertificate, AFlatFaceIsCertifiedEverywhereNear) {
  // Straight edges, mid-side nodes at the midpoints: f is convex for every slave within the face's size.
  const std::array<Vec3, 8> quad = {Vec3(0, 0, 0),   Vec3(1, 0, 0),   Vec3(1, 1, 0),   Vec3(0, 1, 0),
                                    Vec3(0.5, 0, 0), Vec3(1, 0.5, 0), Vec3(0.5, 1, 0), Vec3(0, 0.5, 0)};
  const QuadraticCertificate c = QuadraticCertificate::prepare(geometry::SerendipityQuad(quad));
  EXPECT_GT(c.lambda_floor, 0.0);
  EXPECT_TRUE(c.convex_for(Vec3(0.3, 0.6, 5.0)));
  const auto p = c.closest_point(Vec3(0.3, 0.6, 0.5), projection::ProjectionOptions{});
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->param[0], -0.4, 1e-14);
  EXPECT_NEAR(p->param[1], 0.2, 1e-14);
  EXPECT_EQ(p->location, Location::kFace);
}

TEST(QuadraticCertificate, RefusesWhereFIsNotConvex) {
  // A quad8 bent about the t axis: z = 0.25 (1 - s^2), x = (s + 1) / 2, so z = x (1 - x): radius of curvature
  // 1/2 at the apex (x = 1/2, z = 1/4), the centre of curvature at z = -1/4. A slave at or beyond it, on the
  // concave side, sees |S - P|^2 flat or with two minima along s: not convex.
  const std::array<Vec3, 8> quad = {Vec3(0, 0, 0),      Vec3(1, 0, 0),   Vec3(1, 1, 0),      Vec3(0, 1, 0),
                                    Vec3(0.5, 0, 0.25), Vec3(1, 0.5, 0), Vec3(0.5, 1, 0.25), Vec3(0, 0.5, 0)};
  const geometry::SerendipityQuad face(quad);
  const QuadraticCertificate c = QuadraticCertificate::prepare(face);
  ASSERT_GT(c.lambda_floor, 0.0);
  const projection::ProjectionOptions options;
  for (const Vec3& slave : {Vec3(0.5, 0.5, -0.25), Vec3(0.5, 0.5, -0.6), Vec3(0.5, 0.4, -2.0)}) {
    EXPECT_FALSE(c.convex_for(slave - quad[0])) << slave.transpose();
    EXPECT_FALSE(c.closest_point(slave, options)) << slave.transpose();
  }
  // Beyond the centre, the reference's answer is off the apex (on an edge): a Newton run from the centre
  // would have stopped at the apex, a stationary point that is not the minimum.
  for (const Vec3& slave : {Vec3(0.5, 0.5, -0.6), Vec3(0.5, 0.4, -2.0)}) {
    const auto want = projection::closest_point_on_serendipity_quad(face, slave, options);
    EXPECT_GT(std::abs(want.param[0]), 0.1) << slave.transpose();
  }
  // On the convex side, near: certified and the reference's.
  const Vec3 above(0.5, 0.5, 0.4);
  const auto p = c.closest_point(above, options);
  ASSERT_TRUE(p);
  const auto want = projection::closest_point_on_serendipity_quad(face, above, options);
  EXPECT_LE((p->point - want.point).norm(), 1e-12);
  // The same on a tri6 bent along r: its mid-side nodes of the edges along r raised.
  const std::array<Vec3, 6> tri = {Vec3(0, 0, 0),      Vec3(1, 0, 0),        Vec3(0, 1, 0),
                                   Vec3(0.5, 0, 0.25), Vec3(0.5, 0.5, 0.25), Vec3(0, 0.5, 0)};
  const QuadraticCertificate t = QuadraticCertificate::prepare(geometry::QuadraticTriangle(tri));
  ASSERT_GT(t.lambda_floor, 0.0);
  EXPECT_FALSE(t.closest_point(Vec3(0.4, 0.2, -0.6), options));
  EXPECT_FALSE(t.convex_for(Vec3(0.4, 0.2, -0.6)));
}

TEST(QuadraticCertificate, NoCertificateForAFoldedOrDegenerateFace) {
  // A mid-side node pulled past the opposite edge folds the face: P_s x P_t changes sign on it.
  const std::array<Vec3, 8> folded = {Vec3(0, 0, 0),     Vec3(1, 0, 0),   Vec3(1, 1, 0),   Vec3(0, 1, 0),
                                      Vec3(0.5, 1.2, 0), Vec3(1, 0.5, 0), Vec3(0.5, 1, 0), Vec3(0, 0.5, 0)};
  EXPECT_EQ(QuadraticCertificate::prepare(geometry::SerendipityQuad(folded)).lambda_floor, 0.0);
  const std::array<Vec3, 6> collapsed = {Vec3(0, 0, 0),   Vec3(1, 0, 0),   Vec3(2, 0, 0),
                                         Vec3(0.5, 0, 0), Vec3(1.5, 0, 0), Vec3(1, 0, 0)};
  const QuadraticCertificate c = QuadraticCertificate::prepare(geometry::QuadraticTriangle(collapsed));
  EXPECT_EQ(c.lambda_floor, 0.0);
  EXPECT_FALSE(c.closest_point(Vec3(0.5, 0.5, 0.5), projection::ProjectionOptions{}));
}

}  // namespace
}  // namespace contactnn::contact
