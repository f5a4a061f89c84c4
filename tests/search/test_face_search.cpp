// FaceSearch (lib/search/face_search.hpp) on tri3, tri6 and quad8 faces against the projection's closest
// point on the true face (an independent implementation: Eigen, several starts, Armijo descent), in every
// node order of a face, double and float, a query alone and in a block; FaceNetwork's canonical form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/error.hpp"
#include "face_queries.hpp"
#include "mlp/network.hpp"
#include "search/face_network.hpp"
#include "search/face_search.hpp"

namespace contactnn::search {
namespace {

using geometry::Vec3;
using testing::FaceQuery;

constexpr FaceKind kKinds[] = {FaceKind::kTri3, FaceKind::kTri6, FaceKind::kQuad8};

struct Answers {
  std::vector<double> param, gap;
  std::vector<Status> status;
  std::vector<std::int32_t> iterations;
  std::vector<Location> location;
};

template <class Real = double>
Answers run(const FaceSearch& search, const std::vector<Real>& raw, std::vector<Real> start = {}) {
  const std::size_t n = raw.size() / static_cast<std::size_t>(face_raw_columns(search.face()));
  std::vector<Real> param = start.empty() ? std::vector<Real>(2 * n) : start, gap(n);
  Answers a;
  a.status.resize(n);
  a.iterations.resize(n);
  a.location.resize(n);
  search.run<Real>(
      n, raw.data(),
      Results<Real>{param.data(), gap.data(), a.status.data(), a.iterations.data(), a.location.data()});
  a.param.assign(param.begin(), param.end());
  a.gap.assign(gap.begin(), gap.end());
  return a;
}

std::vector<FaceQuery> queries(FaceKind kind, int count, std::uint64_t seed,
                               const testing::FaceQueryOptions& o = {}) {
  std::mt19937_64 rng(seed);
  std::vector<FaceQuery> q;
  for (int i = 0; i < count; ++i) q.push_back(testing::random_face_query(kind, rng, o));
  return q;
}

std::vector<double> rows(const std::vector<FaceQuery>& q) {
  std::vector<double> raw;
  for (const FaceQuery& x : q) testing::append_row(x, raw);
  return raw;
}

double face_size(const FaceQuery& q) { return (q.nodes[1] - q.nodes[0]).norm(); }

// The safeguarded hybrid reaches the reference's point (interior slave nodes: the foot lies inside the face)
// to 1e-10 of the domain, with its status ok and the gap the reference's signed distance to 1e-10 of the face
// size. Plain Newton from the centre (no safeguard) does too wherever it answers ok; on a curved face it may
// end at another stationary point of |S - P| beyond the face, which it reports (outside, no_convergence): at
// most 1%.
TEST(FaceSearch, ConvergedMethodsReachTheReferencePointOnEveryFaceType) {
  for (const FaceKind kind : kKinds) {
    const auto q = queries(kind, 400, 11 + static_cast<int>(kind));
    const auto raw = rows(q);
    for (const char* name : {"closed_form+newton:12", "newton", "newton:12"}) {
      const bool safeguarded = Method::parse(name).is_hybrid();
      const FaceSearch search(kind, Method::parse(name));
      const Answers a = run(search, raw);
      int compared = 0, reported = 0;
      for (std::size_t i = 0; i < q.size(); ++i) {
        const projection::FaceClosestPoint ref = testing::reference_point(kind, q[i]);
        ASSERT_EQ(ref.status, Status::kOk);
        if (ref.location != Location::kFace) continue;  // a curved face's nearest point on an edge
        ++compared;
        SCOPED_TRACE(std::string(to_string(kind)) + " " + name + " query " + std::to_string(i));
        if (!safeguarded && a.status[i] != Status::kOk) {
          ++reported;
          continue;
        }
        EXPECT_EQ(a.status[i], Status::kOk);
        EXPECT_NEAR(a.param[2 * i], ref.param[0], 1e-10);
        EXPECT_NEAR(a.param[2 * i + 1], ref.param[1], 1e-10);
        const double signed_distance =
            (q[i].slave - ref.point).dot(ref.normal) < 0.0 ? -ref.distance : ref.distance;
        EXPECT_NEAR(a.gap[i], signed_distance, 1e-10 * face_size(q[i]));
      }
      EXPECT_GT(compared, 350) << to_string(kind) << " " << name;
      EXPECT_LE(reported, compared / 100) << to_string(kind) << " " << name;
    }
  }
}

// tri3: the closed form is exact, and with the whole face it is the triangle's closest point everywhere.
TEST(FaceSearch, Tri3ClosedFormIsTheTrianglesClosestPointInsideAndOnItsBoundary) {
  testing::FaceQueryOptions far;
  far.foot_inset = -0.6;  // feet up to 0.6 beyond the edges: answers on edges and vertices
  const auto q = queries(FaceKind::kTri3, 600, 3, far);
  SearchOptions whole;
  whole.closest_point_on_face = true;
  const FaceSearch search(FaceKind::kTri3, Method::parse("closed_form"), whole);
  const Answers a = run(search, rows(q));
  int on_boundary = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const projection::FaceClosestPoint ref = testing::reference_point(FaceKind::kTri3, q[i]);
    SCOPED_TRACE("query " + std::to_string(i));
    EXPECT_EQ(a.status[i], Status::kOk);
    EXPECT_EQ(a.location[i], ref.location);
    EXPECT_NEAR(a.param[2 * i], ref.param[0], 1e-12);
    EXPECT_NEAR(a.param[2 * i + 1], ref.param[1], 1e-12);
    EXPECT_NEAR(std::fabs(a.gap[i]), ref.distance, 1e-12 * face_size(q[i]));
    on_boundary += ref.location != Location::kFace;
  }
  EXPECT_GT(on_boundary, 150);
}

// tri6 and quad8 with the whole face: answers beyond an edge go to the curved edge's nearest point, as the
// reference's.
TEST(FaceSearch, QuadraticFacesWholeFaceAnswersAreTheReferencesOnEdgesAndVertices) {
  testing::FaceQueryOptions far;
  far.foot_inset = -0.3;
  for (const FaceKind kind : {FaceKind::kTri6, FaceKind::kQuad8}) {
    const auto q = queries(kind, 300, 5, far);
    SearchOptions whole;
    whole.closest_point_on_face = true;
    const FaceSearch search(kind, Method::parse("closed_form+newton:12"), whole);
    const Answers a = run(search, rows(q));
    int boundary = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const projection::FaceClosestPoint ref = testing::reference_point(kind, q[i]);
      if (ref.location == Location::kFace && a.location[i] != Location::kFace) continue;  // counted below
      SCOPED_TRACE(std::string(to_string(kind)) + " query " + std::to_string(i));
      EXPECT_EQ(a.status[i], Status::kOk);
      EXPECT_EQ(a.location[i], ref.location);
      EXPECT_NEAR(std::fabs(a.gap[i]), ref.distance, 1e-9 * face_size(q[i]));
      boundary += ref.location != Location::kFace;
    }
    EXPECT_GT(boundary, 60) << to_string(kind);
  }
}

