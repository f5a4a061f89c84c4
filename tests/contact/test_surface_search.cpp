// contact::surface_search (SPEC 9): the closest point on the whole master surface, against a brute force
// over every face and against the exact triangle oracle, on generated surfaces with convex and concave
// edges, boundaries, slave nodes exactly on edges and vertices, and far away.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include "contact/surface_search.hpp"
#include "contact/tracking.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "mesh/grid_surface.hpp"
#include "mesh/surface_mesh.hpp"
#include "projection/closest_point_oracle.hpp"

namespace contactnn::contact {
namespace {

// Exact methods agree to rounding: 1e-12 of the face size (1 here).
constexpr double kExact = 1e-12;

/// grid_surface with the element ids and faces the surface search's tie rule reads (element q + 1, face S1).
mesh::SurfaceMesh surface_of(int nx, int ny, const std::function<Vec3(double, double)>& point) {
  return testing::searched_grid_surface(nx, ny, point);
}

/// A roof: planar faces meeting at a convex ridge along x = 3 and a concave valley along x = 6.
Vec3 roof(double i, double j) {
  const double z = i <= 3 ? i : i <= 6 ? 6 - i : i - 6;
  return Vec3(i, j, 0.5 * z);
}

/// The roof, then a strip of triangles along its far side y = 4..5, tilted down: each column a cell of two,
/// (a, b, c) and (a, c, d) across its diagonal a-c.
mesh::SurfaceMesh roof_with_triangles() {
  mesh::SurfaceMesh m = surface_of(9, 4, roof);
  const int nx = 9;
  for (int i = 0; i <= nx; ++i) {
    m.node_ids.push_back(static_cast<long>(m.node_ids.size()) + 1);
    m.positions.push_back(roof(i, 5) - Vec3(0, 0, 0.3));
    m.adjacency_offsets.push_back(m.adjacency_offsets.back());  // no segment at the new nodes
  }
  const int base = (nx + 1) * 5;  // first node of the new row
  for (int i = 0; i < nx; ++i) {
    const int a = i + (nx + 1) * 4, b = a + 1, c = base + i + 1, d = base + i;
    m.extra_faces.push_back({a, b, c, -1});
    m.extra_faces.push_back({a, c, d, -1});
    for (int k = 0; k < 2; ++k) {
      m.extra_face_faces.push_back({static_cast<int>(m.segments.size() + m.extra_faces.size()) - 1, 1});
      m.extra_face_element_ids.push_back(1000 + static_cast<long>(m.extra_faces.size()));
    }
  }
  return m;
}

std::vector<NodeSegmentPair> search(const mesh::SurfaceMesh& m, const std::vector<Vec3>& slaves,
                                    SearchOptions options = {}) {
  std::vector<long> ids(slaves.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<long>(i) + 1;
  std::vector<Vec3> normals = mesh::node_normals(m);
  return surface_search(m, normals, ids, slaves, options);
}

/// The nearest point of the roof by the triangle oracle over every face (its faces are planar).
Vec3 oracle_point(const mesh::SurfaceMesh& m, const Vec3& slave) {
  Vec3 best = Vec3::Zero();
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& q : m.segments) {
    std::array<Vec3, 4> nodes;
    for (std::size_t i = 0; i < 4; ++i) nodes[i] = m.positions[static_cast<std::size_t>(q[i])];
    const Vec3 p = testing::closest_point_on_planar_quad(slave, nodes);
    if ((slave - p).norm() < best_d) {
      best_d = (slave - p).norm();
      best = p;
    }
  }
  return best;
}

std::vector<Vec3> random_slaves(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> x(-1.5, 10.5), y(-1.5, 5.5), z(-1.5, 4.0);
  std::vector<Vec3> slaves;
  for (int i = 0; i < n; ++i) slaves.emplace_back(x(rng), y(rng), z(rng));
  return slaves;
}

TEST(SurfaceSearch, TreeEqualsBruteForceOverEveryFace) {
  const mesh::SurfaceMesh m = surface_of(9, 4, roof);
  const std::vector<Vec3> slaves = random_slaves(3000, 3);
  SearchOptions brute;
  brute.brute_force_faces = true;
  const auto tree = search(m, slaves);
  const auto all = search(m, slaves, brute);
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    ASSERT_EQ(tree[i].status, all[i].status) << "slave " << slaves[i].transpose();
    if (tree[i].status != PairStatus::kFound) continue;
    EXPECT_EQ(tree[i].segment, all[i].segment);
    EXPECT_LE((tree[i].point - all[i].point).norm(), kExact);
    EXPECT_EQ(tree[i].label.gap, all[i].label.gap);
    EXPECT_EQ(tree[i].location, all[i].location);
  }
}

TEST(SurfaceSearch, PointsAndDistancesEqualTheTriangleOracleOverConvexAndConcaveEdges) {
  const mesh::SurfaceMesh m = surface_of(9, 4, roof);
  const std::vector<Vec3> slaves = random_slaves(3000, 5);
  SearchOptions options;
  options.capture_distance = 1e3;  // every slave of the box gets its point
  const auto found = search(m, slaves, options);
  int locations[3] = {0, 0, 0};
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    ASSERT_EQ(found[i].status, PairStatus::kFound);
    const Vec3 oracle = oracle_point(m, slaves[i]);
    EXPECT_NEAR(std::abs(found[i].label.gap), (slaves[i] - oracle).norm(), kExact) << slaves[i].transpose();
    // The nearest point is unique except where two faces are equally near (then both are right).
    if ((found[i].point - oracle).norm() > kExact) {
      EXPECT_NEAR((slaves[i] - found[i].point).norm(), (slaves[i] - oracle).norm(), kExact);
    }
    ++locations[static_cast<int>(found[i].location)];
  }
  EXPECT_GT(locations[0], 100);
  EXPECT_GT(locations[1], 100);
  EXPECT_GT(locations[2], 20);
}

