// contact::FaceLocator in the surface search (SearchOptions::interior, issue 38: the plan in the loop): a
// method exact enough gives the exact search's answers, a pair the method refuses or puts outside its face
// takes the exact closest point (no slave point is lost), and the judge of replay --plan computes the error
// of a case worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "contact/narrow_phase.hpp"
#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "history/replay.hpp"
#include "mesh/grid_surface.hpp"
#include "mesh/surface_mesh.hpp"

namespace contactnn::contact {
namespace {

/// The grid (searched_grid_surface: element ids and faces for the tie rule).
mesh::SurfaceMesh surface_of(int nx, int ny, const std::function<Vec3(double, double)>& point) {
  return testing::searched_grid_surface(nx, ny, point);
}

/// A warped sheet: every face a curved bilinear facet (no face is a flat parallelogram).
Vec3 wavy(double i, double j) {
  return Vec3(i, j, 0.3 * std::sin(1.3 * i) * std::cos(0.9 * j) + 0.05 * i * j);
}

std::vector<NodeSegmentPair> search(const mesh::SurfaceMesh& m, const std::vector<Vec3>& slaves,
                                    SearchOptions options) {
  std::vector<long> ids(slaves.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<long>(i) + 1;
  const std::vector<Vec3> normals = mesh::node_normals(m);
  return surface_search(m, normals, ids, slaves, options);
}

std::vector<Vec3> random_slaves(int n, unsigned seed, double lo, double hi) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> xy(lo, hi), z(-0.8, 0.8);
  std::vector<Vec3> slaves;
  for (int i = 0; i < n; ++i) slaves.emplace_back(xy(rng), xy(rng), z(rng));
  return slaves;
}

TEST(NarrowPhase, NewtonToConvergenceGivesTheExactSearchsAnswersOnBilinearAndGregoryFaces) {
  const mesh::SurfaceMesh m = surface_of(6, 6, wavy);
  const std::vector<Vec3> slaves = random_slaves(2000, 7, -0.5, 6.5);
  const FaceLocator newton("newton");
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    SearchOptions exact_options;
    exact_options.surface = kind;
    SearchOptions plan_options = exact_options;
    plan_options.interior = &newton;
    const auto exact = search(m, slaves, exact_options);
    const auto plan = search(m, slaves, plan_options);
    long by_method = 0;
    for (std::size_t i = 0; i < slaves.size(); ++i) {
      ASSERT_EQ(plan[i].status, exact[i].status) << "slave " << i;
      if (exact[i].status != PairStatus::kFound) continue;
      by_method += plan[i].by_method ? 1 : 0;
      EXPECT_FALSE(exact[i].by_method);
      EXPECT_EQ(plan[i].segment, exact[i].segment) << "slave " << i;
      EXPECT_EQ(plan[i].location, exact[i].location) << "slave " << i;
      // Faces of size about 1.4: Newton's step tolerance leaves the point within 1e-9 of it.
      EXPECT_LE((plan[i].point - exact[i].point).norm(), 1e-9) << "slave " << i;
      EXPECT_NEAR(plan[i].label.gap, exact[i].label.gap, 1e-9) << "slave " << i;
    }
    // Most slave points lie over a face's interior: the method answered them.
    EXPECT_GT(by_method, 1000) << to_string(kind);
  }
}

TEST(NarrowPhase, PairsOutsideTheFaceFallBackToTheExactPointAndNoSlavePointIsLost) {
  // One flat square face [0, 1]^2: newton:1 is exact inside it (the map is affine) and puts every slave point
  // beyond an edge outside the face, where the exact closest point lies on the edge or at a vertex.
  const mesh::SurfaceMesh m = surface_of(1, 1, [](double i, double j) { return Vec3(i, j, 0.0); });
  const FaceLocator newton1("newton:1");
  SearchOptions plan_options;
  plan_options.interior = &newton1;
  std::vector<Vec3> slaves;
  for (int a = -4; a <= 14; ++a) {
    for (int b = -4; b <= 14; ++b) slaves.emplace_back(0.1 * a + 0.013, 0.1 * b + 0.007, 0.3);
  }
  const auto exact = search(m, slaves, {});
  const auto plan = search(m, slaves, plan_options);
  long inside = 0, outside = 0;
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    ASSERT_EQ(exact[i].status, PairStatus::kFound) << "slave " << i;
    ASSERT_EQ(plan[i].status, PairStatus::kFound) << "slave " << i;
    const bool over =
        slaves[i].x() > 0.0 && slaves[i].x() < 1.0 && slaves[i].y() > 0.0 && slaves[i].y() < 1.0;
    EXPECT_EQ(plan[i].by_method, over) << "slave " << i;
    EXPECT_EQ(plan[i].location, exact[i].location) << "slave " << i;
    if (over) {
      ++inside;
      EXPECT_LE((plan[i].point - exact[i].point).norm(), 1e-14) << "slave " << i;
    } else {
      ++outside;  // the exact answer itself, bit for bit
      EXPECT_EQ(plan[i].point, exact[i].point) << "slave " << i;
      EXPECT_EQ(plan[i].label.gap, exact[i].label.gap) << "slave " << i;
      EXPECT_NE(exact[i].location, Location::kFace) << "slave " << i;
    }
  }
  EXPECT_GT(inside, 50);
  EXPECT_GT(outside, 100);
}

