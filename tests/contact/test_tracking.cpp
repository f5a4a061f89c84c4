// contact::SurfaceTracker: over a moving history the tracked surface search gives the fresh search's faces,
// points and gaps at every increment, starts most nodes from their previous faces and keeps its grid while
// the faces move within its margin; the reference tracker (NarrowPhase::kReference) answers most nodes from
// their lists.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "contact/tracking.hpp"
#include "mesh/grid_surface.hpp"
#include "surface_params.hpp"

namespace contactnn::contact {
namespace {

// Points of the two searches agree to rounding: 1e-12 of the face size (about 1).
constexpr double kSame = 1e-12;

/// A wavy sheet whose waves travel with time t; element q + 1, face S1.
mesh::SurfaceMesh sheet(double t) {
  return testing::searched_grid_surface(12, 8, [&](double i, double j) {
    return Vec3(i, j, 0.4 * std::sin(0.5 * i + t) * std::cos(0.4 * j - 0.5 * t));
  });
}

struct History {
  std::vector<long> ids;
  std::vector<Vec3> start, velocity;
  /// The slave nodes' positions at an increment.
  [[nodiscard]] std::vector<Vec3> at(int increment) const {
    std::vector<Vec3> x;
    for (std::size_t i = 0; i < ids.size(); ++i) x.push_back(start[i] + increment * velocity[i]);
    return x;
  }
};

History slaves(int n) {
  History h;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> x(0.0, 12.0), y(0.0, 8.0), z(-0.6, 0.6), v(-0.05, 0.05);
  for (int i = 0; i < n; ++i) {
    h.ids.push_back(i + 1);
    h.start.emplace_back(x(rng), y(rng), z(rng));
    h.velocity.emplace_back(v(rng), v(rng), 0.3 * v(rng));
  }
  return h;
}

void expect_same(const std::vector<NodeSegmentPair>& a, const std::vector<NodeSegmentPair>& b,
                 int increment) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].status, b[i].status) << "increment " << increment << " slave " << a[i].slave_id;
    if (a[i].status != PairStatus::kFound) continue;
    ASSERT_EQ(a[i].segment, b[i].segment) << "increment " << increment << " slave " << a[i].slave_id;
    ASSERT_LE((a[i].point - b[i].point).norm(), kSame)
        << "increment " << increment << " slave " << a[i].slave_id;
    ASSERT_NEAR(a[i].label.gap, b[i].label.gap, kSame);
    ASSERT_EQ(a[i].location, b[i].location);
  }
}

class Tracking : public ::testing::TestWithParam<SurfaceKind> {};

/// Tracks h over `increments` states of the travelling sheet, each answer expected to be the fresh search's;
/// the counts of every increment.
std::vector<TrackingCounts> track_against_fresh(const SearchOptions& options, const History& h,
                                                int increments) {
  SurfaceTracker tracker(options);
  std::vector<TrackingCounts> all;
  for (int increment = 0; increment < increments; ++increment) {
    const mesh::SurfaceMesh m = sheet(0.05 * increment);
    const std::vector<Vec3> normals = mesh::node_normals(m);
    const std::vector<Vec3> positions = h.at(increment);
    TrackingCounts counts;
    const auto by_tracking = tracker.step(m, normals, h.ids, positions, &counts);
    expect_same(by_tracking, surface_search(m, normals, h.ids, positions, options), increment);
    EXPECT_EQ(counts.fresh + counts.tracked, static_cast<long>(h.ids.size()));
    all.push_back(counts);
  }
  return all;
}