TEST(SurfaceSearch, GapSignFollowsThePseudoNormalAtConvexAndConcaveEdgesAndVertices) {
  const mesh::SurfaceMesh m = surface_of(9, 4, roof);
  // Ridge at x = 3 (z = 1.5), valley at x = 6 (z = 0); the boundary at x = 0 and y = 0.
  struct Case {
    Vec3 slave;
    Location location;
    bool penetrates;
  };
  const Case cases[] = {
      {Vec3(3.0, 2.5, 1.7), Location::kEdge, false},  // above the ridge
      {Vec3(3.0, 2.5, 1.3), Location::kFace, true},   // under the ridge: inside the body
      {Vec3(3.1, 2.3, 1.2), Location::kFace, true},
      {Vec3(6.0, 2.5, 0.2), Location::kFace, false},      // over the valley, nearer a face than its line
      {Vec3(6.0, 2.5, -0.2), Location::kEdge, true},      // below the valley line
      {Vec3(3.0, -0.5, 1.7), Location::kVertex, false},   // beyond the ridge's end, above
      {Vec3(3.0, 0.3, 1.2), Location::kFace, true},       // under the ridge's end
      {Vec3(-0.5, 2.5, 0.3), Location::kEdge, false},     // beyond the boundary edge x = 0, above the plane
      {Vec3(-0.5, -0.5, -0.3), Location::kVertex, true},  // beyond the corner, below the plane
  };
  std::vector<Vec3> slaves;
  for (const Case& c : cases) slaves.push_back(c.slave);
  const auto found = search(m, slaves);
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "slave " << slaves[i].transpose());
    ASSERT_EQ(found[i].status, PairStatus::kFound);
    EXPECT_EQ(found[i].location, cases[i].location);
    EXPECT_EQ(found[i].label.gap < 0.0, cases[i].penetrates) << "gap " << found[i].label.gap;
    EXPECT_NEAR(std::abs(found[i].label.gap), (slaves[i] - oracle_point(m, slaves[i])).norm(), kExact);
  }
}

TEST(SurfaceSearch, SlaveExactlyOnAnEdgeOrAVertexIsFoundWithGapZero) {
  const mesh::SurfaceMesh m = surface_of(9, 4, roof);
  std::vector<Vec3> slaves;
  std::vector<Location> expected;
  for (int i = 0; i <= 9; ++i) {
    for (int j = 0; j <= 4; ++j) {
      slaves.push_back(roof(i, j));  // every node
      expected.push_back(Location::kVertex);
      if (i < 9) {
        slaves.push_back(0.5 * (roof(i, j) + roof(i + 1, j)));  // the middle of every edge along x
        expected.push_back(Location::kEdge);
      }
    }
  }
  const auto found = search(m, slaves);
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    ASSERT_EQ(found[i].status, PairStatus::kFound) << slaves[i].transpose();
    EXPECT_EQ(found[i].location, expected[i]) << slaves[i].transpose();
    EXPECT_LE(std::abs(found[i].label.gap), kExact) << slaves[i].transpose();
    EXPECT_LE((found[i].point - slaves[i]).norm(), kExact);
  }
  // SPEC 9's tie rule: on an edge shared by two faces, the lower element id.
  const auto middle = search(m, {0.5 * (roof(4, 2) + roof(5, 2))});  // edge between faces (4,1) and (4,2)
  EXPECT_EQ(m.segment_element_ids[static_cast<std::size_t>(middle[0].segment)], 4 + 9 * 1 + 1);
}

