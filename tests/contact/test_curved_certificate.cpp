// contact::CurvedCertificate: where it answers for a quad8, tri6 or Gregory face, the answer is the
// reference's (projection::closest_point_on_serendipity_quad / closest_point_on_quadratic_triangle /
// closest_point_on_face, Newton from sampled starts); it answers for most slave nodes near mildly curved
// faces, and refuses where f is not convex (a slave beyond the centre of curvature of a strongly curved face)
// or the face is folded. The Gregory bounds are checked against the patch's own derivatives.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <deque>
#include <random>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <variant>
#include <vector>

#include "contact/curved_certificate.hpp"
#include "projection/closest_point_on_face.hpp"
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

/// A quad4 with node normals, as the surface search holds it: its Gregory certificate and reference are built
/// from the world nodes and the normals as given.
struct GregoryFace {
  std::array<Vec3, 4> nodes;
  std::array<Vec3, 4> normals;
  geometry::GregoryPatch patch;  ///< on the world nodes (for the test's sampling)

  GregoryFace(const std::array<Vec3, 4>& x, const std::array<Vec3, 4>& n)
      : nodes(x), normals(n), patch(x, n) {}
  [[nodiscard]] geometry::SurfacePoint evaluate(double u, double v) const { return patch.evaluate(u, v); }
  [[nodiscard]] double characteristic_length() const { return patch.characteristic_length(); }
};

/// A random Gregory face as a mesh of a smooth surface gives it: the unit square's corners moved in its plane
/// by up to `distortion` and placed on a sphere of radius 1 / (2 bulge) below them (a dome), each node normal
/// the sphere's tilted by up to bulge / 4 (as averaged node normals differ from the surface's), placed at
/// `offset`.
GregoryFace random_gregory(std::mt19937_64& rng, double distortion, double bulge, const Vec3& offset) {
  std::uniform_real_distribution<double> u(-distortion, distortion), tilt(-0.25 * bulge, 0.25 * bulge);
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  const double radius = 0.5 / bulge;
  const Vec3 centre(0.5, 0.5, -radius);
  std::array<Vec3, 4> x, n;
  for (std::size_t k = 0; k < 4; ++k) {
    Vec3 p = square[k] + Vec3(u(rng), u(rng), 0.0);
    p.z() = centre.z() + std::sqrt(radius * radius - (p - centre).head<2>().squaredNorm());
    n[k] = ((p - centre).normalized() + Vec3(tilt(rng), tilt(rng), 0.0)).normalized();
    x[k] = p + offset;
  }
  return GregoryFace(x, n);
}

CurvedCertificate prepare(const geometry::SerendipityQuad& face) { return CurvedCertificate::prepare(face); }
CurvedCertificate prepare(const geometry::QuadraticTriangle& face) {
  return CurvedCertificate::prepare(face);
}
/// Room for the Gregory patches the test's certificates point to (kept to the end of the test program).
void* patch_room() {
  struct alignas(geometry::GregoryPatch) Room {
    std::byte bytes[sizeof(geometry::GregoryPatch)];
  };
  static std::deque<Room> rooms;
  return &rooms.emplace_back();
}

CurvedCertificate prepare_gregory(const std::array<Vec3, 4>& nodes, const std::array<Vec3, 4>& normals) {
  CurvedCertificate c;
  CurvedCertificate::prepare_gregory(c, patch_room(), nodes, normals);
  return c;
}
CurvedCertificate prepare(const GregoryFace& face) { return prepare_gregory(face.nodes, face.normals); }

/// The reference as the surface search calls it for a Gregory face: the patch on the nodes relative to the
/// first, with the normals as given.
projection::FaceClosestPoint reference(const GregoryFace& face, const Vec3& slave,
                                       const projection::ProjectionOptions& options) {
  std::array<Vec3, 4> x = face.nodes;
  for (Vec3& node : x) node -= face.nodes[0];
  projection::FaceClosestPoint p = projection::closest_point_on_face(geometry::GregoryPatch(x, face.normals),
                                                                     slave - face.nodes[0], options);
  if (p.status == Status::kOk) p.point += face.nodes[0];
  return p;
}

