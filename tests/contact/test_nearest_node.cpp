// Tests for lib/contact/nearest_node.*: the k-d tree answers exactly what the brute-force scan answers.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "contact/nearest_node.hpp"

namespace contactnn::contact {
namespace {

TEST(NearestPointTree, AgreesWithBruteForceOnRandomCloudsAndQueries) {
  std::mt19937_64 rng(53);
  for (int cloud = 0; cloud < 20; ++cloud) {
    std::uniform_real_distribution<double> x(-10, 10);
    std::uniform_int_distribution<int> size(1, 3000);
    std::vector<Vec3> points(static_cast<std::size_t>(size(rng)));
    for (auto& p : points) p = Vec3(x(rng), x(rng), 0.1 * x(rng));  // flat-ish, as surface nodes are
    const NearestPointTree tree(points);
    for (int q = 0; q < 500; ++q) {
      const Vec3 query(1.2 * x(rng), 1.2 * x(rng), x(rng));
      ASSERT_EQ(tree.nearest(query), nearest_point_brute_force(points, query)) << cloud << "/" << q;
    }
    // Queries on the points themselves and next to them.
    for (std::size_t i = 0; i < points.size(); i += 7) {
      ASSERT_EQ(tree.nearest(points[i]), static_cast<int>(i));
      const Vec3 near = points[i] + Vec3(1e-9, -1e-9, 1e-9);
      ASSERT_EQ(tree.nearest(near), nearest_point_brute_force(points, near));
    }
  }
}

TEST(NearestPointTree, ExactTiesGoToTheLowestIndexInBoth) {
  // An integer grid (exact arithmetic): a query at the centre of a cell is equidistant from 4 points, at
  // an edge midpoint from 2; listed in a shuffled order so that "lowest index" is not "first in space".
  std::vector<Vec3> points;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 9; ++j) points.emplace_back(i, j, 0);
  }
  std::mt19937_64 rng(59);
  std::shuffle(points.begin(), points.end(), rng);
  const NearestPointTree tree(points);
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      for (const Vec3& query :
           {Vec3(i + 0.5, j + 0.5, 0.25), Vec3(i + 0.5, j, -1.0), Vec3(i, j + 0.5, 0.0)}) {
        int lowest = std::numeric_limits<int>::max();
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < points.size(); ++k)
          best = std::min(best, squared_distance(points[k], query));
        for (std::size_t k = 0; k < points.size(); ++k) {
          if (squared_distance(points[k], query) == best) lowest = std::min(lowest, static_cast<int>(k));
        }
        EXPECT_EQ(nearest_point_brute_force(points, query), lowest);
        EXPECT_EQ(tree.nearest(query), lowest);
      }
    }
  }
}

TEST(NearestPointTree, DuplicatePointsAndDegenerateInputs) {
  const std::vector<Vec3> points = {Vec3(1, 1, 1), Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(0, 0, 0)};
  const NearestPointTree tree(points);
  EXPECT_EQ(tree.nearest(Vec3(0, 0, 0)), 1);  // distance 0 twice: the lower index
  EXPECT_EQ(tree.nearest(Vec3(0.9, 1, 1)), 0);
  EXPECT_EQ(tree.nearest(Vec3(std::nan(""), 0, 0)), -1);
  const NearestPointTree empty(std::span<const Vec3>{});
  EXPECT_EQ(empty.nearest(Vec3::Zero()), -1);
  EXPECT_EQ(nearest_point_brute_force({}, Vec3::Zero()), -1);
}

}  // namespace
}  // namespace contactnn::contact