TEST(SurfaceSearch, FarSlavesHaveNoSegmentAndTheCaptureDistanceIsOneFaceSizeByDefault) {
  const mesh::SurfaceMesh m = surface_of(9, 4, roof);
  SearchOptions options;
  const double capture = capture_distance(m, options);
  EXPECT_NEAR(capture, std::sqrt(1.0 + 1.0 + 0.25), kExact);  // the diagonal of a sloped face
  const auto found =
      search(m, {Vec3(1.0, 2.0, 0.5 + 0.9 * capture), Vec3(1.0, 2.0, 50.0), Vec3(100.0, 100.0, 100.0)});
  EXPECT_EQ(found[0].status, PairStatus::kFound);
  EXPECT_EQ(found[1].status, PairStatus::kNoSegment);
  EXPECT_EQ(found[2].status, PairStatus::kNoSegment);
  options.capture_distance = 100.0;
  EXPECT_EQ(search(m, {Vec3(1.0, 2.0, 50.0)}, options)[0].status, PairStatus::kFound);
}

TEST(SurfaceSearch, PairIsInSpec7NodeOrderWithTheLabelInThatOrder) {
  const mesh::SurfaceMesh m = surface_of(9, 4, roof);
  const std::vector<Vec3> slaves = random_slaves(500, 9);
  const auto found = search(m, slaves);
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    if (found[i].status != PairStatus::kFound) continue;
    const NodeSegmentPair& p = found[i];
    // A is the corner nearest S; the configuration is the face's corners from A on, in the face's cycle.
    for (int k = 1; k < 4; ++k) {
      EXPECT_LE((p.config.nodes[0] - slaves[i]).squaredNorm(),
                (p.config.nodes[static_cast<std::size_t>(k)] - slaves[i]).squaredNorm());
    }
    const auto& quad = m.segments[static_cast<std::size_t>(p.segment)];
    const auto a = std::find(quad.begin(), quad.end(), p.nodes[0]) - quad.begin();
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(p.nodes[static_cast<std::size_t>(k)], quad[static_cast<std::size_t>((a + k) % 4)]);
    // The label's (xi, eta) in that order is the reported point.
    const geometry::BilinearPatch facet(p.config.nodes);
    EXPECT_LE((facet.position(p.label.param[0], p.label.param[1]) - p.point).norm(), kExact);
    EXPECT_EQ(p.label.status, Status::kOk);
  }
}