struct Tally {
  int answered = 0;
  int total = 0;
  int mismatched = 0;
};

/// An interior answer `fast` of `c` is the reference's report at its parameters, bit for bit (a run that ends
/// on its residual reports from its own last evaluation, and a fresh run's first from the one kept at the
/// centre: they must be the evaluations at those parameters).
void expect_report_at_param(const CurvedCertificate& c, const Vec3& slave,
                            const projection::FaceClosestPoint& fast) {
  if (fast.location != Location::kFace) return;
  const Vec3 relative = slave - c.origin;
  projection::FaceClosestPoint report;
  if (const auto* patch = std::get_if<const geometry::GregoryPatch*>(&c.face)) {
    report = projection::nearest_of_interior_and_edges(**patch, relative, &fast.param, 0, nullptr, true);
  } else if (const auto* quad8 = std::get_if<geometry::SerendipityQuad>(&c.face)) {
    report = projection::quadratic_face_point(*quad8, relative, fast.param, 0);
  } else if (const auto* tri6 = std::get_if<geometry::QuadraticTriangle>(&c.face)) {
    report = projection::quadratic_face_point(*tri6, relative, fast.param, 0);
  } else {
    ADD_FAILURE() << "an answer without a face";
    return;
  }
  EXPECT_EQ(fast.point, Vec3(report.point + c.origin)) << "slave " << slave.transpose();
  EXPECT_EQ(fast.normal, report.normal) << "slave " << slave.transpose();
  EXPECT_EQ(fast.distance, report.distance) << "slave " << slave.transpose();
}

TEST(CurvedCertificate, KeepsTheFaceEvaluatedAtTheCentreOfItsDomain) {
  std::mt19937_64 rng(99);
  const geometry::SerendipityQuad quad8 = random_quad8(rng, 0.1, 0.1, Vec3(2.0, 1.0, -3.0));
  const geometry::QuadraticTriangle tri6 = random_tri6(rng, 0.1, 0.1, Vec3(2.0, 1.0, -3.0));
  const GregoryFace gregory = random_gregory(rng, 0.1, 0.1, Vec3(2.0, 1.0, -3.0));
  const auto same = [](const geometry::SurfacePoint& a, const geometry::SurfacePoint& b) {
    return a.position == b.position && a.d_s == b.d_s && a.d_t == b.d_t && a.d_ss == b.d_ss &&
           a.d_st == b.d_st && a.d_tt == b.d_tt;
  };
  const CurvedCertificate q = prepare(quad8), t = prepare(tri6), g = prepare(gregory);
  ASSERT_GT(q.lambda_floor, 0.0);
  ASSERT_GT(t.lambda_floor, 0.0);
  ASSERT_GT(g.lambda_floor, 0.0);
  EXPECT_TRUE(same(q.at_centre, std::get<geometry::SerendipityQuad>(q.face).evaluate(0.0, 0.0)));
  EXPECT_TRUE(
      same(t.at_centre, std::get<geometry::QuadraticTriangle>(t.face).evaluate(1.0 / 3.0, 1.0 / 3.0)));
  EXPECT_TRUE(same(g.at_centre, std::get<const geometry::GregoryPatch*>(g.face)->evaluate(0.5, 0.5)));
}