TEST_P(Tracking, GivesTheFreshSearchsFacesPointsAndGapsAtEveryIncrement) {
  // Fewer nodes on Gregory patches, whose closest points cost ten times more.
  const int n = GetParam() == SurfaceKind::kGregory ? 300 : 1500;
  SearchOptions options;
  options.surface = GetParam();
  const std::vector<TrackingCounts> counts = track_against_fresh(options, slaves(n), 12);
  EXPECT_EQ(counts[0].fresh, n);
  EXPECT_EQ(counts[0].grid_builds, 1);
  long tracked = 0, warm = 0, grid_builds = 0;
  for (const TrackingCounts& c : counts) {
    tracked += c.tracked;
    warm += c.warm;
    grid_builds += c.grid_builds;
  }
  // Most nodes start from their previous face and point.
  EXPECT_GT(tracked, 8 * n);
  EXPECT_GT(warm, 8 * n);
  // The waves move the faces by less than the grid's margin at most increments: the answers above were found
  // with grids kept from earlier increments.
  EXPECT_LT(grid_builds, 6);
  EXPECT_GT(grid_builds, 1);
}

TEST_P(Tracking, FacesThatDidNotMoveKeepTheirEntriesAndTheAnswersStayTheFreshOnes) {
  // Half the sheet still (i < 6: its faces keep what the searcher computed for them, SearchStorage), the
  // other half waving, and one node of the still half nudged at increment 3 (its faces, and on Gregory
  // patches its neighbours' through the normals, computed again); every answer the fresh search's.
  const auto half = [](double t, bool nudge) {
    return testing::searched_grid_surface(12, 8, [&](double i, double j) {
      const double wave = i < 6.0 ? 0.0 : t;
      const double bump = nudge && i == 3.0 && j == 4.0 ? 0.05 : 0.0;
      return Vec3(i, j, 0.4 * std::sin(0.5 * i + wave) * std::cos(0.4 * j) + bump);
    });
  };
  const History h = slaves(GetParam() == SurfaceKind::kGregory ? 300 : 1200);
  SearchOptions options;
  options.surface = GetParam();
  SurfaceTracker tracker(options);
  for (int increment = 0; increment < 6; ++increment) {
    const mesh::SurfaceMesh m = half(0.05 * increment, increment >= 3);
    const std::vector<Vec3> normals = mesh::node_normals(m);
    const std::vector<Vec3> positions = h.at(increment);
    expect_same(tracker.step(m, normals, h.ids, positions),
                surface_search(m, normals, h.ids, positions, options), increment);
  }
}

TEST(Tracking, TheReferenceTrackerAnswersFromItsLists) {
  SearchOptions options;
  options.narrow = NarrowPhase::kReference;
  long tracked = 0;
  for (const TrackingCounts& c : track_against_fresh(options, slaves(600), 6)) {
    EXPECT_EQ(c.grid_builds, 0);
    tracked += c.tracked;
  }
  EXPECT_GT(tracked, 4 * 600);
}

TEST_P(Tracking, ANodeThatJumpsFarGetsItsNewFace) {
  for (const NarrowPhase narrow : {NarrowPhase::kCertified, NarrowPhase::kReference}) {
    SearchOptions options;
    options.surface = GetParam();
    options.narrow = narrow;
    SurfaceTracker tracker(options);
    const mesh::SurfaceMesh m = sheet(0.0);
    const std::vector<Vec3> normals = mesh::node_normals(m);
    const std::vector<long> ids = {7};
    TrackingCounts counts;
    (void)tracker.step(m, normals, ids, std::vector<Vec3>{Vec3(1.5, 1.5, 0.3)}, &counts);
    const std::vector<Vec3> far = {Vec3(10.5, 6.5, 0.3)};
    const auto jumped = tracker.step(m, normals, ids, far, &counts);
    // The certified tracker starts from the previous face, far away now; the reference rebuilds the list.
    EXPECT_EQ(counts.tracked, narrow == NarrowPhase::kCertified ? 1 : 0);
    EXPECT_EQ(counts.fresh, narrow == NarrowPhase::kCertified ? 0 : 1);
    expect_same(jumped, surface_search(m, normals, ids, far, options), 1);
    // A surface with other faces starts over (and the grid is rebuilt).
    const mesh::SurfaceMesh with_ids =
        testing::searched_grid_surface(3, 3, [](double i, double j) { return Vec3(i, j, 0.0); });
    const std::vector<Vec3> on = {Vec3(1.5, 1.5, 0.2)};
    const auto other = tracker.step(with_ids, mesh::node_normals(with_ids), ids, on, &counts);
    EXPECT_EQ(counts.fresh, 1);
    EXPECT_EQ(counts.grid_builds, narrow == NarrowPhase::kCertified ? 1 : 0);
    expect_same(other, surface_search(with_ids, mesh::node_normals(with_ids), ids, on, options), 2);
  }
}