TEST(SurfaceSearch, GregorySurfaceTreeEqualsBruteForceAndNoPatchSampleIsNearer) {
  // A curved surface: a quarter cylinder of radius 4 (curved along i), 6 x 3 faces.
  const auto cylinder = [](double i, double j) {
    const double angle = 0.25 * i;
    return Vec3(4.0 * std::sin(angle), j, 4.0 * std::cos(angle));
  };
  const mesh::SurfaceMesh m = surface_of(6, 3, cylinder);
  const std::vector<Vec3> normals = mesh::node_normals(m);
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> x(-0.5, 4.5), y(-0.5, 3.5), z(1.0, 5.0);
  std::vector<Vec3> slaves;
  for (int i = 0; i < 300; ++i) slaves.emplace_back(x(rng), y(rng), z(rng));
  SearchOptions options;
  options.surface = SurfaceKind::kGregory;
  options.capture_distance = 10.0;
  SearchOptions brute = options;
  brute.brute_force_faces = true;
  const auto tree = search(m, slaves, options);
  const auto all = search(m, slaves, brute);
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    ASSERT_EQ(tree[i].status, PairStatus::kFound);
    ASSERT_EQ(all[i].status, PairStatus::kFound);
    EXPECT_EQ(tree[i].segment, all[i].segment);
    EXPECT_LE((tree[i].point - all[i].point).norm(), kExact);
    double sampled = std::numeric_limits<double>::infinity();
    for (const auto& q : m.segments) {
      std::array<Vec3, 4> nodes, node_normals;
      for (std::size_t k = 0; k < 4; ++k) {
        nodes[k] = m.positions[static_cast<std::size_t>(q[k])];
        node_normals[k] = normals[static_cast<std::size_t>(q[k])];
      }
      sampled = std::min(sampled, testing::sampled_distance(geometry::GregoryPatch(nodes, node_normals),
                                                            slaves[i], 0.0, 1.0, 41));
    }
    EXPECT_LE(std::abs(tree[i].label.gap), sampled + kExact) << slaves[i].transpose();
    // Outside the cylinder (radius > 4) is separated, inside penetrates.
    const double radius = std::hypot(slaves[i].x(), slaves[i].z());
    if (std::abs(radius - 4.0) > 0.05 && slaves[i].y() > 0.0 && slaves[i].y() < 3.0 && slaves[i].x() > 0.0 &&
        std::atan2(slaves[i].x(), slaves[i].z()) < 1.5) {
      EXPECT_EQ(tree[i].label.gap < 0.0, radius < 4.0) << slaves[i].transpose();
    }
  }
}

TEST(SurfaceSearch, TrianglesCountAndMeetTheQuadsAtSharedEdges) {
  const mesh::SurfaceMesh m = roof_with_triangles();
  const std::vector<Vec3> slaves = random_slaves(2000, 31);
  SearchOptions options;
  options.capture_distance = 1e3;
  const auto found = search(m, slaves, options);
  int on_triangles = 0;
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    ASSERT_EQ(found[i].status, PairStatus::kFound);
    double best = (slaves[i] - oracle_point(m, slaves[i])).norm();
    for (const auto& t : m.extra_faces) {
      const Vec3 p = testing::closest_point_on_triangle(
          slaves[i], m.positions[static_cast<std::size_t>(t[0])], m.positions[static_cast<std::size_t>(t[1])],
          m.positions[static_cast<std::size_t>(t[2])]);
      best = std::min(best, (slaves[i] - p).norm());
    }
    EXPECT_NEAR(std::abs(found[i].label.gap), best, kExact) << slaves[i].transpose();
    on_triangles += m.face_corners(found[i].segment).size() == 3;
  }
  EXPECT_GT(on_triangles, 100);
  // Just above and below the fold between the roof and the triangles (y = 4): separated, penetrating.
  const auto fold = search(m, {Vec3(1.5, 4.0, 0.75 + 0.1), Vec3(1.5, 4.0, 0.75 - 0.1)});
  EXPECT_GT(fold[0].label.gap, 0.0);
  EXPECT_LT(fold[1].label.gap, 0.0);
}

TEST(SurfaceSearch, ASlaveOverOneTriangleOfACellProjectsThatTriangleAlone) {
  // The roof's strip of triangles (as above): each cell's two triangles share a diagonal, and each one's box
  // is the whole cell's. A slave 0.05 over a triangle, 0.1 or more from each of its edges, is beyond the
  // other triangle's edge plane (EdgePlanes): one face projected, not two.
  const mesh::SurfaceMesh m = roof_with_triangles();
  std::vector<Vec3> slaves;
  for (std::size_t q = 0; q < m.extra_faces.size(); ++q) {
    const std::array<int, 4>& t = m.extra_faces[q];
    // A point inside each triangle, 0.1 or more from its edges in barycentric weight.
    const Vec3 weights = q % 2 == 0 ? Vec3(0.5, 0.3, 0.2) : Vec3(0.5, 0.2, 0.3);
    const Vec3 &x = m.positions[static_cast<std::size_t>(t[0])],
               &y = m.positions[static_cast<std::size_t>(t[1])],
               &z = m.positions[static_cast<std::size_t>(t[2])];
    const Vec3 normal = (y - x).cross(z - x).normalized();
    slaves.push_back(weights[0] * x + weights[1] * y + weights[2] * z + 0.05 * normal);
  }
  const auto found = search(m, slaves);
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    ASSERT_EQ(found[i].status, PairStatus::kFound) << i;
    EXPECT_EQ(m.face_corners(found[i].segment).size(), 3U) << i;
    EXPECT_NEAR(found[i].label.gap, 0.05, kExact) << i;
    EXPECT_EQ(found[i].candidates, 1) << i;
  }
}