// The same face in each of its node orders (6 for triangles, 8 for quads; mid-side nodes with their edges)
// gives the same point, status and gap.
TEST(FaceSearch, EveryNodeOrderOfAFaceGivesTheSamePointStatusAndGap) {
  for (const FaceKind kind : kKinds) {
    const auto q = queries(kind, 100, 21);
    const auto orders = testing::face_orders(kind);
    for (const char* name : {"newton", "closed_form", "closed_form+newton:3", "newton:5"}) {
      const FaceSearch search(kind, Method::parse(name));
      std::vector<Answers> by_order;
      std::vector<std::vector<FaceQuery>> permuted(orders.size());
      for (std::size_t k = 0; k < orders.size(); ++k) {
        for (const FaceQuery& x : q) {
          FaceQuery y = x;
          for (std::size_t i = 0; i < orders[k].size(); ++i)
            y.nodes[i] = x.nodes[static_cast<std::size_t>(orders[k][i])];
          permuted[k].push_back(y);
        }
        by_order.push_back(run(search, rows(permuted[k])));
      }
      for (std::size_t i = 0; i < q.size(); ++i) {
        const Vec3 p0 = testing::face_point(kind, permuted[0][i].nodes, by_order[0].param[2 * i],
                                            by_order[0].param[2 * i + 1])
                            .position;
        for (std::size_t k = 1; k < orders.size(); ++k) {
          SCOPED_TRACE(std::string(to_string(kind)) + " " + name + " order " + std::to_string(k) + " query " +
                       std::to_string(i));
          const Answers& a = by_order[k];
          ASSERT_EQ(a.status[i], by_order[0].status[i]);
          const Vec3 p =
              testing::face_point(kind, permuted[k][i].nodes, a.param[2 * i], a.param[2 * i + 1]).position;
          // A point, not its coordinates: each order has its own parametrisation. The mirrored orders reverse
          // the normal, and with it the gap's sign.
          EXPECT_LT((p - p0).norm(), 1e-10 * face_size(q[i]));
          EXPECT_NEAR(std::fabs(a.gap[i]), std::fabs(by_order[0].gap[i]), 1e-12 * face_size(q[i]));
          if (k < orders.size() / 2) {
            EXPECT_NEAR(a.gap[i], by_order[0].gap[i], 1e-12 * face_size(q[i]));
          }
        }
      }
    }
  }
}