/// Random slave nodes around the face (parameters a little beyond it, heights up to `height`), from the
/// centre and from a warm start: each certified answer against the reference.
template <class Face>
Tally check_face(const Face& face, std::mt19937_64& rng, int slaves, double height) {
  const CurvedCertificate certificate = prepare(face);
  const projection::ProjectionOptions options;
  const bool triangle = certificate.triangle;
  constexpr bool gregory = std::is_same_v<Face, GregoryFace>;
  // The domain's bounds, and the sampled parameters a little beyond them.
  const double lo = triangle || gregory ? 0.0 : -1.0, reach = gregory ? 0.15 : 0.3;
  std::uniform_real_distribution<double> u(lo - reach, 1.0 + reach), w(-height, height);
  const double size = face.characteristic_length();
  Tally tally;
  for (int i = 0; i < slaves; ++i) {
    const double a = u(rng), b = u(rng);
    const geometry::SurfacePoint sp = face.evaluate(a, b);
    const Vec3 n = sp.d_s.cross(sp.d_t).normalized();
    const Vec3 slave = sp.position + w(rng) * n;
    const std::array<double, 2> warm = {std::clamp(a, lo, 1.0), std::clamp(b, lo, 1.0)};
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
      expect_report_at_param(certificate, slave, *fast);
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

TEST(CurvedCertificate, Quad8AnswersAsTheReference) {
  // Mildly curved faces, slaves near: most answered. Strongly curved, and far: checked where answered.
  check_faces(random_quad8, 0.05, 0.3, 0.5, "quad8");  // 60 % seen: random saddles and twists
  check_faces(random_quad8, 0.2, 0.5, 0.0, "quad8");
  check_faces(random_quad8, 0.1, 3.0, 0.0, "quad8");
}

TEST(CurvedCertificate, Tri6AnswersAsTheReference) {
  check_faces(random_tri6, 0.05, 0.3, 0.85, "tri6");  // 91 % seen
  check_faces(random_tri6, 0.2, 0.5, 0.0, "tri6");
  check_faces(random_tri6, 0.1, 3.0, 0.0, "tri6");
}

TEST(CurvedCertificate, GregoryAnswersAsTheReference) {
  check_faces(random_gregory, 0.05, 0.3, 0.85, "gregory");  // 93 % seen
  check_faces(random_gregory, 0.3, 0.5, 0.0, "gregory");
  check_faces(random_gregory, 0.1, 3.0, 0.0, "gregory");
}

TEST(CurvedCertificate, EachEdgesChordBoundsItsDistanceFromBelow) {
  // chord_bound(e, S) is at most S's distance to edge e, sampled at 4001 points of the face's own edge (the
  // reference's positions at the edge's parameters), for faces with edges bent by up to half their length;
  // and beside a straight edge it is that distance.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 2.0);
  int checked = 0;
  const auto check = [&](const CurvedCertificate& c, const auto& face, int edges, bool triangle,
                         bool gregory) {
    ASSERT_GT(c.lambda_floor, 0.0);
    for (int s = 0; s < 50; ++s) {
      const Vec3 slave(u(rng), u(rng), 0.5 * u(rng));
      const Vec3 relative = slave - c.origin;
      for (int e = 0; e < edges; ++e) {
        double nearest = std::numeric_limits<double>::infinity();
        for (int k = 0; k <= 4000; ++k) {
          const double t = k / 4000.0;
          const std::array<double, 2> q =
              triangle  ? projection::triangle_edge_param(e, t)
              : gregory ? projection::domain_edge_param(e, t, param_domain(SurfaceKind::kGregory))
                        : projection::quad_edge_param(e, t);
          nearest = std::min(nearest, (relative - face.position(q[0], q[1])).norm());
        }
        EXPECT_LE(c.chord_bound(static_cast<std::size_t>(e), relative), nearest + 1e-12) << e;
        ++checked;
      }
    }
  };
  for (int f = 0; f < 20; ++f) {
    const geometry::QuadraticTriangle tri6 = random_tri6(rng, 0.1, 0.5, Vec3::Zero());
    const CurvedCertificate c6 = prepare(tri6);
    if (c6.lambda_floor > 0.0) check(c6, *std::get_if<geometry::QuadraticTriangle>(&c6.face), 3, true, false);
    const geometry::SerendipityQuad quad8 = random_quad8(rng, 0.1, 0.5, Vec3::Zero());
    const CurvedCertificate c8 = prepare(quad8);
    if (c8.lambda_floor > 0.0) check(c8, *std::get_if<geometry::SerendipityQuad>(&c8.face), 4, false, false);
    const CurvedCertificate cg = prepare(random_gregory(rng, 0.1, 0.5, Vec3::Zero()));
    if (cg.lambda_floor > 0.0)
      check(cg, **std::get_if<const geometry::GregoryPatch*>(&cg.face), 4, false, true);
  }
  EXPECT_GT(checked, 3000);
  // A flat tri6 with straight edges: the bound is the distance to the edge itself, to rounding.
  const geometry::QuadraticTriangle flat(
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.5, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0, 0.5, 0)});
  const CurvedCertificate c = prepare(flat);
  EXPECT_NEAR(c.chord_bound(0, Vec3(0.3, -0.4, 0.3)), 0.5, 1e-9);
  EXPECT_NEAR(c.chord_bound(2, Vec3(-0.2, 2.0, 0.0)), std::sqrt(0.04 + 1.0), 1e-9);
}