TEST(SurfaceSearch, EverySearchGivesTheUnitScalesAnswerAtScalesFrom1eMinus200To1e200) {
  // The closest points and the trees' squared radii need lengths whose fourth powers stay in the double
  // range: scaled by 1e-100 the surface search found no point for any slave node, by 1e100 it put every point
  // on an edge, and the nearest-node search lost its labels at 1e+-200. Both now work in a unit of their own
  // (working_unit) and answer in world units: the same faces, locations and statuses, the points and gaps
  // scaled (to the rounding of the scaled inputs).
  const mesh::SurfaceMesh unit_mesh = surface_of(9, 4, [](double i, double j) -> Vec3 {
    return roof(i, j) + Vec3(0, 0, 0.2 * std::sin(0.9 * i) * std::cos(0.7 * j));
  });
  const std::vector<Vec3> unit_slaves = random_slaves(400, 17);
  std::vector<long> ids(unit_slaves.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<long>(i) + 1;
  struct Kind {
    GlobalSearchKind search;
    SurfaceKind surface;
  };
  for (const Kind kind : {Kind{GlobalSearchKind::kSurface, SurfaceKind::kBilinear},
                          Kind{GlobalSearchKind::kSurface, SurfaceKind::kGregory},
                          Kind{GlobalSearchKind::kNearestNode, SurfaceKind::kBilinear}}) {
    SearchOptions options;
    options.search = kind.search;
    options.surface = kind.surface;
    const auto run = [&](const mesh::SurfaceMesh& m, const std::vector<Vec3>& slaves) {
      const std::vector<Vec3> normals = mesh::node_normals(m);
      return kind.search == GlobalSearchKind::kSurface ? surface_search(m, normals, ids, slaves, options)
                                                       : global_search(m, normals, ids, slaves, options);
    };
    const auto reference = run(unit_mesh, unit_slaves);
    int found = 0;
    for (const NodeSegmentPair& p : reference) found += p.status == PairStatus::kFound;
    ASSERT_GT(found, 100);
    for (const double scale : {1e-200, 1e-100, 1e100, 1e200}) {
      mesh::SurfaceMesh m = unit_mesh;
      for (Vec3& x : m.positions) x *= scale;
      std::vector<Vec3> slaves = unit_slaves;
      for (Vec3& x : slaves) x *= scale;
      const auto scaled = run(m, slaves);
      // And the tracker, over two states (the second the same: every node tracked).
      SurfaceTracker tracker(options);
      std::vector<NodeSegmentPair> tracked;
      if (kind.search == GlobalSearchKind::kSurface) {
        for (int step = 0; step < 2; ++step) tracker.step(m, mesh::node_normals(m), ids, slaves, tracked);
        // A third state, every slave node moved by 0.3 face sizes: its list stays valid by the rule only if
        // the movement is measured (a norm of world lengths near 1e-200 underflowed to 0), and then the
        // tracked answers are the fresh ones.
        std::vector<Vec3> moved = slaves;
        for (Vec3& x : moved) x += scale * Vec3(0.21, -0.21, 0.0);
        std::vector<NodeSegmentPair> third;
        SurfaceTracker copy = tracker;
        copy.step(m, mesh::node_normals(m), ids, moved, third);
        const auto fresh_moved = surface_search(m, mesh::node_normals(m), ids, moved, options);
        for (std::size_t i = 0; i < third.size(); ++i) {
          ASSERT_EQ(third[i].status, fresh_moved[i].status) << "moved, scale " << scale << " slave " << i;
          if (third[i].status != PairStatus::kFound) continue;
          EXPECT_EQ(third[i].segment, fresh_moved[i].segment) << "moved, scale " << scale << " slave " << i;
          EXPECT_LE(((third[i].point - fresh_moved[i].point) / scale).norm(), 1e-12)
              << "moved, scale " << scale << " slave " << i;
        }
      }
      for (std::size_t i = 0; i < reference.size(); ++i) {
        const std::string where = std::string(to_string(kind.surface)) +
                                  (kind.search == GlobalSearchKind::kSurface ? " surface" : " nearest-node") +
                                  " search, scale " + std::to_string(std::log10(scale)) + " (log10), slave " +
                                  std::to_string(i);
        for (const std::vector<NodeSegmentPair>* answers :
             {&scaled, static_cast<const std::vector<NodeSegmentPair>*>(&tracked)}) {
          if (answers->empty()) continue;
          const NodeSegmentPair& p = (*answers)[i];
          ASSERT_EQ(p.status, reference[i].status) << where << (answers == &scaled ? " search" : " tracker");
          if (p.status != PairStatus::kFound) continue;
          EXPECT_EQ(p.segment, reference[i].segment) << where;
          EXPECT_EQ(p.location, reference[i].location) << where;
          EXPECT_EQ(p.label.status, reference[i].label.status) << where;
          EXPECT_NEAR(p.label.gap / scale, reference[i].label.gap, 1e-12) << where;
          EXPECT_LE((p.config.slave / scale - unit_slaves[i]).norm(), 1e-12) << where;
          EXPECT_LE((p.config.nodes[0] / scale - reference[i].config.nodes[0]).norm(), 1e-12) << where;
          if (kind.search == GlobalSearchKind::kSurface) {
            EXPECT_LE((p.point / scale - reference[i].point).norm(), 1e-12) << where;
          }
        }
      }
    }
  }
}

TEST(SurfaceSearch, SameResultForAnyThreadCount) {
  const mesh::SurfaceMesh m = surface_of(9, 4, roof);
  const std::vector<Vec3> slaves = random_slaves(2000, 23);
  omp_set_num_threads(1);
  const auto one = search(m, slaves);
  omp_set_num_threads(2);
  const auto two = search(m, slaves);
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    ASSERT_EQ(one[i].segment, two[i].segment);
    ASSERT_EQ(one[i].label.gap, two[i].label.gap);
    ASSERT_EQ(one[i].label.param, two[i].label.param);
  }
}