// A query's result does not depend on its batch: alone (the one-lane kernel) and in a block, the same bits;
// and float inputs give the double answer to float precision.
TEST(FaceSearch, AQueryAloneAndInABlockGivesTheSameBitsAndFloatFollowsDouble) {
  for (const FaceKind kind : kKinds) {
    const auto q = queries(kind, 70, 31);
    const auto raw = rows(q);
    const auto columns = static_cast<std::size_t>(face_raw_columns(kind));
    for (const char* name : {"newton", "closed_form+newton:2", "newton:3", "closed_form"}) {
      const FaceSearch search(kind, Method::parse(name));
      const Answers all = run(search, raw);
      for (std::size_t i = 0; i < q.size(); ++i) {
        const std::vector<double> one(raw.begin() + static_cast<std::ptrdiff_t>(i * columns),
                                      raw.begin() + static_cast<std::ptrdiff_t>((i + 1) * columns));
        const Answers a = run(search, one);
        EXPECT_EQ(a.param[0], all.param[2 * i]) << to_string(kind) << " " << name << " " << i;
        EXPECT_EQ(a.param[1], all.param[2 * i + 1]) << to_string(kind) << " " << name << " " << i;
        EXPECT_EQ(a.gap[0], all.gap[i]) << to_string(kind) << " " << name << " " << i;
        EXPECT_EQ(a.status[0], all.status[i]);
      }
      // Float: the rows placed near the origin (float has no room for the placement's offsets).
      testing::FaceQueryOptions local;
      local.place = false;
      const auto near = queries(kind, 70, 32, local);
      const auto raw_d = rows(near);
      const std::vector<float> raw_f(raw_d.begin(), raw_d.end());
      const Answers d = run(search, raw_d);
      const Answers f = run<float>(search, raw_f);
      for (std::size_t i = 0; i < near.size(); ++i) {
        if (d.status[i] != Status::kOk) continue;
        EXPECT_EQ(f.status[i], d.status[i]) << to_string(kind) << " " << name << " " << i;
        EXPECT_NEAR(f.param[2 * i], d.param[2 * i], 1e-4);
        EXPECT_NEAR(f.param[2 * i + 1], d.param[2 * i + 1], 1e-4);
        EXPECT_NEAR(f.gap[i], d.gap[i], 1e-4);
      }
    }
  }
}