/// g(u, v) = B_1(u) B_1(v) u / (u + v) (curved_certificate.hpp), written out here.
double g(double u, double v) {
  return 9.0 * u * (1.0 - u) * (1.0 - u) * v * (1.0 - v) * (1.0 - v) * u / (u + v);
}

/// The sum over the four reflections of g of |g_uu|, |g_uv|, |g_vv| at (u, v), by central differences.
std::array<double, 3> reflected_second_derivatives(double u, double v) {
  const double h = 1e-4;
  std::array<double, 3> sum = {0.0, 0.0, 0.0};
  for (const bool flip_u : {false, true}) {
    for (const bool flip_v : {false, true}) {
      const double a = flip_u ? 1.0 - u : u, b = flip_v ? 1.0 - v : v;
      sum[0] += std::abs((g(a + h, b) - 2.0 * g(a, b) + g(a - h, b)) / (h * h));
      sum[1] +=
          std::abs((g(a + h, b + h) - g(a + h, b - h) - g(a - h, b + h) + g(a - h, b - h)) / (4.0 * h * h));
      sum[2] += std::abs((g(a, b + h) - 2.0 * g(a, b) + g(a, b - h)) / (h * h));
    }
  }
  return sum;
}

TEST(CurvedCertificate, GregoryBoundsHoldAndAreTight) {
  // The second derivatives of g's reflections by central differences on a grid (its edges included) and on
  // circles about the corners, where they come nearest their suprema: within the bounds, and within 2% of
  // them (a looser bound would refuse faces for nothing).
  std::array<double, 3> most = {0.0, 0.0, 0.0};
  const auto sample = [&](double u, double v) {
    const std::array<double, 3> at = reflected_second_derivatives(u, v);
    for (std::size_t k = 0; k < 3; ++k) most[k] = std::max(most[k], at[k]);
  };
  for (int i = 0; i <= 400; ++i) {
    for (int j = 0; j <= 400; ++j) {
      if ((i <= 1 || i >= 399) && (j <= 1 || j >= 399)) continue;  // the stencil would cross a corner
      sample(i / 400.0, j / 400.0);
    }
  }
  for (const double radius : {0.05, 0.01, 0.002}) {
    for (int k = 0; k <= 400; ++k) {
      const double angle = 1.5707963 * k / 400.0;
      sample(2e-4 + radius * std::cos(angle), 2e-4 + radius * std::sin(angle));
    }
  }
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_LE(most[k], kGregoryBound[k]) << k;
    EXPECT_GE(most[k], 0.97 * kGregoryBound[k]) << k;
  }
  // On real patches: the certificate's bounds against the patch's own derivatives on a grid.
  std::mt19937_64 rng(99);
  for (int face = 0; face < 40; ++face) {
    const GregoryFace f = random_gregory(rng, 0.1, face % 2 == 0 ? 0.05 : 0.15, Vec3(3.0, -1.0, 2.0));
    const CurvedCertificate c = prepare(f);
    ASSERT_GT(c.lambda_floor, 0.0) << face;
    for (int i = 0; i <= 20; ++i) {
      for (int j = 0; j <= 20; ++j) {
        const geometry::SurfacePoint sp = f.evaluate(i / 20.0, j / 20.0);
        const Vec3& n = c.gregory.normal;
        const std::array<Vec3, 3> second = {sp.d_ss, sp.d_st, sp.d_tt};
        for (std::size_t k = 0; k < 3; ++k) {
          EXPECT_LE(std::abs(second[k].dot(n)), c.gregory.second[2 * k]) << k;
          EXPECT_LE((second[k] - second[k].dot(n) * n).norm(), c.gregory.second[2 * k + 1]) << k;
        }
        const double gram = sp.d_s.squaredNorm() + sp.d_t.squaredNorm();
        const double det = sp.d_s.cross(sp.d_t).squaredNorm();
        const double lambda = 0.5 * (gram - std::sqrt(std::max(gram * gram - 4.0 * det, 0.0)));
        EXPECT_LE(c.lambda_floor, lambda * (1.0 + 1e-9));
        const Vec3 d = sp.position - f.nodes[0] - c.gregory.centre;
        EXPECT_GE(d.dot(n), c.gregory.below - 1e-12);
        EXPECT_LE(d.dot(n), c.gregory.above + 1e-12);
        EXPECT_LE((d - d.dot(n) * n).norm(), c.gregory.across * (1.0 + 1e-12));
      }
    }
  }
}