TEST(SurfaceSearch, SameBitsInAnyNodeOrder) {
  // Each node's first face is its neighbour's answer or a face of its grid cell, whichever the order gives;
  // the answer must not depend on it: every node's point, gap and parameters bit for bit when searched
  // alone (no neighbour) and among all the others.
  const mesh::SurfaceMesh m = surface_of(9, 4, roof);
  const std::vector<Vec3> slaves = random_slaves(2000, 29);
  for (const SurfaceKind surface : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    SearchOptions options;
    options.surface = surface;
    const auto all = search(m, slaves, options);
    for (std::size_t i = 0; i < slaves.size(); i += 5) {
      const NodeSegmentPair& a = all[i];
      const NodeSegmentPair b = search(m, {slaves[i]}, options)[0];
      ASSERT_EQ(a.status, b.status) << i;
      ASSERT_EQ(a.segment, b.segment) << i;
      ASSERT_EQ(a.label.gap, b.label.gap) << i;
      ASSERT_EQ(a.face_param, b.face_param) << i;
      ASSERT_EQ(a.point, b.point) << i;
    }
  }
}

/// Every field of two answers, bit for bit.
void expect_same_contact(const Contact& a, const Contact& b, const std::string& where) {
  EXPECT_EQ(a.status, b.status) << where;
  EXPECT_EQ(a.face, b.face) << where;
  EXPECT_EQ(a.location, b.location) << where;
  EXPECT_EQ(a.param, b.param) << where;
  EXPECT_EQ(a.point, b.point) << where;
  EXPECT_EQ(a.gap, b.gap) << where;
  EXPECT_EQ(a.normal, b.normal) << where;
}

/// The points' box, as surface_search takes it from spatial_order.
PointBox box_of(const std::vector<Vec3>& points) {
  std::vector<std::uint32_t> order;
  std::vector<std::uint64_t> scratch;
  PointBox box;
  spatial_order(points, order, scratch, &box);
  return box;
}

/// Each slave's answer from `searcher` (nearest_fresh, no hint).
std::vector<Contact> answers(const SurfaceSearcher& searcher, const std::vector<Vec3>& slaves) {
  std::vector<Contact> out(slaves.size());
  std::vector<std::pair<double, int>> candidates;
  std::vector<std::pair<std::uint32_t, double>> scratch;
  for (std::size_t i = 0; i < slaves.size(); ++i)
    searcher.nearest_fresh(static_cast<long>(i) + 1, slaves[i], candidates, scratch, out[i]);
  return out;
}