// The corner facet's closed form is exact where the face is its corner facet (mid-side nodes at their edges'
// midpoints: a flat triangle, a bilinear quad) and an estimate otherwise, which a few Newton steps refine.
TEST(FaceSearch, TheCornerClosedFormIsExactOnStraightEdgedFacesAndAStartOnCurvedOnes) {
  for (const FaceKind kind : {FaceKind::kTri6, FaceKind::kQuad8}) {
    testing::FaceQueryOptions straight;
    straight.curvature = 0.0;
    straight.flat = true;  // a warped bilinear quad is not flat: its closed form is exact only where it is
    const auto q = queries(kind, 200, 41, straight);
    const Answers a = run(FaceSearch(kind, Method::parse("closed_form")), rows(q));
    double worst = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const projection::FaceClosestPoint ref = testing::reference_point(kind, q[i]);
      if (ref.location != Location::kFace) continue;
      worst = std::max(
          {worst, std::fabs(a.param[2 * i] - ref.param[0]), std::fabs(a.param[2 * i + 1] - ref.param[1])});
    }
    EXPECT_LT(worst, 1e-9) << to_string(kind);
    const auto curved = queries(kind, 200, 42);
    const Answers c = run(FaceSearch(kind, Method::parse("closed_form")), rows(curved));
    double off = 0.0;
    for (std::size_t i = 0; i < curved.size(); ++i) {
      const projection::FaceClosestPoint ref = testing::reference_point(kind, curved[i]);
      off = std::max(off, std::fabs(c.param[2 * i] - ref.param[0]));
    }
    EXPECT_GT(off, 1e-3) << to_string(kind) << ": curved faces are not their corner facets";
  }
}

TEST(FaceSearch, StatusesForNonFiniteCollapsedAndOutsideQueries) {
  for (const FaceKind kind : kKinds) {
    std::mt19937_64 rng(51);
    testing::FaceQueryOptions local;
    local.place = false;
    FaceQuery good = testing::random_face_query(kind, rng, local);
    FaceQuery nan = good;
    nan.slave.x() = std::numeric_limits<double>::quiet_NaN();
    FaceQuery collapsed = good;
    collapsed.nodes[1] = collapsed.nodes[0];
    FaceQuery beyond = good;  // far beyond corner B, in the face's plane direction
    beyond.slave = good.nodes[1] + 3.0 * (good.nodes[1] - good.nodes[0]);
    for (const char* name : {"newton", "newton:5", "closed_form", "closed_form+newton:5"}) {
      const Answers a = run(FaceSearch(kind, Method::parse(name)), rows({good, nan, collapsed, beyond}));
      SCOPED_TRACE(std::string(to_string(kind)) + " " + name);
      EXPECT_EQ(a.status[0], Status::kOk);
      EXPECT_EQ(a.status[1], Status::kInvalid);
      EXPECT_EQ(a.status[2], Status::kDegenerate);
      EXPECT_NE(a.status[3], Status::kOk);
      for (const double x : a.param) EXPECT_TRUE(std::isfinite(x));
      for (const double x : a.gap) EXPECT_TRUE(std::isfinite(x));
      EXPECT_EQ(a.gap[1], 0.0);
      EXPECT_EQ(a.gap[2], 0.0);
    }
  }
}

TEST(FaceSearch, RefusesMethodsAFaceTypeDoesNotTake) {
  EXPECT_THROW(FaceSearch(FaceKind::kTri3, Method::parse("network")), contactnn::InvalidArgument);
  EXPECT_THROW(FaceSearch(FaceKind::kQuad8, Method::parse("network")),
               contactnn::InvalidArgument);  // no network
  EXPECT_THROW(FaceSearch(FaceKind::kTri6, Method::parse("four_triangles")), contactnn::InvalidArgument);
  EXPECT_EQ(face_kind_from_string("quad8"), FaceKind::kQuad8);
  EXPECT_THROW((void)face_kind_from_string("quad9"), contactnn::InvalidArgument);
  // A network of the other face type.
  mlp::Scaling scaling;
  scaling.input_min.assign(14, -1.0);
  scaling.input_max.assign(14, 1.0);
  scaling.output_min.assign(2, 0.0);
  scaling.output_max.assign(2, 1.0);
  mlp::Network<float> net({14, 4, 2}, 1.0, scaling);
  const FaceNetwork tri6(FaceKind::kTri6, net, std::vector<double>(14, -1.0), std::vector<double>(14, 1.0));
  EXPECT_THROW(FaceSearch(FaceKind::kQuad8, Method::parse("network"), {}, &tri6), contactnn::InvalidArgument);
  EXPECT_THROW(
      FaceNetwork(FaceKind::kQuad8, net, std::vector<double>(20, -1.0), std::vector<double>(20, 1.0)),
      contactnn::InvalidArgument);
}