TEST(Tracking, AFaceTurningInPlaceIntoACandidateIsFound) {
  // A long thin face (2 x 0.2) turns by 90 degrees about its centre: its bounding sphere stays where it was
  // (no drift), its box does not. The slave node, 0.9 off its long axis, was 0.8 from the box at the first
  // increment (beyond capture 0.5 + margin 0.25) and lies 0.05 above the face at the second. A reference list
  // built by the boxes left the face out (no_segment where the fresh search finds it); lists are built by the
  // spheres. The grid lists the face by its box: it is rebuilt, the box having left its margin.
  for (const NarrowPhase narrow : {NarrowPhase::kCertified, NarrowPhase::kReference}) {
    SearchOptions options;
    options.capture_distance = 0.5;
    options.narrow = narrow;
    SurfaceTracker tracker(options, TrackingOptions{0.5, 0.5});
    const auto face_at = [](double angle) {
      mesh::SurfaceMesh m = testing::grid_surface(1, 1, [&](double i, double j) {
        const double x = 2.0 * i - 1.0, y = 0.2 * j - 0.1;
        return Vec3(std::cos(angle) * x - std::sin(angle) * y, std::sin(angle) * x + std::cos(angle) * y,
                    0.0);
      });
      m.segment_faces.push_back({0, 1});
      m.segment_element_ids.push_back(1);
      return m;
    };
    const std::vector<long> ids = {1};
    const std::vector<Vec3> slave = {Vec3(0.0, 0.9, 0.05)};
    std::vector<NodeSegmentPair> pairs;  // one buffer for both increments, as an FE code's
    const mesh::SurfaceMesh before = face_at(0.0);
    tracker.step(before, mesh::node_normals(before), ids, slave, pairs);
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0].status, PairStatus::kNoSegment);
    const mesh::SurfaceMesh after = face_at(0.5 * std::numbers::pi);
    TrackingCounts counts;
    tracker.step(after, mesh::node_normals(after), ids, slave, pairs, &counts);
    if (narrow == NarrowPhase::kReference) {
      EXPECT_EQ(counts.tracked, 1);  // the list is still valid: nothing moved by the rule
    } else {
      EXPECT_EQ(counts.grid_builds, 1);
    }
    const auto fresh = surface_search(after, mesh::node_normals(after), ids, slave, options);
    ASSERT_EQ(fresh[0].status, PairStatus::kFound);
    EXPECT_NEAR(fresh[0].label.gap, 0.05, 1e-12);
    expect_same(pairs, fresh, 1);
  }
}

