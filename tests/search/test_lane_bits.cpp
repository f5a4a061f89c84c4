// A query's bits do not depend on its place in the batch (README: the same bits for a query alone or in any
// batch; issue 39, failure 3). For every face type (bilinear and Gregory segments of LocalSearch; tri3, tri6,
// quad8 of FaceSearch), every method, float and double, and every kernel variant this CPU runs
// (CONTACTNN_ISA): random queries (seeded; some spoiled so that they do not converge, are degenerate or
// invalid) each run alone, at every lane of a full block (its other lanes holding other queries), and in
// tails of every length after a full block and alone; the outputs (param, gap, status, iterations, location)
// compared bit for bit.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/input_features.hpp"
#include "face_queries.hpp"
#include "geometry/domain.hpp"
#include "mlp/network.hpp"
#include "search/face_network.hpp"
#include "search/face_search.hpp"
#include "search/isa_dispatch.hpp"
#include "search/local_search.hpp"
#include "search/network_model.hpp"
#include "search/random_queries.hpp"

namespace contactnn::search {
namespace {

/// CONTACTNN_ISA set for a scope, then put back.
class ScopedIsa {
 public:
  explicit ScopedIsa(const std::string& value) {
    if (const char* old = std::getenv("CONTACTNN_ISA")) old_ = old;
    ::setenv("CONTACTNN_ISA", value.c_str(), 1);
  }
  ~ScopedIsa() {
    if (old_) {
      ::setenv("CONTACTNN_ISA", old_->c_str(), 1);
    } else {
      ::unsetenv("CONTACTNN_ISA");
    }
  }
  ScopedIsa(const ScopedIsa&) = delete;
  ScopedIsa& operator=(const ScopedIsa&) = delete;