// The canonical form (FaceNetwork's input): the same features in every node order of a face (the nearest
// corner first, then the mirror by edge length), and the parameters mapped there and back unchanged.
TEST(FaceNetwork, TheCanonicalFormIsTheSameInEveryNodeOrderAndMapsParametersBothWays) {
  for (const FaceKind kind : {FaceKind::kTri6, FaceKind::kQuad8}) {
    const auto q = queries(kind, 200, 61);
    const auto orders = testing::face_orders(kind);
    const int nf = face_feature_count(kind);
    for (std::size_t i = 0; i < q.size(); ++i) {
      std::vector<double> f0(static_cast<std::size_t>(nf));
      int order0[4];
      double base0[2];
      ASSERT_TRUE(face_canonical_form(kind, rows({q[i]}).data(), f0.data(), order0, base0));
      for (const auto& order : orders) {
        FaceQuery y = q[i];
        for (std::size_t k = 0; k < order.size(); ++k)
          y.nodes[k] = q[i].nodes[static_cast<std::size_t>(order[k])];
        std::vector<double> f(static_cast<std::size_t>(nf));
        int o[4];
        double base[2];
        ASSERT_TRUE(face_canonical_form(kind, rows({y}).data(), f.data(), o, base));
        EXPECT_NEAR(base[0], base0[0], 1e-9);
        EXPECT_NEAR(base[1], base0[1], 1e-9);
        for (int k = 0; k < nf; ++k)
          EXPECT_NEAR(f[static_cast<std::size_t>(k)], f0[static_cast<std::size_t>(k)], 1e-9) << k;
        // The foot in this order's parameters, to canonical: the canonical foot of the first order.
        double s = q[i].foot[0], t = q[i].foot[1];
        face_param_to_canonical(kind, order0, s, t);
        // The same point's parameters in order y: found by mapping canonical back through y's order.
        double u = s, v = t;
        face_param_to_caller(kind, o, u, v);
        const Vec3 p = testing::face_point(kind, y.nodes, u, v).position;
        const Vec3 p0 = testing::face_point(kind, q[i].nodes, q[i].foot[0], q[i].foot[1]).position;
        EXPECT_LT((p - p0).norm(), 1e-9 * face_size(q[i]));
        double back_s = u, back_t = v;
        face_param_to_canonical(kind, o, back_s, back_t);
        EXPECT_NEAR(back_s, s, 1e-14);
        EXPECT_NEAR(back_t, t, 1e-14);
      }
    }
  }
}

// A network's estimate is a point of the face that does not depend on the caller's node order, whatever its
// weights (here random ones): it sees only the canonical form.
TEST(FaceNetwork, ANetworksEstimateIsTheSamePointInEveryNodeOrder) {
  for (const FaceKind kind : {FaceKind::kTri6, FaceKind::kQuad8}) {
    const int nf = face_feature_count(kind);
    mlp::Scaling scaling;
    scaling.input_min.assign(static_cast<std::size_t>(nf), -2.0);
    scaling.input_max.assign(static_cast<std::size_t>(nf), 2.0);
    scaling.output_min.assign(2, kind == FaceKind::kQuad8 ? -1.0 : 0.0);
    scaling.output_max.assign(2, 1.0);
    mlp::Network<float> net({nf, 16, 2}, 1.0, scaling);
    net.initialize(7);
    const FaceNetwork model(kind, net, std::vector<double>(static_cast<std::size_t>(nf), -5.0),
                            std::vector<double>(static_cast<std::size_t>(nf), 5.0));
    const FaceSearch search(kind, Method::parse("network"), {}, &model);
    const auto q = queries(kind, 40, 71);
    const auto orders = testing::face_orders(kind);
    std::vector<Vec3> first;
    for (std::size_t k = 0; k < orders.size(); ++k) {
      std::vector<FaceQuery> permuted;
      for (const FaceQuery& x : q) {
        FaceQuery y = x;
        for (std::size_t i = 0; i < orders[k].size(); ++i)
          y.nodes[i] = x.nodes[static_cast<std::size_t>(orders[k][i])];
        permuted.push_back(y);
      }
      const Answers a = run(search, rows(permuted));
      for (std::size_t i = 0; i < q.size(); ++i) {
        ASSERT_EQ(a.status[i], Status::kOk);
        const Vec3 p =
            testing::face_point(kind, permuted[i].nodes, a.param[2 * i], a.param[2 * i + 1]).position;
        if (k == 0) {
          first.push_back(p);
        } else {
          EXPECT_LT((p - first[i]).norm(), 1e-5 * face_size(q[i]))
              << to_string(kind) << " order " << k << " query " << i;
        }
      }
    }
  }
}

}  // namespace
}  // namespace contactnn::search