TEST(Tracking, TwoWarmRunsEndingOnTheirSharedEdgeGetTheGrid) {
  // Node 1021849 of make-large-history's 1e6-node history at increment 4: it lies over the edge x = 240
  // between its previous face (x 239..240, warm-started from its point of increment 3) and the next one,
  // whose closest point is 5.4e-5 inside. Both warm runs ended on the shared edge at the same distance; the
  // tie went to the previous face, whose grid confirmed its edge point, and the next face's interior
  // point, 1.5e-7 nearer, was never found. A warm boundary answer within the tie band of the best now gets
  // the grid as well. The node coordinates of the .frd (z = 0.2 sin(x / 5) cos(y / 7) to 6 digits) and the
  // slave's (+ DISP).
  static constexpr double kZ[2][3] = {{-1.96176e-02, -2.40847e-02, -2.75916e-02},
                                      {-3.70158e-02, -4.54445e-02, -5.20615e-02}};
  mesh::SurfaceMesh m = testing::grid_surface(2, 1, [](double i, double j) -> Vec3 {
    return Vec3(239.0 + i, 254.0 + j, kZ[static_cast<int>(j)][static_cast<int>(i)]);
  });
  for (std::size_t q = 0; q < m.segments.size(); ++q) {
    m.segment_faces.push_back({static_cast<int>(q), 1});
    m.segment_element_ids.push_back(static_cast<long>(q) + 1);
  }
  const std::vector<Vec3> normals = mesh::node_normals(m);
  const SearchOptions options;
  const SurfaceSearcher searcher(m, normals, options);
  const Vec3 slave(239.95 + 0.05, 254.65, 1.22670e-02 + -0.06);
  std::vector<std::pair<double, int>> candidates;
  std::vector<std::pair<std::uint32_t, double>> scratch;
  searcher.faces_within(slave, searcher.capture(), candidates, scratch);
  std::vector<std::pair<double, int>> fresh_candidates = candidates;
  const NodeSegmentPair fresh = searcher.nearest(1, slave, fresh_candidates);
  ASSERT_EQ(fresh.status, PairStatus::kFound);
  ASSERT_EQ(fresh.segment, 1);
  ASSERT_EQ(fresh.location, Location::kFace);
  const FaceHint previous{0, {0.9001424304424398, 0.30042795947597628}};
  const NodeSegmentPair tracked = searcher.nearest(1, slave, candidates, &previous);
  expect_same({fresh}, {tracked}, 4);
}

TEST(Tracking, ANodesListIsMadeAroundItAndTakenWhileItCoversTheReach) {
  // Rule 5 at one node: the list made at the first query, taken at the next (the node moved 0.01: the same
  // answer as without a list), made again where the drift has spent its radius.
  const mesh::SurfaceMesh m = sheet(0.0);
  const std::vector<Vec3> normals = mesh::node_normals(m);
  const SearchOptions options;
  const SurfaceSearcher searcher(m, normals, options);
  std::vector<std::pair<double, int>> candidates;
  std::vector<std::pair<std::uint32_t, double>> scratch;
  NearFaces near;
  const Vec3 s(3.4, 2.6, 0.4 * std::sin(0.5 * 3.4) * std::cos(0.4 * 2.6) + 0.05);
  Contact first;
  searcher.nearest_fresh(1, s, candidates, scratch, first, nullptr, &near, 0.0);
  ASSERT_EQ(first.status, PairStatus::kFound);
  EXPECT_EQ(near.anchor, s);
  ASSERT_GE(near.radius, 0.0F);
  ASSERT_GE(near.count, 1);
  ASSERT_LE(near.count, static_cast<int>(NearFaces::kCapacity));
  const auto listed = [&](int face) {
    return std::find(near.faces.begin(), near.faces.begin() + near.count, face) !=
           near.faces.begin() + near.count;
  };
  EXPECT_TRUE(listed(first.face));
  for (int k = 1; k < near.count; ++k)
    EXPECT_LE(near.bounds[static_cast<std::size_t>(k - 1)], near.bounds[static_cast<std::size_t>(k)]);
  // Every face within the list's radius is listed (the faces' own bounds, by brute force).
  for (int f = 0; f < m.face_count(); ++f) {
    if (searcher.lower_bound(s, f) <= 0.99 * static_cast<double>(near.radius)) {
      EXPECT_TRUE(listed(f)) << f;
    }
  }
  const Vec3 moved = s + Vec3(0.01, 0.0, 0.0);
  const FaceHint hint{first.face, first.param};
  Contact taken, without;
  searcher.nearest_fresh(1, moved, candidates, scratch, taken, &hint, &near, 0.0);
  EXPECT_EQ(near.anchor, s);  // taken, not made again
  searcher.nearest_fresh(1, moved, candidates, scratch, without, &hint);
  EXPECT_EQ(taken.face, without.face);
  EXPECT_EQ(taken.point, without.point);
  EXPECT_EQ(taken.gap, without.gap);
  EXPECT_EQ(taken.candidates, without.candidates);
  Contact drifted;
  searcher.nearest_fresh(1, moved, candidates, scratch, drifted, &hint, &near, 10.0);
  EXPECT_EQ(near.anchor, moved);  // made again
  EXPECT_EQ(near.drift, 10.0);
  EXPECT_EQ(drifted.gap, without.gap);
}

