// contact::FaceGrid: every face whose box comes within the reach of a point is reported, each once, against a
// brute-force distance to every box; the kept grid's rule (holds) against boxes moved inside and outside
// their margin. contact::NodeFaces: each node's faces against a scan of every face, and its rule for being
// kept (matches) against moved nodes, a changed corner and another node count.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "contact/face_grid.hpp"
#include "contact/node_faces.hpp"
#include "mesh/grid_surface.hpp"

namespace contactnn::contact {
namespace {

/// The distance from x to the box [lo, hi] (0 inside), computed independently of the grid.
double box_distance(const Vec3& x, const Vec3& lo, const Vec3& hi) {
  double squared = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max({lo[k] - x[k], x[k] - hi[k], 0.0});
    squared += d * d;
  }
  return std::sqrt(squared);
}

struct Boxes {
  std::vector<Vec3> lo, hi;
};

/// Boxes of mixed sizes: a sheet of small ones and a few large ones far away (the cells then grow).
Boxes random_boxes(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> at(0.0, 20.0), side(0.01, 1.5), z(-0.5, 0.5);
  Boxes b;
  for (int f = 0; f < n; ++f) {
    const Vec3 lo(at(rng), at(rng), z(rng));
    b.lo.push_back(lo);
    b.hi.push_back(lo + Vec3(side(rng), side(rng), 0.1 * side(rng)));
  }
  b.lo.emplace_back(500.0, 500.0, 500.0);  // a lone face far from the others
  b.hi.emplace_back(503.0, 502.0, 501.0);
  return b;
}

void expect_exact_superset(const FaceGrid& grid, const Boxes& b, double margin, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> at(-2.0, 22.0), z(-2.0, 2.0), reach(0.0, 3.0);
  std::vector<int> seen(b.lo.size());
  for (int q = 0; q < 2000; ++q) {
    const Vec3 x = q == 0 ? Vec3(501.0, 501.0, 499.5) : Vec3(at(rng), at(rng), z(rng));
    const double r = q % 7 == 0 ? 0.0 : reach(rng);
    std::fill(seen.begin(), seen.end(), 0);
    grid.for_faces_near(x, r, [&](int f) { ++seen[static_cast<std::size_t>(f)]; });
    for (std::size_t f = 0; f < b.lo.size(); ++f) {
      ASSERT_LE(seen[f], 1) << "face " << f << " reported twice, query " << q;
      const Vec3 m = Vec3::Constant(margin);
      if (box_distance(x, b.lo[f] - m, b.hi[f] + m) <= r) {
        ASSERT_EQ(seen[f], 1) << "face " << f << " within reach " << r << " missed, query " << q;
      }
    }
  }
}

TEST(FaceGrid, ReportsEveryFaceWithinReachOnce) {
  const Boxes b = random_boxes(3000, 1);
  FaceGrid grid;
  grid.build(b.lo, b.hi, 0.0);
  expect_exact_superset(grid, b, 0.0, 2);
}

TEST(FaceGrid, TheSameLayoutAtAnyThreadCount) {
  // Enough faces for the threads to fill the cells (16384 and more): each cell lists its faces in face order
  // whoever fills it, so every query visits the same faces in the same order at 1, 2 and 3 threads.
  Boxes b = random_boxes(20000, 5);
  b.lo.pop_back();  // a sheet: its rows split among the threads (with the lone far face, cells grow and the
  b.hi.pop_back();  // sheet sits in one row of cells along z)
  const int threads = omp_get_max_threads();
  std::vector<FaceGrid> grids(3);
  for (int t = 1; t <= 3; ++t) {
    omp_set_num_threads(t);
    grids[static_cast<std::size_t>(t - 1)].build(b.lo, b.hi, 0.05);
  }
  omp_set_num_threads(threads);
  expect_exact_superset(grids[1], b, 0.05, 6);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> at(-1.0, 21.0), z(-1.0, 1.0), reach(0.0, 2.0);
  for (int q = 0; q < 500; ++q) {
    const Vec3 x(at(rng), at(rng), z(rng));
    const double r = reach(rng);
    std::vector<std::vector<int>> visited(3);
    for (std::size_t g = 0; g < 3; ++g)
      grids[g].for_faces_near(x, r, [&](int f) { visited[g].push_back(f); });
    ASSERT_EQ(visited[0], visited[1]) << "query " << q;
    ASSERT_EQ(visited[0], visited[2]) << "query " << q;
  }
}

TEST(FaceGrid, InflatedBoxesAndTheirMovement) {
  Boxes b = random_boxes(500, 3);
  FaceGrid grid;
  grid.build(b.lo, b.hi, 0.25);
  expect_exact_superset(grid, b, 0.25, 4);
  EXPECT_TRUE(grid.holds(b.lo, b.hi));
  // Moved by less than the margin: the grid still holds; by more (one face): it does not.
  Boxes moved = b;
  for (auto& x : moved.lo) x += Vec3(0.2, -0.2, 0.1);
  for (auto& x : moved.hi) x += Vec3(0.2, -0.2, 0.1);
  EXPECT_TRUE(grid.holds(moved.lo, moved.hi));
  moved.hi[17].x() += 0.1;
  EXPECT_FALSE(grid.holds(moved.lo, moved.hi));
  // Another face count never holds.
  moved = b;
  moved.lo.pop_back();
  moved.hi.pop_back();
  EXPECT_FALSE(grid.holds(moved.lo, moved.hi));
}

TEST(FaceGrid, NonFiniteBoxesAndPointsAreListedNowhere) {
  Boxes b = random_boxes(50, 5);
  b.lo[3].x() = std::numeric_limits<double>::quiet_NaN();
  FaceGrid grid;
  grid.build(b.lo, b.hi, 0.0);
  int reported = 0;
  grid.for_faces_near(Vec3(10.0, 10.0, 0.0), 1e6, [&](int f) {
    EXPECT_NE(f, 3);
    ++reported;
  });
  EXPECT_EQ(reported, 50);  // every finite face of the 51
  grid.for_faces_near(Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0), 1.0,
                      [&](int) { ++reported; });
  EXPECT_EQ(reported, 50);
  EXPECT_EQ(grid.face_near(Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0), {}), -1);
  // A box made finite again does not hold (it is listed nowhere).
  Boxes fixed = b;
  fixed.lo[3] = fixed.hi[3] - Vec3::Constant(0.1);
  EXPECT_FALSE(grid.holds(fixed.lo, fixed.hi));
  EXPECT_TRUE(grid.holds(b.lo, b.hi));
}

