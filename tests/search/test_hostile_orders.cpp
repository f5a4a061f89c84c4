// lib/search on hostile configurations in all 8 node orders (SPEC 4): folded segments (C inside the triangle
// ABD, C reflex behind A), slave nodes 1e6 to 1e15 element sizes away, nearly collinear and nearly collapsed
// segments, configurations at 1e+-100 and 1e+-300 and far from the origin, beside random ones of the paper's
// domains. For every method on both surfaces, double and float, in a block and one query at a time: the
// status, the gap (to 1e-12 of the segment size), the point (mapped to one node order) and the steps are the
// same in every node order (gap and point to the bit on a bilinear facet, but for a network's start); no
// output is NaN; no gap exceeds the distance to the segment's nearest node. Where the labels call a fold
// degenerate, so do the methods that converge there. A stalled refinement stops.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/symmetry.hpp"
#include "dataset/labeller.hpp"
#include "search/local_search.hpp"
#include "search/random_queries.hpp"
#include "search/shipped_networks.hpp"

namespace contactnn::search {
namespace {

using geometry::Configuration;
using geometry::Vec3;

constexpr SurfaceKind kBilinear = SurfaceKind::kBilinear;
constexpr SurfaceKind kGregory = SurfaceKind::kGregory;

/// `c` given in the node order `order` (canonical node i becomes the caller's node order.caller_node(i)).
Configuration relabel(const Configuration& c, const SquareSymmetry& order) {
  Configuration r = c;
  for (int k = 0; k < 4; ++k) {
    const auto to = static_cast<std::size_t>(order.caller_node(k));
    r.nodes[to] = c.nodes[static_cast<std::size_t>(k)];
    r.normals[to] = c.normals[static_cast<std::size_t>(k)];
  }
  return r;
}

/// One hostile configuration: a name for the messages, and what the test knows of it.
struct Hostile {
  std::string name;
  Configuration config;
  bool fold = false;  ///< S lies beyond the image of the fold of a folded segment
};

std::array<Vec3, 4> plane_normals() {
  std::array<Vec3, 4> n;
  n.fill(Vec3(0, 0, 1));
  return n;
}

std::string named(const std::string& what, double x) {
  std::ostringstream o;
  o << what << ' ' << x;
  return o.str();
}

/// The hostile set: every configuration for both surfaces (node normals: the segment's plane normal, tilted).
std::vector<Hostile> hostile_set() {
  std::vector<Hostile> set;
  const std::array<Vec3, 4> up = plane_normals();
  const std::array<Vec3, 4> tilted = {Vec3(0.05, -0.03, 1), Vec3(-0.02, 0.06, 1), Vec3(-0.1, 0.02, 1),
                                      Vec3(0.04, 0.05, 1)};
  // Folded segments. A dart (C inside the triangle ABD) and C reflex behind A: their bilinear map folds over
  // itself inside the domain, and a slave node beyond the image of the fold has its nearest point on the
  // fold, where the normal vanishes (the labels: degenerate). Elsewhere over them the labels project.
  const std::array<Vec3, 4> dart = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.3, 0.3, 0), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> reflex = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(-0.3, -0.3, 0), Vec3(0, 1, 0)};
  set.push_back({"dart, S beyond the fold", {dart, Vec3(0.5, 0.3, 0.2), up}, true});
  set.push_back({"dart, S beyond the fold, below", {dart, Vec3(0.5, 0.3, -0.2), up}, true});
  set.push_back({"dart, S over the fold's sheets", {dart, Vec3(0.2, 0.2, 0.2), up}, false});
  set.push_back({"dart, S over the other sheet", {dart, Vec3(0.1, 0.1, 0.2), up}, false});
  set.push_back({"reflex C, S beyond the fold", {reflex, Vec3(0.2, 0.2, 0.2), up}, true});
  set.push_back({"reflex C, S beyond the fold, below", {reflex, Vec3(0.2, 0.2, -0.2), up}, true});
  set.push_back({"dart, tilted normals", {dart, Vec3(0.5, 0.3, 0.2), tilted}, false});
  // Slave nodes far away: 1e6 to 1e15 element sizes, along the normal, sideways and in between.
  const std::array<Vec3, 4> warped = {Vec3(0, 0, 0), Vec3(1, 0, 0.05), Vec3(1.1, 0.9, -0.05),
                                      Vec3(0.1, 1, 0.1)};
  for (const double d : {1e6, 1.7e6, 1e9, 1e12, 1e15}) {
    for (const Vec3& dir : {Vec3(0.3, 0.2, 1), Vec3(1, 0.4, 0.2), Vec3(-0.7, -0.6, 0.3), Vec3(0, 0, -1)}) {
      set.push_back({named("far", d), {warped, Vec3(0.5, 0.5, 0) + d * dir.normalized(), tilted}, false});
    }
  }
  // Nearly collinear and nearly collapsed segments, just short of the degeneracy thresholds.
  const Vec3 s(0.3, 0.4, 0.2);
  for (const double h : {1e-3, 1e-6, 1e-9}) {
    set.push_back(
        {named("sliver", h), {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, h, 0), Vec3(0, h, 0)}, s, up}, false});
    set.push_back(
        {named("nearly collinear", h),
         {{Vec3(0, 0, 0), Vec3(1, h, 0), Vec3(2, 0, 0.5 * h), Vec3(3, h, h)}, Vec3(1.5, 0.2, 0.1), up},
         false});
  }
  set.push_back({"C and D 1e-9 apart",
                 {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1 - 1e-9, 1, 0)}, s, up},
                 false});
  set.push_back({"0.1 degree corner",
                 {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0.0017, 0), Vec3(0.99, 0.0017, 0)}, s, up},
                 false});
  set.push_back(
      {"straight angle at B", {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)}, s, up}, false});
  set.push_back({"S on a node", {warped, warped[2], tilted}, false});
  set.push_back({"S over the centre of a square",
                 {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, Vec3(0.5, 0.5, 0.25), up},
                 false});
  // Extreme scales and positions.
  const Configuration unit{warped, Vec3(0.4, 0.7, 0.3), tilted};
  for (const double scale : {1e-300, 1e-100, 1e100, 1e300}) {
    Configuration c = unit;
    for (Vec3& x : c.nodes) x *= scale;
    c.slave *= scale;
    set.push_back({named("scale", scale), c, false});
  }
  Configuration shifted = unit;
  for (Vec3& x : shifted.nodes) x += Vec3(1e8, -3e8, 2e8);
  shifted.slave += Vec3(1e8, -3e8, 2e8);
  set.push_back({"1e8 from the origin", shifted, false});
  // Ordinary configurations of both paper domains, placed at random.
  for (const SurfaceKind kind : {kBilinear, kGregory}) {
    const std::vector<double> raw = testing::random_queries(kind, 16, kind == kBilinear ? 71 : 72);
    for (std::size_t i = 0; i < 16; ++i)
      set.push_back({"random", testing::configuration_of(raw.data(), kind, i), false});
  }
  return set;
}