TEST(Tracking, AListWithMoreFacesThanItHoldsKeepsTheNearestAndShrinksItsRadius) {
  // A node 0.3 over a face of a flat unit grid, 0.1 off its centre along y: its own face's box is 0.3 away,
  // its four edge neighbours' 0.5 to 0.67, the two diagonal ones below 0.71, all within the list's radius
  // (the reach, 0.3, plus a grid cell of half a face). The list keeps the five nearest, whichever order the
  // grid gives them in, and its radius is at most 0.71 (every face nearer than it is listed); a move within
  // that takes the list, and answers as without one.
  const mesh::SurfaceMesh m =
      testing::searched_grid_surface(6, 6, [](double i, double j) { return Vec3(i, j, 0.0); });
  const std::vector<Vec3> normals = mesh::node_normals(m);
  SearchOptions options;
  options.capture_distance = 1.0;
  const SurfaceSearcher searcher(m, normals, options);
  std::vector<std::pair<double, int>> candidates;
  std::vector<std::pair<std::uint32_t, double>> scratch;
  NearFaces near;
  const Vec3 s(2.5, 2.4, 0.3);
  Contact first;
  searcher.nearest_fresh(1, s, candidates, scratch, first, nullptr, &near, 0.0);
  ASSERT_EQ(first.status, PairStatus::kFound);
  ASSERT_EQ(near.count, static_cast<int>(NearFaces::kCapacity));  // a list, not the grid's
  const double diagonal = std::sqrt(0.25 + 0.16 + 0.09);
  EXPECT_LE(static_cast<double>(near.radius), diagonal);
  EXPECT_GT(static_cast<double>(near.radius), 0.99 * diagonal);
  const auto listed = [&](int face) {
    return std::find(near.faces.begin(), near.faces.begin() + near.count, face) !=
           near.faces.begin() + near.count;
  };
  int within = 0;
  for (int f = 0; f < m.face_count(); ++f) {
    if (searcher.lower_bound(s, f) < static_cast<double>(near.radius)) {
      ++within;
      EXPECT_TRUE(listed(f)) << f;
    }
  }
  EXPECT_EQ(within, 5);
  // 0.2 along x: spent 0.2 and the reach 0.3 stay within the radius.
  const Vec3 moved = s + Vec3(0.2, 0.0, 0.0);
  const FaceHint hint{first.face, first.param};
  Contact taken, without;
  searcher.nearest_fresh(1, moved, candidates, scratch, taken, &hint, &near, 0.0);
  EXPECT_EQ(near.anchor, s);  // taken, not made again
  searcher.nearest_fresh(1, moved, candidates, scratch, without, &hint);
  EXPECT_EQ(taken.face, without.face);
  EXPECT_EQ(taken.point, without.point);
  EXPECT_EQ(taken.gap, without.gap);
  EXPECT_EQ(taken.candidates, without.candidates);
  // 0.5 along x: beyond the radius, made again.
  const Vec3 far = s + Vec3(0.5, 0.0, 0.0);
  searcher.nearest_fresh(1, far, candidates, scratch, taken, &hint, &near, 0.0);
  EXPECT_EQ(near.anchor, far);
}