TEST(FaceGrid, FaceNearIsAFaceOfTheCellsAround) {
  const Boxes b = random_boxes(400, 6);
  std::vector<Vec3> centres;
  for (std::size_t f = 0; f < b.lo.size(); ++f) centres.push_back(0.5 * (b.lo[f] + b.hi[f]));
  FaceGrid grid;
  grid.build(b.lo, b.hi, 0.0);
  const int f = grid.face_near(Vec3(10.0, 10.0, 0.0), centres);
  ASSERT_GE(f, 0);
  // Within a few cells of the point (the cells are the mean box side, under 1.5 here).
  EXPECT_LT((centres[static_cast<std::size_t>(f)] - Vec3(10.0, 10.0, 0.0)).norm(), 8.0);
  FaceGrid empty;
  empty.build({}, {}, 0.0);
  EXPECT_EQ(empty.face_near(Vec3::Zero(), centres), -1);
  int reported = 0;
  empty.for_faces_near(Vec3::Zero(), 1.0, [&](int) { ++reported; });
  EXPECT_EQ(reported, 0);
}

TEST(NodeFaces, TheSameListsAtAnyThreadCount) {
  // Enough faces for the threads to fill the lists (16384 and more), each list against a scan of every face.
  const mesh::SurfaceMesh m = testing::searched_grid_surface(
      150, 120, [](double i, double j) { return Vec3(i, j, 0.1 * std::sin(0.3 * i) * std::cos(0.2 * j)); });
  ASSERT_GE(m.face_count(), 16384);
  std::vector<std::vector<int>> want(m.positions.size());
  for (int f = 0; f < m.face_count(); ++f) {
    for (const int c : m.face_corners(f)) want[static_cast<std::size_t>(c)].push_back(f);
  }
  const int threads = omp_get_max_threads();
  for (int t = 1; t <= 3; ++t) {
    omp_set_num_threads(t);
    const NodeFaces topology(m);
    for (std::size_t node = 0; node < want.size(); ++node) {
      const std::span<const int> got = topology.at(static_cast<int>(node));
      ASSERT_EQ(std::vector<int>(got.begin(), got.end()), want[node])
          << "node " << node << ", " << t << " threads";
    }
    EXPECT_TRUE(topology.matches(m));
  }
  omp_set_num_threads(threads);
}

TEST(NodeFaces, ListsEachNodesFacesAndIsKeptOnlyForTheSameConnectivity) {
  const auto wavy = [](double t) {
    return testing::searched_grid_surface(7, 5, [&](double i, double j) {
      return Vec3(i, j, 0.3 * std::sin(0.7 * i + t) * std::cos(0.5 * j));
    });
  };
  const mesh::SurfaceMesh m = wavy(0.0);
  const NodeFaces topology(m);
  for (int node = 0; node < static_cast<int>(m.positions.size()); ++node) {
    std::vector<int> want;
    for (int f = 0; f < m.face_count(); ++f) {
      const std::span<const int> corners = m.face_corners(f);
      if (std::find(corners.begin(), corners.end(), node) != corners.end()) want.push_back(f);
    }
    const std::span<const int> got = topology.at(node);
    EXPECT_EQ(std::vector<int>(got.begin(), got.end()), want) << node;
  }
  // Moved nodes: the same topology. A face with another corner, or another node count: not.
  EXPECT_TRUE(topology.matches(wavy(0.4)));
  mesh::SurfaceMesh changed = wavy(0.0);
  changed.segments[3][2] = changed.segments[3][2] == 0 ? 1 : 0;
  EXPECT_FALSE(topology.matches(changed));
  mesh::SurfaceMesh more = wavy(0.0);
  more.positions.push_back(Vec3::Zero());
  EXPECT_FALSE(topology.matches(more));
}

}  // namespace
}  // namespace contactnn::contact