 private:
  std::optional<std::string> old_;
};

/// One query's outputs, as bytes: param (2), gap, status, iterations, location.
template <class Real>
struct Answer {
  Real param[2];
  Real gap;
  Status status;
  std::int32_t iterations;
  Location location;
};

template <class Real>
bool same_bits(const Answer<Real>& a, const Answer<Real>& b) {
  return std::memcmp(a.param, b.param, sizeof a.param) == 0 &&
         std::memcmp(&a.gap, &b.gap, sizeof a.gap) == 0 && a.status == b.status &&
         a.iterations == b.iterations && a.location == b.location;
}

template <class Real>
std::string describe(const Answer<Real>& a) {
  std::ostringstream o;
  o.precision(17);
  o << "(" << a.param[0] << ", " << a.param[1] << ") gap " << a.gap << " " << to_string(a.status) << " "
    << a.iterations << " steps";
  return o.str();
}

/// A search under test: run(count, raw, out) on rows of `columns` values, blocks of `block` queries.
template <class Real>
struct Searcher {
  std::function<void(std::size_t, const Real*, Results<Real>)> run;
  std::size_t columns = 0;
  std::size_t block = 0;
};

/// A LocalSearch or FaceSearch (kept alive by the caller) on one thread, its rows `columns` wide.
template <class Real, class Search>
Searcher<Real> searcher_of(const Search& search, std::size_t columns) {
  Searcher<Real> s;
  s.run = [&search](std::size_t n, const Real* raw, Results<Real> out) { search.run(n, raw, out, 1); };
  s.columns = columns;
  s.block = static_cast<std::size_t>(search.block_size());
  return s;
}

/// A network's input scaling from the box [-2, 2] of `inputs` features, outputs in [lo, hi].
mlp::Scaling box_scaling(int inputs, double lo, double hi) {
  mlp::Scaling scaling;
  scaling.input_min.assign(static_cast<std::size_t>(inputs), -2.0);
  scaling.input_max.assign(static_cast<std::size_t>(inputs), 2.0);
  scaling.output_min.assign(2, lo);
  scaling.output_max.assign(2, hi);
  return scaling;
}

/// The queries `rows` of `pool` (a pool row index each) as one batch; each query's start (start+newton:K) is
/// its pool row's `starts` entry. Returns each query's answer.
template <class Real>
std::vector<Answer<Real>> run_batch(const Searcher<Real>& s, const std::vector<Real>& pool,
                                    const std::vector<Real>& starts, const std::vector<std::size_t>& rows) {
  const std::size_t n = rows.size();
  std::vector<Real> raw(n * s.columns), param(2 * n), gap(n);
  std::vector<Status> status(n);
  std::vector<std::int32_t> iterations(n);
  std::vector<Location> location(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(raw.data() + i * s.columns, pool.data() + rows[i] * s.columns, s.columns * sizeof(Real));
    param[2 * i] = starts[2 * rows[i]];
    param[2 * i + 1] = starts[2 * rows[i] + 1];
  }
  s.run(n, raw.data(),
        Results<Real>{param.data(), gap.data(), status.data(), iterations.data(), location.data()});
  std::vector<Answer<Real>> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::memset(&out[i], 0, sizeof out[i]);  // padding bytes too
    out[i].param[0] = param[2 * i];
    out[i].param[1] = param[2 * i + 1];
    out[i].gap = gap[i];
    out[i].status = status[i];
    out[i].iterations = iterations[i];
    out[i].location = location[i];
  }
  return out;
}

/// Every query of the pool alone, then at every lane of full blocks (the pool taken W at a time, each group
/// in its W rotations, so that each query sits at each lane beside other queries), then in the tails of every
/// length 1 .. W - 1, after a full block and alone. Returns the number of answers that differ from the
/// query's alone (and reports the first few).
template <class Real>
std::size_t lane_mismatches(const Searcher<Real>& s, const std::vector<Real>& pool,
                            const std::vector<Real>& starts, const std::string& what, bool to_convergence) {
  const std::size_t count = pool.size() / s.columns, w = s.block;
  std::vector<Answer<Real>> alone(count);
  std::size_t unconverged = 0;
  for (std::size_t i = 0; i < count; ++i) {
    alone[i] = run_batch(s, pool, starts, {i})[0];
    unconverged += alone[i].status == Status::kNoConvergence;
  }
  // Newton to convergence has lanes that run all max_iterations beside lanes that stop early.
  if (to_convergence) {
    EXPECT_GT(unconverged, 0u) << what << ": no query of the pool fails to converge";
  }
  std::size_t mismatches = 0;
  const auto check = [&](const std::vector<std::size_t>& rows, const std::string& where) {
    const std::vector<Answer<Real>> got = run_batch(s, pool, starts, rows);
    for (std::size_t j = 0; j < rows.size(); ++j) {
      if (same_bits(got[j], alone[rows[j]])) continue;
      if (++mismatches <= 3) {
        ADD_FAILURE() << what << ": query " << rows[j] << " at position " << j << " of " << where << " ("
                      << rows.size() << " queries, blocks of " << w << "): " << describe(got[j]) << ", alone "
                      << describe(alone[rows[j]]);
      }
    }
  };
  for (std::size_t group = 0; group + w <= count; group += w) {
    for (std::size_t r = 0; r < w; ++r) {
      std::vector<std::size_t> rows(w);
      for (std::size_t l = 0; l < w; ++l) rows[l] = group + (l + r) % w;
      check(rows, "a full block");
    }
  }
  for (std::size_t t = 1; t < w; ++t) {
    std::vector<std::size_t> rows(w + t);
    for (std::size_t j = 0; j < w + t; ++j) rows[j] = (7 * t + j) % count;
    check(rows, "a block and a tail");
    check(std::vector<std::size_t>(rows.begin() + static_cast<std::ptrdiff_t>(w), rows.end()),
          "a tail alone");
  }
  return mismatches;
}

/// Starts for start+newton:K: around the domain's centre, some outside it, one in eleven not finite.
std::vector<double> random_starts(std::size_t count, double lo, double hi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo - 0.2 * (hi - lo), hi + 0.2 * (hi - lo));
  std::vector<double> out(2 * count);
  for (double& x : out) x = u(rng);
  for (std::size_t i = 5; i < count; i += 11) out[2 * i] = std::numeric_limits<double>::quiet_NaN();
  return out;
}

template <class Real>
std::vector<Real> as(const std::vector<double>& x) {
  return std::vector<Real>(x.begin(), x.end());
}

// --- LocalSearch: bilinear and Gregory segments
// --------------------------------------------------------------

/// Three blocks of 32 queries of the paper's domain, every seventh spoiled (NaN, collapsed, far, tiny, huge,
/// a random box: statuses other than ok, Newton that does not converge).
std::vector<double> segment_pool(SurfaceKind kind) {
  return testing::mixed_queries(kind, 96, kind == SurfaceKind::kBilinear ? 61 : 62);
}