TEST(CurvedCertificate, GregoryRefusesBeyondTheCentreOfCurvature) {
  // A dome: the unit square's corners on a sphere of radius 4 about (0.5, 0.5, -4), the sphere's normals. A
  // slave beyond the centre of curvature (on the concave side) is refused; one above is answered as the
  // reference.
  const Vec3 centre(0.5, 0.5, -4.0);
  std::array<Vec3, 4> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  std::array<Vec3, 4> n;
  for (std::size_t k = 0; k < 4; ++k) {
    x[k].z() = centre.z() + std::sqrt(16.0 - (x[k] - centre).head<2>().squaredNorm());
    n[k] = (x[k] - centre).normalized();
  }
  const GregoryFace face(x, n);
  const CurvedCertificate c = prepare(face);
  ASSERT_GT(c.lambda_floor, 0.0);
  const projection::ProjectionOptions options;
  EXPECT_FALSE(c.closest_point(Vec3(0.5, 0.4, -6.0), options));
  EXPECT_FALSE(c.convex_for(Vec3(0.5, 0.4, -6.0) - x[0]));
  const Vec3 above(0.6, 0.3, 0.2);
  const auto p = c.closest_point(above, options);
  ASSERT_TRUE(p);
  EXPECT_LE((p->point - reference(face, above, options).point).norm(), 1e-12);
  // A degenerate face (two corners together) has no certificate.
  const std::array<Vec3, 4> collapsed = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_EQ(prepare_gregory(collapsed, n).lambda_floor, 0.0);
}

TEST(CurvedCertificate, AFlatFaceIsCertifiedEverywhereNear) {
  // Straight edges, mid-side nodes at the midpoints: f is convex for every slave within the face's size.
  const std::array<Vec3, 8> quad = {Vec3(0, 0, 0),   Vec3(1, 0, 0),   Vec3(1, 1, 0),   Vec3(0, 1, 0),
                                    Vec3(0.5, 0, 0), Vec3(1, 0.5, 0), Vec3(0.5, 1, 0), Vec3(0, 0.5, 0)};
  const CurvedCertificate c = CurvedCertificate::prepare(geometry::SerendipityQuad(quad));
  EXPECT_GT(c.lambda_floor, 0.0);
  EXPECT_TRUE(c.convex_for(Vec3(0.3, 0.6, 5.0)));
  const auto p = c.closest_point(Vec3(0.3, 0.6, 0.5), projection::ProjectionOptions{});
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->param[0], -0.4, 1e-14);
  EXPECT_NEAR(p->param[1], 0.2, 1e-14);
  EXPECT_EQ(p->location, Location::kFace);
}