TEST(SurfaceSearch, FacesBeyondTheQueriesAreLeftOutAndEveryQueryGetsTheSameAnswer) {
  // A wavy sheet of 30 x 30 faces with node normals turned at random by up to 0.4 (the Gregory patches then
  // bulge off their nodes); the slave nodes over a corner of it, some beyond the capture distance.
  const mesh::SurfaceMesh m = surface_of(
      30, 30, [](double i, double j) { return Vec3(i, j, 0.6 * std::sin(i / 3.0) * std::cos(j / 4.0)); });
  std::vector<Vec3> normals = mesh::node_normals(m);
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> turn(-0.4, 0.4), x(1.0, 7.0), z(-1.5, 3.0);
  for (Vec3& n : normals) n = (n + Vec3(turn(rng), turn(rng), turn(rng))).normalized();
  std::vector<Vec3> slaves;
  for (int i = 0; i < 400; ++i) slaves.emplace_back(x(rng), x(rng), z(rng));
  for (const SurfaceKind surface : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    SearchOptions options;
    options.surface = surface;
    const SurfaceSearcher all(m, normals, options);
    const PointBox slaves_box = box_of(slaves);
    const SurfaceSearcher near(m, normals, options, nullptr, 0.0, nullptr, nullptr, &slaves_box);
    EXPECT_EQ(all.faces_left_out(), 0U);
    // The slaves' box is 6 x 6 faces; with the capture distance (sqrt 2) and the patches' bounds, at most
    // 13 x 13 faces come within reach of it.
    EXPECT_GE(near.faces_left_out(), 900U - 169U);
    const std::vector<Contact> a = answers(all, slaves), b = answers(near, slaves);
    int found = 0;
    for (std::size_t i = 0; i < slaves.size(); ++i) {
      expect_same_contact(a[i], b[i], "slave " + std::to_string(i));
      found += a[i].status == PairStatus::kFound;
    }
    EXPECT_GT(found, 200);
    EXPECT_LT(found, 400);  // some beyond the capture distance: no face within it, with or without the region
    // A slave off the sheet's edge, 1.2 from it (the capture distance is sqrt 2): the edge face is kept.
    const std::vector<Vec3> off = {Vec3(-1.2, 3.5, 0.0)};
    const PointBox off_box = box_of(off);
    const SurfaceSearcher edge(m, normals, options, nullptr, 0.0, nullptr, nullptr, &off_box);
    EXPECT_GE(edge.faces_left_out(), 900U - 30U);
    const Contact answer = answers(edge, off)[0];
    EXPECT_EQ(answer.status, PairStatus::kFound);
    expect_same_contact(answers(all, off)[0], answer, "the slave off the edge");
  }
}

TEST(SurfaceSearch, AGregoryPatchBulgingFarOffItsNodesIsKeptForAQueryNearItsTop) {
  // One flat unit square whose node normals lean out from its centre: its Gregory patch rises about 0.2 above
  // the nodes' plane. A slave 0.01 above its top, with a capture distance of 0.05, lies far beyond the
  // capture distance of the nodes: the face is kept only if its bound holds the patch.
  const mesh::SurfaceMesh m = surface_of(1, 1, [](double i, double j) { return Vec3(i, j, 0.0); });
  std::vector<Vec3> normals;
  for (const Vec3& x : m.positions) normals.push_back(Vec3(x.x() - 0.5, x.y() - 0.5, 0.5).normalized());
  std::array<Vec3, 4> nodes, node_normals;
  for (std::size_t k = 0; k < 4; ++k) {
    nodes[k] = m.positions[static_cast<std::size_t>(m.segments[0][k])];
    node_normals[k] = normals[static_cast<std::size_t>(m.segments[0][k])];
  }
  const Vec3 top = geometry::GregoryPatch(nodes, node_normals).position(0.5, 0.5);
  ASSERT_GT(top.z(), 0.1);
  SearchOptions options;
  options.surface = SurfaceKind::kGregory;
  options.capture_distance = 0.05;
  const std::vector<Vec3> slave = {top + Vec3(0.0, 0.0, 0.01)};
  const SurfaceSearcher all(m, normals, options);
  const PointBox slave_box = box_of(slave);
  const SurfaceSearcher near(m, normals, options, nullptr, 0.0, nullptr, nullptr, &slave_box);
  EXPECT_EQ(near.faces_left_out(), 0U);
  const std::vector<Contact> a = answers(all, slave), b = answers(near, slave);
  ASSERT_EQ(b[0].status, PairStatus::kFound);
  EXPECT_NEAR(b[0].gap, 0.01, 1e-6);
  expect_same_contact(a[0], b[0], "the slave above the top");
  // Beyond the capture distance of the whole patch, the face is left out, and nothing is found either way.
  const std::vector<Vec3> high = {top + Vec3(0.0, 0.0, 5.0)};
  const PointBox high_box = box_of(high);
  const SurfaceSearcher far(m, normals, options, nullptr, 0.0, nullptr, nullptr, &high_box);
  EXPECT_EQ(far.faces_left_out(), 1U);
  expect_same_contact(answers(all, high)[0], answers(far, high)[0], "the slave far above");
  EXPECT_EQ(answers(far, high)[0].status, PairStatus::kNoSegment);
}