/// Every (method, network) of `cases` in each variant: 0 the default options; 1 the whole face
/// (SearchOptions::closest_point_on_face), for newton and `hybrid`; 2 Newton to convergence cut at 4 steps
/// (lanes that stop early beside lanes that run to the limit and fail), newton only. check(method, network,
/// options, suffix naming the variant, whether the variant leaves lanes unconverged).
template <class Net, class Check>
void for_each_variant(const std::vector<std::pair<std::string, Net>>& cases, const std::string& hybrid,
                      const Check& check) {
  for (const int variant : {0, 1, 2}) {
    for (const auto& [method, net] : cases) {
      if (variant == 1 && method != "newton" && method != hybrid) continue;
      if (variant == 2 && method != "newton") continue;
      SearchOptions options;
      options.closest_point_on_face = variant == 1;
      if (variant == 2) options.max_iterations = 4;
      const std::string suffix =
          std::string(variant == 1 ? " (whole face)" : "") + (variant == 2 ? " (max_iterations 4)" : "");
      check(method, net, options, suffix, variant == 2);
    }
  }
}

/// A random network of the surface (float or double), its training domain a box of the features narrow enough
/// that some queries are out of it.
template <class Net>
NetworkModel random_segment_network(SurfaceKind kind, std::uint64_t seed) {
  const int n_in = feature_count(kind);
  const ParamDomain range = param_domain(kind);
  mlp::Scaling scaling = box_scaling(n_in, range.lo, range.hi);
  scaling.input_features = InputFeatures::kPaper;
  mlp::Network<Net> net({n_in, 12, 7, 2}, 1.7, scaling);
  net.initialize(seed);
  geometry::TrainingDomain domain;
  domain.surface = kind;
  domain.feature_min.assign(static_cast<std::size_t>(n_in), -0.8);
  domain.feature_max.assign(static_cast<std::size_t>(n_in), 0.8);
  domain.filters = testing::paper_filters(kind);
  return NetworkModel(net, domain);
}

template <class Real>
void check_segments(SurfaceKind kind, const std::string& isa) {
  const NetworkModel float_net = random_segment_network<float>(kind, 64);
  const NetworkModel double_net = random_segment_network<double>(kind, 65);
  const std::vector<double> pool = segment_pool(kind);
  const ParamDomain range = param_domain(kind);
  const auto columns = static_cast<std::size_t>(LocalSearch::raw_columns(kind));
  const std::vector<double> starts = random_starts(pool.size() / columns, range.lo, range.hi, 63);
  std::vector<std::pair<std::string, const NetworkModel*>> cases;
  for (const std::string& m : testing::methods_of(kind)) cases.emplace_back(m, &float_net);
  cases.emplace_back("network", &double_net);
  cases.emplace_back("network+newton:2", &double_net);
  cases.emplace_back("start+newton:5", &float_net);
  cases.emplace_back("newton:5", &float_net);
  for_each_variant(cases, "closed_form+newton:2",
                   [&](const std::string& method, const NetworkModel* net, const SearchOptions& options,
                       const std::string& suffix, bool unconverged) {
                     const LocalSearch search(kind, Method::parse(method), options, net);
                     const Searcher<Real> s = searcher_of<Real>(search, columns);
                     const std::string what = std::string(to_string(kind)) + " " + method +
                                              (net == &double_net ? " (double net)" : "") + suffix + ", " +
                                              (sizeof(Real) == 4 ? "float" : "double") + ", " + isa;
                     EXPECT_EQ(lane_mismatches(s, as<Real>(pool), as<Real>(starts), what, unconverged), 0u)
                         << what;
                   });
}

// --- FaceSearch: tri3, tri6, quad8
// ---------------------------------------------------------------------------

/// Random faces (placed at random positions, orientations and scales; one in five strongly curved, one in
/// five with its slave node 3 face sizes off), one in five spoiled: a slave node 1e3 face sizes away (Newton
/// from the centre wanders over the extrapolated surface), a NaN, a face collapsed to a point, a slave node
/// far beyond an edge.
std::vector<double> face_pool(FaceKind kind, std::size_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> raw;
  for (std::size_t i = 0; i < count; ++i) {
    testing::FaceQueryOptions o;
    if (i % 5 == 1) o.curvature = 0.35;
    if (i % 5 == 3) o.height = 3.0;
    testing::FaceQuery q = testing::random_face_query(kind, rng, o);
    const double size = (q.nodes[1] - q.nodes[0]).norm();
    switch (i % 20) {
      case 0: q.slave += geometry::Vec3(u(rng), u(rng), u(rng)) * (1e3 * size); break;
      case 5: q.nodes[i % q.nodes.size()].y() = std::numeric_limits<double>::quiet_NaN(); break;
      case 10:
        for (auto& x : q.nodes) x = q.nodes[0];
        break;
      case 15: q.slave = q.nodes[1] + (q.nodes[1] - q.nodes[0]) * 4.0; break;
      default: break;
    }
    testing::append_row(q, raw);
  }
  return raw;
}