/// The results of one method on one query list, owned.
template <class Real>
struct Outputs {
  std::vector<Real> param, gap;
  std::vector<Status> status;
  std::vector<std::int32_t> iterations;
};

/// `search` on `raw`, all at once (one_at_a_time false) or one query per call (the one-lane kernel). `start`:
/// param on input (start+newton:K).
template <class Real>
Outputs<Real> run(const LocalSearch& search, const std::vector<Real>& raw, const std::vector<Real>& start,
                  bool one_at_a_time) {
  const std::size_t columns = static_cast<std::size_t>(LocalSearch::raw_columns(search.surface()));
  const std::size_t n = raw.size() / columns;
  Outputs<Real> r{start, std::vector<Real>(n), std::vector<Status>(n), std::vector<std::int32_t>(n)};
  if (!one_at_a_time) {
    search.run(n, raw.data(),
               Results<Real>{r.param.data(), r.gap.data(), r.status.data(), r.iterations.data()}, 1);
    return r;
  }
  for (std::size_t i = 0; i < n; ++i) {
    search.run(
        1, raw.data() + i * columns,
        Results<Real>{r.param.data() + 2 * i, r.gap.data() + i, r.status.data() + i, r.iterations.data() + i},
        1);
  }
  return r;
}

double size_of(const Configuration& c) {
  double size = 0.0;
  for (const Vec3& x : c.nodes) {
    for (const Vec3& y : c.nodes) size = std::max(size, (x - y).stableNorm());
  }
  return size;
}