TEST(CurvedCertificate, RefusesWhereFIsNotConvex) {
  // A quad8 bent about the t axis: z = 0.25 (1 - s^2), x = (s + 1) / 2, so z = x (1 - x): radius of curvature
  // 1/2 at the apex (x = 1/2, z = 1/4), the centre of curvature at z = -1/4. A slave at or beyond it, on the
  // concave side, sees |S - P|^2 flat or with two minima along s: not convex.
  const std::array<Vec3, 8> quad = {Vec3(0, 0, 0),      Vec3(1, 0, 0),   Vec3(1, 1, 0),      Vec3(0, 1, 0),
                                    Vec3(0.5, 0, 0.25), Vec3(1, 0.5, 0), Vec3(0.5, 1, 0.25), Vec3(0, 0.5, 0)};
  const geometry::SerendipityQuad face(quad);
  const CurvedCertificate c = CurvedCertificate::prepare(face);
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
  const CurvedCertificate t = CurvedCertificate::prepare(geometry::QuadraticTriangle(tri));
  ASSERT_GT(t.lambda_floor, 0.0);
  EXPECT_FALSE(t.closest_point(Vec3(0.4, 0.2, -0.6), options));
  EXPECT_FALSE(t.convex_for(Vec3(0.4, 0.2, -0.6)));
}

TEST(CurvedCertificate, NoCertificateForAFoldedOrDegenerateFace) {
  // A mid-side node pulled past the opposite edge folds the face: P_s x P_t changes sign on it.
  const std::array<Vec3, 8> folded = {Vec3(0, 0, 0),     Vec3(1, 0, 0),   Vec3(1, 1, 0),   Vec3(0, 1, 0),
                                      Vec3(0.5, 1.2, 0), Vec3(1, 0.5, 0), Vec3(0.5, 1, 0), Vec3(0, 0.5, 0)};
  EXPECT_EQ(CurvedCertificate::prepare(geometry::SerendipityQuad(folded)).lambda_floor, 0.0);
  const std::array<Vec3, 6> collapsed = {Vec3(0, 0, 0),   Vec3(1, 0, 0),   Vec3(2, 0, 0),
                                         Vec3(0.5, 0, 0), Vec3(1.5, 0, 0), Vec3(1, 0, 0)};
  const CurvedCertificate c = CurvedCertificate::prepare(geometry::QuadraticTriangle(collapsed));
  EXPECT_EQ(c.lambda_floor, 0.0);
  EXPECT_FALSE(c.closest_point(Vec3(0.5, 0.5, 0.5), projection::ProjectionOptions{}));
}

TEST(CurvedCertificates, EachFaceIsPreparedOnceWhateverTheThreadsAndAgainAfterAFailure) {
  // Four threads ask for every face of 64 in different orders: each face prepared once, every thread given
  // it.
  constexpr std::size_t kFaces = 64;
  CurvedCertificates table(kFaces);
  std::array<std::atomic<int>, kFaces> prepared{};
  std::vector<std::thread> threads;
  std::atomic<int> wrong = 0;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t k = 0; k < kFaces; ++k) {
        const std::size_t f = (k * (2 * static_cast<std::size_t>(t) + 1)) % kFaces;
        const CurvedCertificate& c = table.get(f, [&](CurvedCertificate& out, void*) {
          prepared[f].fetch_add(1);
          out.lambda_floor = static_cast<double>(f) + 1.0;
        });
        if (c.lambda_floor != static_cast<double>(f) + 1.0) wrong.fetch_add(1);
      }
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(wrong.load(), 0);
  for (std::size_t f = 0; f < kFaces; ++f) EXPECT_EQ(prepared[f].load(), 1) << f;
  // A preparation that throws leaves the face to be prepared by the next caller (no caller waits forever).
  table.reset(kFaces);
  EXPECT_THROW((void)table.get(5, [](CurvedCertificate&, void*) { throw std::runtime_error("no"); }),
               std::runtime_error);
  EXPECT_EQ(table.get(5, [](CurvedCertificate& out, void*) { out.lambda_floor = 2.0; }).lambda_floor, 2.0);
  // keep() holds what was prepared, forget() one face: only it is prepared again.
  table.keep(kFaces);
  table.forget(7);
  int again = 0;
  (void)table.get(5, [&](CurvedCertificate&, void*) { ++again; });
  (void)table.get(7, [&](CurvedCertificate&, void*) { ++again; });
  EXPECT_EQ(again, 1);
}

}  // namespace
}  // namespace contactnn::contact