template <class Net>
FaceNetwork random_face_network(FaceKind kind, std::uint64_t seed) {
  const int nf = face_feature_count(kind);
  mlp::Network<Net> net({nf, 12, 2}, 1.0, box_scaling(nf, -0.3, 0.3));
  net.initialize(seed);
  // A narrow domain: some queries are out of it.
  return FaceNetwork(kind, net, std::vector<double>(static_cast<std::size_t>(nf), -1.0),
                     std::vector<double>(static_cast<std::size_t>(nf), 1.0));
}

template <class Real>
void check_faces(FaceKind kind, const std::string& isa) {
  const bool quadratic = kind != FaceKind::kTri3;
  std::optional<FaceNetwork> float_net, double_net;
  if (quadratic) {
    float_net.emplace(random_face_network<float>(kind, 71));
    double_net.emplace(random_face_network<double>(kind, 72));
  }
  const auto columns = static_cast<std::size_t>(face_raw_columns(kind));
  const std::vector<double> pool = face_pool(kind, 96, 73 + static_cast<std::uint64_t>(kind));
  const bool quad = kind == FaceKind::kQuad8;
  const std::vector<double> starts = random_starts(pool.size() / columns, quad ? -1.0 : 0.0, 1.0, 74);
  std::vector<std::pair<std::string, const FaceNetwork*>> cases;
  for (const char* m :
       {"newton", "newton:0", "newton:5", "closed_form", "closed_form+newton:3", "start+newton:5", "start"}) {
    cases.emplace_back(m, nullptr);
  }
  if (quadratic) {
    for (const FaceNetwork* net : {&*float_net, &*double_net}) {
      cases.emplace_back("network", net);
      cases.emplace_back("network+newton:2", net);
    }
  }
  for_each_variant(cases, "closed_form+newton:3",
                   [&](const std::string& method, const FaceNetwork* net, const SearchOptions& options,
                       const std::string& suffix, bool cut) {
                     const FaceSearch search(kind, Method::parse(method), options, net);
                     const Searcher<Real> s = searcher_of<Real>(search, columns);
                     const std::string what =
                         std::string(to_string(kind)) + " " + method +
                         (net == nullptr ? "" : (net == &*double_net ? " (double net)" : " (float net)")) +
                         suffix + ", " + (sizeof(Real) == 4 ? "float" : "double") + ", " + isa;
                     // Float rows: the faces as they are (float rounds their placement; the same bits are
                     // asked of whatever float makes of them).
                     const bool unconverged = cut && kind != FaceKind::kTri3;
                     EXPECT_EQ(lane_mismatches(s, as<Real>(pool), as<Real>(starts), what, unconverged), 0u)
                         << what;
                   });
}

class LaneBits : public ::testing::TestWithParam<KernelIsa> {};

TEST_P(LaneBits, BilinearAndGregorySegments) {
  const std::string isa(to_string(GetParam()));
  if (!cpu_runs(GetParam())) GTEST_SKIP() << isa << " does not run on this CPU";
  const ScopedIsa scope(isa);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    check_segments<double>(kind, isa);
    check_segments<float>(kind, isa);
  }
}

TEST_P(LaneBits, Tri3Tri6AndQuad8Faces) {
  const std::string isa(to_string(GetParam()));
  if (!cpu_runs(GetParam())) GTEST_SKIP() << isa << " does not run on this CPU";
  const ScopedIsa scope(isa);
  for (const FaceKind kind : {FaceKind::kTri3, FaceKind::kTri6, FaceKind::kQuad8}) {
    check_faces<double>(kind, isa);
    check_faces<float>(kind, isa);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryBuiltVariant, LaneBits, ::testing::ValuesIn(built_kernel_isas()),
                         [](const ::testing::TestParamInfo<KernelIsa>& p) {
                           return std::string(to_string(p.param));
                         });

}  // namespace
}  // namespace contactnn::search