TEST(Tracking, AFaceMovingOntoANodeIsFoundThoughTheNodeStayed) {
  // A sheet folded back over itself at height H: its overhang is lowered from 0.8 to 0.4 above the sheet by
  // 0.02 an increment (within rule 5's drift for lists), then dropped from 5 to 0.2 in one (beyond it). The
  // node, 0.3 above the sheet, does not move; its list (its face below) is spent by the drift of the
  // overhang's boxes, and the overhang is found once it is nearer, as fresh (gap 0.1 at H = 0.4).
  const auto folded = [](double h) {
    return testing::searched_grid_surface(
        6, 3, [h](double i, double j) { return i <= 3.0 ? Vec3(i, j, 0.0) : Vec3(6.0 - i, j, h); });
  };
  SearchOptions options;
  options.capture_distance = 1.0;
  const std::vector<long> ids = {1};
  const std::vector<Vec3> slave = {Vec3(1.5, 1.5, 0.3)};
  std::vector<double> heights;
  for (int k = 0; k <= 20; ++k) heights.push_back(0.8 - 0.02 * k);
  for (const bool drop : {false, true}) {
    SurfaceTracker tracker(options);
    int increment = 0;
    for (const double h : drop ? std::vector<double>{5.0, 0.5} : heights) {
      const mesh::SurfaceMesh m = folded(h);
      const std::vector<Vec3> normals = mesh::node_normals(m);
      const auto tracked = tracker.step(m, normals, ids, slave);
      const auto fresh = surface_search(m, normals, ids, slave, options);
      ASSERT_EQ(fresh[0].status, PairStatus::kFound);
      EXPECT_NEAR(std::abs(fresh[0].label.gap), std::min(0.3, h - 0.3), 1e-12) << h;
      expect_same(tracked, fresh, increment++);
    }
  }
}

TEST(Tracking, ANodeMovingWithinItsListFindsTheListedFaceNowNearer) {
  // A flat strip rising steeply from x = 2 (z = 2 (x - 2)). The node, 0.3 above the flat face at x = 1.6, is
  // 0.4 from the rising face's box: listed (capture 3: a budget of 0.3) but beyond the reach. At x = 1.85 it
  // has moved 0.25, within the list's radius, and the rising face is 0.268 away, nearer than the flat one:
  // its bound less the movement brings it into the reach. At x = 1.95 the list is made again.
  const mesh::SurfaceMesh m = testing::searched_grid_surface(
      4, 1, [](double i, double j) { return Vec3(i, j, 2.0 * std::max(0.0, i - 2.0)); });
  const std::vector<Vec3> normals = mesh::node_normals(m);
  SearchOptions options;
  options.capture_distance = 3.0;
  SurfaceTracker tracker(options);
  const std::vector<long> ids = {1};
  int increment = 0;
  for (const double x : {1.6, 1.85, 1.95}) {
    const std::vector<Vec3> slave = {Vec3(x, 0.5, 0.3)};
    const auto tracked = tracker.step(m, normals, ids, slave);
    const auto fresh = surface_search(m, normals, ids, slave, options);
    ASSERT_EQ(fresh[0].status, PairStatus::kFound);
    EXPECT_EQ(fresh[0].segment, x == 1.6 ? 1 : 2) << x;
    expect_same(tracked, fresh, increment++);
  }
}

TEST(Tracking, ASteadyNodeStartsFromItsExtrapolatedPoint) {
  // A node sliding at a constant velocity over one flat face: from the third increment on, its start (rule
  // 2: twice its last point less the one before) is its answer, and the certified run takes no Newton step
  // (from its last point alone it takes one). The answers are the fresh search's.
  const mesh::SurfaceMesh m =
      testing::searched_grid_surface(1, 1, [](double i, double j) { return Vec3(4.0 * i, 4.0 * j, 0.0); });
  const std::vector<Vec3> normals = mesh::node_normals(m);
  const SearchOptions options;
  SurfaceTracker tracker(options);
  const std::vector<long> ids = {1};
  std::vector<Contact> contacts;
  for (int increment = 0; increment < 5; ++increment) {
    const std::vector<Vec3> slave = {Vec3(1.0 + 0.3 * increment, 1.5 + 0.2 * increment, 0.4)};
    tracker.step(m, normals, ids, slave, contacts);
    ASSERT_EQ(contacts[0].status, PairStatus::kFound);
    EXPECT_EQ(contacts[0].iterations, increment == 0 ? 1 : increment == 1 ? 1 : 0) << increment;
    const auto fresh = surface_search(m, normals, ids, slave, options);
    EXPECT_NEAR((contacts[0].point - fresh[0].point).norm(), 0.0, kSame) << increment;
    EXPECT_NEAR(contacts[0].gap, fresh[0].label.gap, kSame) << increment;
  }
}

