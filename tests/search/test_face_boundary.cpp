// SearchOptions::closest_point_on_face: every method's answer outside its segment goes to the nearest point
// of the segment's boundary, the point the surface search's reference (projection::closest_point_on_face)
// finds; answers inside are untouched, bit for bit.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/surface_of.hpp"
#include "projection/closest_point_on_face.hpp"
#include "search/local_search.hpp"
#include "search/random_queries.hpp"
#include "surface_params.hpp"

namespace contactnn::search {
namespace {

// The boundary point is exact on a straight edge and converged to rounding on a cubic one: 1e-9 in local
// units and of the segment size (about 1 here, the queries are placed at scales near 1 and beyond).
constexpr double kSamePoint = 1e-9;

struct Outputs {
  std::vector<double> param, gap;
  std::vector<Status> status;
  std::vector<Location> location;
};

Outputs run(const LocalSearch& search, const std::vector<double>& raw, std::size_t count,
            bool one_at_a_time = false) {
  Outputs r{std::vector<double>(2 * count), std::vector<double>(count), std::vector<Status>(count),
            std::vector<Location>(count)};
  const std::size_t columns = static_cast<std::size_t>(LocalSearch::raw_columns(search.surface()));
  if (one_at_a_time) {
    for (std::size_t i = 0; i < count; ++i) {
      search.run<double>(
          1, raw.data() + i * columns,
          {r.param.data() + 2 * i, r.gap.data() + i, r.status.data() + i, nullptr, r.location.data() + i}, 1);
    }
  } else {
    search.run<double>(count, raw.data(),
                       {r.param.data(), r.gap.data(), r.status.data(), nullptr, r.location.data()}, 1);
  }
  return r;
}

class FaceBoundary : public ::testing::TestWithParam<SurfaceKind> {};

TEST_P(FaceBoundary, AnswersOutsideGoToTheReferencesBoundaryPointAndInsideOnesStayAsTheyWere) {
  const SurfaceKind kind = GetParam();
  constexpr std::size_t kCount = 3000;
  const std::vector<double> raw = testing::random_queries(kind, kCount, 41);
  std::vector<std::string> methods = {"newton", "closed_form+newton:3", "newton:5"};
  if (kind == SurfaceKind::kBilinear) methods.emplace_back("four_triangles");
  for (const std::string& name : methods) {
    SCOPED_TRACE(name);
    SearchOptions on;
    on.closest_point_on_face = true;
    const LocalSearch plain(kind, Method::parse(name));
    const LocalSearch whole(kind, Method::parse(name), on);
    const Outputs before = run(plain, raw, kCount);
    const Outputs after = run(whole, raw, kCount);
    const Outputs alone = run(whole, raw, kCount, true);
    long moved = 0, compared = 0;
    for (std::size_t i = 0; i < kCount; ++i) {
      // The same bits alone and in a batch.
      ASSERT_EQ(after.param[2 * i], alone.param[2 * i]);
      ASSERT_EQ(after.gap[i], alone.gap[i]);
      ASSERT_EQ(after.location[i], alone.location[i]);
      if (before.status[i] != Status::kOutside) {
        ASSERT_EQ(after.status[i], before.status[i]);
        ASSERT_EQ(after.param[2 * i], before.param[2 * i]);
        ASSERT_EQ(after.param[2 * i + 1], before.param[2 * i + 1]);
        ASSERT_EQ(after.gap[i], before.gap[i]);
        ASSERT_EQ(after.location[i], Location::kFace);
        continue;
      }
      ++moved;
      ASSERT_EQ(after.status[i], Status::kOk);
      ASSERT_NE(after.location[i], Location::kFace);
      const geometry::Configuration c = testing::configuration_of(raw.data(), kind, i);
      const projection::FaceClosestPoint reference = geometry::with_surface(
          c, kind, [&](const auto& surface) { return projection::closest_point_on_face(surface, c.slave); });
      ASSERT_EQ(reference.status, Status::kOk);
      if (reference.location == Location::kFace) continue;  // the method's 'outside' missed an interior point
      ++compared;
      const double size = geometry::max_node_distance(c.nodes);
      EXPECT_NEAR(after.param[2 * i], reference.param[0], kSamePoint) << "query " << i;
      EXPECT_NEAR(after.param[2 * i + 1], reference.param[1], kSamePoint) << "query " << i;
      EXPECT_NEAR(std::abs(after.gap[i]), reference.distance, kSamePoint * size) << "query " << i;
      EXPECT_EQ(after.gap[i] < 0.0, reference.normal.dot(c.slave - reference.point) < 0.0) << "query " << i;
      EXPECT_EQ(after.location[i], reference.location) << "query " << i;
    }
    // The sample has answers outside (the paper's slaves range over (-2, 2)^2 about a unit segment). Plain
    // Newton's 'outside' is the far root of a warped quad for about one in seven of them, where the reference
    // finds an interior point: a limit of the method, not of the boundary step.
    EXPECT_GT(moved, 50);
    EXPECT_GT(compared, moved / 2);
  }
}

INSTANTIATE_TEST_SUITE_P(Surfaces, FaceBoundary, testing::kBothSurfaces, testing::surface_name);

}  // namespace
}  // namespace contactnn::search