double nearest_node_distance(const Configuration& c) {
  double d = std::numeric_limits<double>::infinity();
  for (const Vec3& x : c.nodes) d = std::min(d, (x - c.slave).stableNorm());
  return d;
}

/// Every method of lib/search that depends on the node order through its arithmetic (network alone and
/// four_triangles compute in orders of their own, the canonical frame's and the triangles').
std::vector<std::string> methods() {
  return {"newton:1",
          "newton:3",
          "newton:5",
          "newton",
          "closed_form",
          "closed_form+newton:1",
          "closed_form+newton:3",
          "network+newton:1",
          "network+newton:3",
          "start",
          "start+newton:3",
          "start+newton:20"};
}

/// The hostile set in all 8 node orders, for `kind` and `Real`, through each method: the same status, gap,
/// steps and point (in the first order's coordinates) in every order; the same bits in a block and alone;
/// finite outputs; no gap beyond the nearest node's distance.
template <class Real>
void expect_the_same_in_every_node_order(SurfaceKind kind) {
  const std::vector<Hostile> set = hostile_set();
  const std::array<SquareSymmetry, 8> orders = all_square_symmetries();
  const double centre = kind == kGregory ? 0.5 : 0.0;
  std::vector<Real> raw, start;
  std::vector<double> raw_d;
  for (const Hostile& h : set) {
    for (const SquareSymmetry& order : orders) {
      const std::size_t before = raw_d.size();
      testing::append_raw(relabel(h.config, order), kind, raw_d);
      for (std::size_t k = before; k < raw_d.size(); ++k) raw.push_back(static_cast<Real>(raw_d[k]));
      // start+newton:K: the same point in every order, exactly (dyadic: its reflections are exact in float).
      const double half = kind == kGregory ? 0.5 : 1.0;
      const std::array<double, 2> p = order.to_caller({centre + 0.25 * half, centre - 0.125 * half}, kind);
      start.push_back(static_cast<Real>(p[0]));
      start.push_back(static_cast<Real>(p[1]));
    }
  }
  const auto& trained = testing::shipped(kind == kGregory ? "gregory-48.h5" : "bilinear-8.h5");
  const NetworkModel model(trained.network, trained.domain);
  int checked = 0;
  for (const std::string& name : methods()) {
    SCOPED_TRACE(name);
    const LocalSearch search(kind, Method::parse(name), {}, &model);
    const Outputs<Real> block = run(search, raw, start, false);
    const Outputs<Real> alone = run(search, raw, start, true);
    for (std::size_t h = 0; h < set.size(); ++h) {
      const Configuration& c = set[h].config;
      const double size = size_of(c);
      const double reach = nearest_node_distance(c);
      for (std::size_t k = 0; k < 8; ++k) {
        const std::size_t i = 8 * h + k;
        const std::string where = set[h].name + ", order " + std::to_string(k);
        ASSERT_EQ(alone.status[i], block.status[i]) << where;
        ASSERT_EQ(alone.param[2 * i], block.param[2 * i]) << where;
        ASSERT_EQ(alone.param[2 * i + 1], block.param[2 * i + 1]) << where;
        ASSERT_EQ(alone.gap[i], block.gap[i]) << where;
        ASSERT_TRUE(std::isfinite(block.param[2 * i]) && std::isfinite(block.param[2 * i + 1]) &&
                    std::isfinite(block.gap[i]))
            << where;
        // No gap beyond the nearest node (in the input's own rounding for float).
        EXPECT_LE(std::abs(static_cast<double>(block.gap[i])),
                  reach * (1.0 + (sizeof(Real) == 4 ? 1e-6 : 1e-12)))
            << where;
        const std::size_t first = 8 * h;
        EXPECT_EQ(block.status[i], block.status[first]) << where;
        EXPECT_EQ(block.iterations[i], block.iterations[first]) << where;
        // The gap along the caller's own normal: its sign follows the orientation (the mirror reverses it).
        // On a bilinear facet the same bits, from the same start: its arithmetic is the same in every order
        // but for exact changes of sign (surface_block.hpp, LaneSwap). (A network's estimate, the hybrids'
        // start, is the same in every order to its own rounding only.)
        const bool exact = kind == kBilinear && name.rfind("network", 0) != 0;
        const double gap = orders[k].orientation() * static_cast<double>(block.gap[i]);
        const double gap_tol = exact ? 0.0 : 1e-12 * size;
        EXPECT_NEAR(gap, static_cast<double>(block.gap[first]), gap_tol) << where;
        // The point, in the first order's coordinates (exact for (xi, eta); (u, v) round in 1 - u, in the
        // output's precision), where there is one (degenerate and invalid report no point).
        const std::array<double, 2> p = orders[k].to_canonical(
            {static_cast<double>(block.param[2 * i]), static_cast<double>(block.param[2 * i + 1])}, kind);
        const bool point =
            block.status[first] != Status::kDegenerate && block.status[first] != Status::kInvalid;
        const double rounding =
            exact ? 0.0 : 1e-12 + (kind == kGregory ? 4.0 * std::numeric_limits<Real>::epsilon() : 0.0);
        for (int a = 0; a < 2 && point; ++a) {
          const double ref = static_cast<double>(block.param[2 * first + static_cast<std::size_t>(a)]);
          EXPECT_NEAR(p[static_cast<std::size_t>(a)], ref, rounding * std::max(1.0, std::abs(ref))) << where;
        }
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, static_cast<int>(methods().size() * set.size() * 8));
}

TEST(HostileOrders, BilinearDoubleGivesTheSameAnswerInEveryNodeOrder) {
  expect_the_same_in_every_node_order<double>(kBilinear);
}
TEST(HostileOrders, BilinearFloatGivesTheSameAnswerInEveryNodeOrder) {
  expect_the_same_in_every_node_order<float>(kBilinear);
}
TEST(HostileOrders, GregoryDoubleGivesTheSameAnswerInEveryNodeOrder) {
  expect_the_same_in_every_node_order<double>(kGregory);
}
TEST(HostileOrders, GregoryFloatGivesTheSameAnswerInEveryNodeOrder) {
  expect_the_same_in_every_node_order<float>(kGregory);
}

/// A slave node beyond a fold: the labels say degenerate in every node order, and so does every method that
/// converges there (they said ok, with a gap of 0, +0.2 or -0.2 by the node order and another sign in float),
/// with the gap 0.
template <class Real>
void expect_folds_degenerate(SurfaceKind kind) {
  const std::array<SquareSymmetry, 8> orders = all_square_symmetries();
  const auto& trained = testing::shipped(kind == kGregory ? "gregory-48.h5" : "bilinear-8.h5");
  const NetworkModel model(trained.network, trained.domain);
  int folds = 0;
  for (const Hostile& h : hostile_set()) {
    if (!h.fold) continue;
    ++folds;
    std::vector<double> raw_d;
    for (const SquareSymmetry& order : orders) {
      const Configuration c = relabel(h.config, order);
      ASSERT_EQ(dataset::label_configuration(c, kind).status, Status::kDegenerate) << h.name;
      testing::append_raw(c, kind, raw_d);
    }
    const std::vector<Real> raw(raw_d.begin(), raw_d.end());
    for (const char* name :
         {"newton", "closed_form+newton:3", "closed_form+newton:5", "network+newton:3", "network+newton:5"}) {
      const LocalSearch search(kind, Method::parse(name), {}, &model);
      const Outputs<Real> out =
          run(search, raw, std::vector<Real>(16, static_cast<Real>(kind == kGregory ? 0.5 : 0.0)), false);
      for (std::size_t k = 0; k < 8; ++k) {
        EXPECT_EQ(out.status[k], Status::kDegenerate) << h.name << ", " << name << ", order " << k;
        EXPECT_EQ(out.gap[k], Real(0)) << h.name << ", " << name << ", order " << k;
      }
    }
  }
  EXPECT_EQ(folds, 4);
}

TEST(HostileOrders, ABilinearFoldIsDegenerateAsItsLabelInEveryNodeOrder) {
  expect_folds_degenerate<double>(kBilinear);
  expect_folds_degenerate<float>(kBilinear);
}
TEST(HostileOrders, AGregoryFoldIsDegenerateAsItsLabelInEveryNodeOrder) {
  expect_folds_degenerate<double>(kGregory);
  expect_folds_degenerate<float>(kGregory);
}

TEST(HostileOrders, TheGregoryClosedFormsGapOfAFarSlaveIsNoLargerThanItsDistance) {
  // The estimate of a slave node 1.7e6 or 1e15 element sizes away lies far beyond the segment, where the
  // patch is its cubic extrapolation: the gap there was 130 times the distance, and 2.1e44 for 1e15.
  const std::array<Vec3, 4> normals = {Vec3(0.05, -0.03, 1), Vec3(-0.02, 0.06, 1), Vec3(-0.1, 0.02, 1),
                                       Vec3(0.04, 0.05, 1)};
  const std::array<Vec3, 4> nodes = {Vec3(0, 0, 0), Vec3(1, 0, 0.05), Vec3(1.1, 0.9, -0.05),
                                     Vec3(0.1, 1, 0.1)};
  for (const double d : {1.7e6, 1e15}) {
    const Configuration c{nodes, Vec3(0.5, 0.5, 0) + d * Vec3(1, 0.4, 0.2).normalized(), normals};
    std::vector<double> raw;
    testing::append_raw(c, kGregory, raw);
    const LocalSearch search(kGregory, Method::parse("closed_form"));
    const Outputs<double> out = run(search, raw, {0.5, 0.5}, false);
    EXPECT_EQ(out.status[0], Status::kOutside) << d;
    EXPECT_LE(std::abs(out.gap[0]), nearest_node_distance(c) * (1.0 + 1e-12)) << d;
    EXPECT_GT(std::abs(out.gap[0]), 0.5 * d) << d;
  }
}

TEST(HostileOrders, AStalledRefinementStopsWhereItStands) {
  // Slave nodes far beyond a corner of a flat square, started in that corner of the bilinear box: every step
  // points out of the box in both coordinates, so the clamped iterate cannot move. start+newton:1000 stops
  // after one step (it ran all 1000) with the answer of start+newton:1: no_convergence, held on the box's
  // corner beyond the domain; a block of such lanes, and one of them beside ordinary lanes, the same.
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  std::vector<double> raw, start;
  for (int i = 0; i < 40; ++i) {
    testing::append_raw(Configuration{square, Vec3(5.0 + i, 6.0 + 0.5 * i, 0.3), plane_normals()}, kBilinear,
                        raw);
    start.insert(start.end(), {1.5, 1.5});
  }
  const std::vector<double> ordinary = testing::random_queries(kBilinear, 40, 73);
  raw.insert(raw.end(), ordinary.begin(), ordinary.end());
  start.resize(2 * 80, 0.0);
  const Outputs<double> one = run(LocalSearch(kBilinear, Method::parse("start+newton:1")), raw, start, false);
  const Outputs<double> many =
      run(LocalSearch(kBilinear, Method::parse("start+newton:1000")), raw, start, false);
  for (std::size_t i = 0; i < 40; ++i) {
    EXPECT_EQ(many.status[i], Status::kNoConvergence) << i;
    EXPECT_EQ(many.status[i], one.status[i]) << i;
    EXPECT_EQ(many.param[2 * i], 1.5) << i;
    EXPECT_EQ(many.param[2 * i + 1], 1.5) << i;
    EXPECT_EQ(many.gap[i], one.gap[i]) << i;
    EXPECT_EQ(many.iterations[i], 1) << i;
  }
}

}  // namespace
}  // namespace contactnn::search