TEST(Tracking, ASteadyNodeOnATri6FaceStartsFromItsExtrapolatedPoint) {
  // The same on a flat tri6 face (corners (0, 0), (4, 0), (0, 4), mid-side nodes between): its parameters are
  // x / 4 and y / 4, so the extrapolated start is the answer from the third increment on. A node sliding on
  // across the hypotenuse is started from its extrapolated point moved back into the triangle, and answers
  // as fresh.
  mesh::SurfaceMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0)};
  for (int k = 0; k < 6; ++k) {
    m.node_ids.push_back(k + 1);
    m.mesh_nodes.push_back(k);
  }
  m.extra_faces = {{0, 1, 2, -1}};
  m.extra_face_midsides = {{3, 4, 5, -1}};
  m.extra_face_faces = {{0, 1}};
  m.extra_face_element_ids = {1};
  ASSERT_EQ(m.face_type(0), mesh::FaceType::kTri6);
  const std::vector<Vec3> normals;  // none: no Gregory face
  const SearchOptions options;
  for (const bool across : {false, true}) {
    SurfaceTracker tracker(options);
    const std::vector<long> ids = {1};
    std::vector<Contact> contacts;
    for (int increment = 0; increment < 8; ++increment) {
      const std::vector<Vec3> slave = {across ? Vec3(1.2 + 0.3 * increment, 1.5 + 0.3 * increment, 0.4)
                                              : Vec3(0.5 + 0.2 * increment, 0.6 + 0.15 * increment, 0.4)};
      tracker.step(m, normals, ids, slave, contacts);
      ASSERT_EQ(contacts[0].status, PairStatus::kFound);
      if (!across) {
        EXPECT_EQ(contacts[0].location, Location::kFace);
        EXPECT_EQ(contacts[0].iterations, increment <= 1 ? 1 : 0) << increment;
      }
      const auto fresh = surface_search(m, normals, ids, slave, options);
      ASSERT_EQ(fresh[0].status, PairStatus::kFound);
      EXPECT_EQ(contacts[0].location, fresh[0].location) << across << " " << increment;
      EXPECT_NEAR((contacts[0].point - fresh[0].point).norm(), 0.0, kSame) << across << " " << increment;
      EXPECT_NEAR(contacts[0].gap, fresh[0].label.gap, kSame) << across << " " << increment;
    }
  }
}

TEST(Tracking, SameResultsForAnyThreadCount) {
  const History h = slaves(800);
  std::vector<std::vector<NodeSegmentPair>> runs;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    SurfaceTracker tracker(SearchOptions{});
    std::vector<NodeSegmentPair> last;
    for (int increment = 0; increment < 5; ++increment) {
      const mesh::SurfaceMesh m = sheet(0.05 * increment);
      const std::vector<Vec3> positions = h.at(increment);
      last = tracker.step(m, mesh::node_normals(m), h.ids, positions);
    }
    runs.push_back(last);
  }
  for (std::size_t i = 0; i < runs[0].size(); ++i) {
    ASSERT_EQ(runs[0][i].segment, runs[1][i].segment);
    ASSERT_EQ(runs[0][i].label.gap, runs[1][i].label.gap);
  }
}

INSTANTIATE_TEST_SUITE_P(Surfaces, Tracking, testing::kBothSurfaces, testing::surface_name);

}  // namespace
}  // namespace contactnn::contact