namespace contactnn::search {
namespace {

// The extremes, as the quad4 search's hostile set (issue 31): a face at any scale from 1e-200 to 1e200 gives
// the unit face's answer (every conversion a power of two is exact); a slave node 1e3 to 1e15 face sizes away
// gets a finite answer whose |gap| is never more than its distance to the face's nearest node (FaceSearch
// computes in the caller's node order, so which stationary point of the extrapolated surface a far slave's
// Newton reaches, and its status, may differ between node orders: docs/library.md "Faces"); nothing
// non-finite comes out of any input.
TEST(FaceSearchExtremes, ScalesFarSlavesAndNonFiniteInputs) {
  for (const FaceKind kind : kKinds) {
    testing::FaceQueryOptions local;
    local.place = false;
    const auto q = queries(kind, 40, 81, local);
    for (const char* name : {"newton", "newton:3", "closed_form", "closed_form+newton:2"}) {
      const FaceSearch search(kind, Method::parse(name));
      const Answers unit = run(search, rows(q));
      for (const double scale : {0x1p-660, 0x1p-300, 0x1p300, 0x1p660}) {  // about 1e-200 .. 1e200
        std::vector<FaceQuery> scaled = q;
        for (FaceQuery& x : scaled) {
          for (Vec3& p : x.nodes) p *= scale;
          x.slave *= scale;
        }
        const Answers a = run(search, rows(scaled));
        for (std::size_t i = 0; i < q.size(); ++i) {
          SCOPED_TRACE(std::string(to_string(kind)) + " " + name + " scale " +
                       std::to_string(std::log2(scale)));
          EXPECT_EQ(a.status[i], unit.status[i]);
          EXPECT_EQ(a.param[2 * i], unit.param[2 * i]);
          EXPECT_EQ(a.param[2 * i + 1], unit.param[2 * i + 1]);
          EXPECT_EQ(a.gap[i], unit.gap[i] * scale);
        }
      }
      // Far slaves, in every node order.
      const auto orders = testing::face_orders(kind);
      for (const double far : {1e3, 1e6, 1e10, 1e15}) {
        std::vector<Answers> by_order;
        std::vector<std::vector<FaceQuery>> permuted(orders.size());
        for (std::size_t k = 0; k < orders.size(); ++k) {
          for (const FaceQuery& x : q) {
            FaceQuery y = x;
            const Vec3 n = (x.nodes[1] - x.nodes[0]).cross(x.nodes[2] - x.nodes[0]).normalized();
            y.slave = x.slave + far * (n + Vec3(0.3, -0.2, 0.1));
            for (std::size_t j = 0; j < orders[k].size(); ++j)
              y.nodes[j] = x.nodes[static_cast<std::size_t>(orders[k][j])];
            permuted[k].push_back(y);
          }
          by_order.push_back(run(search, rows(permuted[k])));
        }
        for (std::size_t i = 0; i < q.size(); ++i) {
          SCOPED_TRACE(std::string(to_string(kind)) + " " + name + " far " + std::to_string(far) + " query " +
                       std::to_string(i));
          double nearest = std::numeric_limits<double>::infinity();
          for (const Vec3& p : permuted[0][i].nodes)
            nearest = std::min(nearest, (permuted[0][i].slave - p).norm());
          for (std::size_t k = 0; k < orders.size(); ++k) {
            const Answers& a = by_order[k];
            EXPECT_TRUE(std::isfinite(a.param[2 * i]) && std::isfinite(a.param[2 * i + 1]) &&
                        std::isfinite(a.gap[i]));
            EXPECT_LE(std::fabs(a.gap[i]), nearest * (1.0 + 1e-12)) << "order " << k;
          }
        }
      }
    }
    // Non-finite values anywhere: invalid, finite outputs, in float and double.
    std::vector<double> raw = rows({q[0]});
    const auto columns = raw.size();
    for (std::size_t k = 0; k < columns; ++k) {
      for (const double bad :
           {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        std::vector<double> r = raw;
        r[k] = bad;
        for (const char* name : {"newton", "closed_form+newton:3", "newton:2"}) {
          const Answers a = run(FaceSearch(kind, Method::parse(name)), r);
          EXPECT_EQ(a.status[0], Status::kInvalid) << to_string(kind) << " " << name << " value " << k;
          EXPECT_TRUE(std::isfinite(a.param[0]) && std::isfinite(a.param[1]) && a.gap[0] == 0.0);
          const std::vector<float> rf(r.begin(), r.end());
          const Answers f = run<float>(FaceSearch(kind, Method::parse(name)), rf);
          EXPECT_EQ(f.status[0], Status::kInvalid);
        }
      }
    }
  }
}

// A face far from the origin gives the answer of the same face at the origin to the rounding of its
// coordinates there (issue 39: the boundary step of the whole face, computed in world coordinates, was 1e-5
// off in the parameters 2e6 face sizes away). The kernels compute relative to S, the boundary step relative
// to the face's first node: the translated face differs from the untranslated one by the rounding of its
// coordinates, eps |offset|, and the answers by a few of those (well-conditioned queries: slave nodes within
// 0.1 of the face size, mid-side nodes within 0.1 of their chords). Offsets up to 1e8 face sizes in random
// directions, faces of size 1e-3 to 1e3; interior feet, and feet outside the face with the whole face.
TEST(FaceSearchTranslation, AFaceFarFromTheOriginGivesItsAnswerThereToTheRoundingOfTheOffset) {
  std::mt19937_64 rng(91);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const FaceKind kind : kKinds) {
    for (const bool outside : {false, true}) {
      testing::FaceQueryOptions o;
      o.place = false;
      o.foot_inset = outside ? -0.3 : 0.05;
      const auto q = queries(kind, 60, 92, o);
      SearchOptions options;
      options.closest_point_on_face = outside;
      // Plain Newton from the centre is not asked to a slave beyond the face: it reaches a stationary point
      // of the extrapolated surface, which a few ulps of the input may change (FaceSearchExtremes).
      const std::vector<const char*> methods =
          outside ? std::vector<const char*>{"closed_form+newton:3", "closed_form"}
                  : std::vector<const char*>{"newton", "newton:5", "closed_form+newton:3", "closed_form"};
      for (const char* name : methods) {
        const FaceSearch search(kind, Method::parse(name), options);
        for (const double size : {1e-3, 1.0, 1e3}) {
          std::vector<FaceQuery> here = q;
          for (FaceQuery& x : here) {
            for (Vec3& p : x.nodes) p *= size;
            x.slave *= size;
          }
          const Answers origin = run(search, rows(here));
          for (const double offset : {1e2, 1e4, 2e6, 1e8}) {
            std::vector<FaceQuery> far = here;
            std::vector<double> rounding(q.size());
            for (std::size_t i = 0; i < q.size(); ++i) {
              const Vec3 shift = offset * size * Vec3(unit(rng), unit(rng), unit(rng));
              for (Vec3& p : far[i].nodes) p += shift;
              far[i].slave += shift;
              // eps |offset|, with the face's own size (the untranslated answer's rounding).
              rounding[i] =
                  std::numeric_limits<double>::epsilon() * (shift.lpNorm<Eigen::Infinity>() + 4.0 * size);
            }
            const Answers a = run(search, rows(far));
            for (std::size_t i = 0; i < q.size(); ++i) {
              SCOPED_TRACE(std::string(to_string(kind)) + " " + name + (outside ? " (whole face)" : "") +
                           " size " + std::to_string(size) + " offset " + std::to_string(offset) + " query " +
                           std::to_string(i));
              EXPECT_EQ(a.status[i], origin.status[i]);
              EXPECT_NEAR(a.param[2 * i], origin.param[2 * i], 8.0 * rounding[i] / size);
              EXPECT_NEAR(a.param[2 * i + 1], origin.param[2 * i + 1], 8.0 * rounding[i] / size);
              EXPECT_NEAR(a.gap[i], origin.gap[i], 8.0 * rounding[i]);
            }
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace contactnn::search