TEST(SurfaceSearch, OneStorageServesFreshSearchesOfAnySurfaceWithTheSameBits) {
  // A fresh search reuses the memory of a SearchStorage's tables, grid and faces at each node, never their
  // entries: each search below, made with one storage after the others, answers bit for bit as without one.
  const mesh::SurfaceMesh roof_quads = surface_of(9, 4, roof);
  // The same roof with its faces numbered backwards: the node count is the same, the faces at each node are
  // not (a storage's faces at each node, kept from the roof above, would name the wrong faces).
  mesh::SurfaceMesh renumbered = roof_quads;
  std::reverse(renumbered.segments.begin(), renumbered.segments.end());
  std::reverse(renumbered.segment_faces.begin(), renumbered.segment_faces.end());
  std::reverse(renumbered.segment_element_ids.begin(), renumbered.segment_element_ids.end());
  mesh::set_adjacency(renumbered);
  mesh::SurfaceMesh moved = renumbered;
  for (Vec3& x : moved.positions) x += Vec3(0.1 * std::sin(x.y()), 0.0, 0.2 * std::cos(x.x()));
  const std::vector<Vec3> slaves = random_slaves(3000, 43);
  std::vector<long> ids(slaves.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<long>(i) + 1;
  SearchStorage storage;
  const auto expect_same_with_storage = [&](const mesh::SurfaceMesh& m, SurfaceKind surface,
                                            const std::string& what) {
    SearchOptions options;
    options.surface = surface;
    const std::vector<Vec3> normals = mesh::node_normals(m);
    std::vector<Contact> alone, kept;
    surface_search(m, normals, ids, slaves, options, alone);
    surface_search(m, normals, ids, slaves, options, kept, &storage);
    int edges = 0;
    for (std::size_t i = 0; i < slaves.size(); ++i) {
      expect_same_contact(alone[i], kept[i], what + ", slave " + std::to_string(i));
      edges += alone[i].status == PairStatus::kFound && alone[i].location != Location::kFace;
    }
    EXPECT_GT(edges, 300) << what;  // the faces at each node matter: many points on edges and vertices
  };
  expect_same_with_storage(roof_quads, SurfaceKind::kBilinear, "the roof");
  expect_same_with_storage(roof_quads, SurfaceKind::kGregory, "the roof's Gregory patches");
  expect_same_with_storage(roof_with_triangles(), SurfaceKind::kBilinear, "the roof with triangles");
  expect_same_with_storage(renumbered, SurfaceKind::kBilinear, "the roof renumbered");
  // A searcher that keeps the faces' entries between states (a tracker's) in the same storage, then a fresh
  // search of a moved state in it: neither takes the other's entries.
  {
    const std::vector<Vec3> normals = mesh::node_normals(renumbered);
    const SurfaceSearcher keeping(renumbered, normals, SearchOptions{}, nullptr, 0.0, nullptr, &storage);
    const SurfaceSearcher alone(renumbered, normals, SearchOptions{});
    const std::vector<Contact> a = answers(alone, slaves), b = answers(keeping, slaves);
    for (std::size_t i = 0; i < slaves.size(); ++i)
      expect_same_contact(a[i], b[i], "keeping, slave " + std::to_string(i));
  }
  expect_same_with_storage(moved, SurfaceKind::kBilinear, "the renumbered roof moved");
  expect_same_with_storage(moved, SurfaceKind::kGregory, "its Gregory patches");
}

}  // namespace
}  // namespace contactnn::contact