TEST(NarrowPhase, AnInexactMethodLosesNoSlavePointOnAWarpedSheet) {
  const mesh::SurfaceMesh m = surface_of(6, 6, wavy);
  const std::vector<Vec3> slaves = random_slaves(2000, 11, -0.5, 6.5);
  const FaceLocator closed("closed_form");
  SearchOptions plan_options;
  plan_options.interior = &closed;
  const auto exact = search(m, slaves, {});
  const auto plan = search(m, slaves, plan_options);
  long by_method = 0, fallen_back = 0;
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    if (exact[i].status != PairStatus::kFound) continue;
    // (Slave 903 is 1.593 from the surface, the capture distance 1.603: the method's point on that face lies
    // beyond it, and the face's exact point is taken.)
    ASSERT_EQ(plan[i].status, PairStatus::kFound) << "slave " << i;
    (plan[i].by_method ? by_method : fallen_back) += 1;
    // A method's point is a point of the surface: never nearer than the exact closest point.
    EXPECT_GE(std::abs(plan[i].label.gap), std::abs(exact[i].label.gap) - 1e-12) << "slave " << i;
  }
  EXPECT_GT(by_method, 0);
  EXPECT_GT(fallen_back, 0);
}

TEST(NarrowPhase, MethodsTheSearchCannotRunAreRefusedAtConstruction) {
  EXPECT_THROW(FaceLocator("start+newton:2"), InvalidArgument);
  EXPECT_THROW(FaceLocator("network+newton:1"), InvalidArgument);
  EXPECT_THROW(FaceLocator("newton:x"), InvalidArgument);
  EXPECT_EQ(FaceLocator("closed_form+newton:0").name(), "closed_form");
}

/// A found pair on face `face` at local coordinates `param` and point `point`.
Contact found(int face, std::array<double, 2> param, const Vec3& point, bool by_method,
              Location location = Location::kFace) {
  Contact p;
  p.status = PairStatus::kFound;
  p.face = face;
  p.param = param;
  p.point = point;
  p.by_method = by_method;
  p.location = location;
  return p;
}

TEST(NarrowPhase, TheJudgeOfReplayPlanCountsAndMeasuresACaseWorkedByHand) {
  // Two unit squares side by side (face size sqrt 2), bilinear: a domain width is 2.
  const mesh::SurfaceMesh m = surface_of(2, 1, [](double i, double j) { return Vec3(i, j, 0.0); });
  const double size = std::sqrt(2.0);
  std::vector<Contact> exact, plan;
  // 0: the method's point off by (0.03, -0.01) in (xi, eta), i.e. (0.015, -0.005) in length.
  exact.push_back(found(0, {0.1, 0.2}, Vec3(0.55, 0.6, 0), false));
  plan.push_back(found(0, {0.13, 0.19}, Vec3(0.565, 0.595, 0), true));
  // 1: refused (the plan found nothing).
  exact.push_back(found(0, {0.0, 0.0}, Vec3(0.5, 0.5, 0), false));
  plan.push_back(Contact{});
  // 2: the method's point on the other face: one domain width; its point 0.2 away.
  exact.push_back(found(0, {0.9, 0.0}, Vec3(0.95, 0.5, 0), false));
  plan.push_back(found(1, {-0.7, 0.0}, Vec3(1.15, 0.5, 0), true));
  // 3: inside a face by the exact search, the exact point taken again: a fallback, no error.
  exact.push_back(found(1, {0.5, 0.5}, Vec3(1.75, 0.75, 0), false));
  plan.push_back(found(1, {0.5, 0.5}, Vec3(1.75, 0.75, 0), false));
  // 4: on an edge: the exact point, not a fallback (the method is for interiors).
  exact.push_back(found(1, {1.0, 0.5}, Vec3(2.0, 0.75, 0), false, Location::kEdge));
  plan.push_back(found(1, {1.0, 0.5}, Vec3(2.0, 0.75, 0), false, Location::kEdge));
  const history::PlanRow row = history::judge_plan(m, SurfaceKind::kBilinear, exact, plan);
  EXPECT_EQ(row.by_method, 2);
  EXPECT_EQ(row.refused, 1);
  EXPECT_EQ(row.other_face, 1);
  EXPECT_EQ(row.fallbacks, 1);
  EXPECT_NEAR(row.mean_error, (0.03 + 2.0) / 2.0, 1e-15);
  EXPECT_DOUBLE_EQ(row.max_error, 2.0);
  const double d0 = std::hypot(0.015, 0.005) / size, d2 = 0.2 / size;
  EXPECT_NEAR(row.mean_distance, (d0 + d2) / 4.0, 1e-15);
  EXPECT_NEAR(row.max_distance, d2, 1e-15);
  plan.pop_back();
  EXPECT_THROW((void)history::judge_plan(m, SurfaceKind::kBilinear, exact, plan), InvalidArgument);
}

}  // namespace
}  // namespace contactnn::contact
