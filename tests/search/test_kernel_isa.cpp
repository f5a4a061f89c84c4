// The kernel variants of lib/search (search/isa_dispatch.hpp), every one this CPU runs, forced in turn
// through CONTACTNN_ISA: the variants with FMA give the same bits as each other, baseline the same statuses
// and results within rounding (it rounds each multiply-add twice); in every variant a query alone gives its
// bits in a block (the one-lane kernel is the block kernel's variant); and CONTACTNN_ISA is read and checked
// at construction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "search/isa_dispatch.hpp"
#include "search/local_search.hpp"
#include "search/random_queries.hpp"
#include "search/shipped_networks.hpp"

namespace contactnn::search {
namespace {

using testing::shipped;

constexpr SurfaceKind kBilinear = SurfaceKind::kBilinear;
constexpr SurfaceKind kGregory = SurfaceKind::kGregory;

/// CONTACTNN_ISA set (or unset: nullptr) for a scope, then put back.
class ScopedIsa {
 public:
  explicit ScopedIsa(const char* value) {
    if (const char* old = std::getenv("CONTACTNN_ISA")) old_ = old;
    set(value);
  }
  ~ScopedIsa() { set(old_ ? old_->c_str() : nullptr); }
  ScopedIsa(const ScopedIsa&) = delete;
  ScopedIsa& operator=(const ScopedIsa&) = delete;

 private:
  static void set(const char* value) {
    if (value != nullptr) {
      ::setenv("CONTACTNN_ISA", value, 1);
    } else {
      ::unsetenv("CONTACTNN_ISA");
    }
  }
  std::optional<std::string> old_;
};

/// The variants this build holds and this CPU runs.
std::vector<KernelIsa> runnable() {
  std::vector<KernelIsa> out;
  for (const KernelIsa isa : built_kernel_isas()) {
    if (cpu_runs(isa)) out.push_back(isa);
  }
  return out;
}

bool has_fma(KernelIsa isa) { return isa != KernelIsa::kBaseline; }

template <class Real>
struct Output {
  std::vector<Real> param, gap;
  std::vector<Status> status;
  std::vector<std::int32_t> iterations;
  std::vector<Location> location;
  explicit Output(std::size_t n) : param(2 * n), gap(n), status(n), iterations(n), location(n) {}
  Results<Real> results() {
    return Results<Real>{param.data(), gap.data(), status.data(), iterations.data(), location.data()};
  }
};

template <class Real>
Output<Real> run(const LocalSearch& search, const std::vector<Real>& raw) {
  const std::size_t n = raw.size() / static_cast<std::size_t>(LocalSearch::raw_columns(search.surface()));
  Output<Real> out(n);
  search.run(n, raw.data(), out.results(), 1);
  return out;
}

template <class Real>
bool same_bits(Real a, Real b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// One method to run in every variant.
struct Case {
  SurfaceKind kind;
  std::string method;
  const NetworkModel* network;
  SearchOptions options;
  std::string name;
};

/// Random queries of the paper's domains with every seventh row spoiled (NaN, collapsed, far, tiny, huge,
/// random), the queries on a tie (the network's scalar tie path), and a count that leaves a tail outside
/// whole blocks.
std::vector<double> queries(SurfaceKind kind) {
  std::vector<double> raw = testing::mixed_queries(kind, 1000, kind == kBilinear ? 41 : 42);
  std::mt19937_64 rng(43);
  for (const geometry::Configuration& c : testing::tie_queries(rng)) testing::append_raw(c, kind, raw);
  const std::vector<double> tail = testing::random_queries(kind, 13, 44);
  raw.insert(raw.end(), tail.begin(), tail.end());
  return raw;
}

/// Every path of the kernels (testing::methods_of), with the shipped float networks and a double network
/// (blocks of 16), and once with the whole face (SearchOptions::closest_point_on_face).
class Cases {
 public:
  Cases() {
    for (const SurfaceKind kind : {kBilinear, kGregory}) {
      const auto& trained = shipped(kind == kBilinear ? "bilinear-8.h5" : "gregory-48.h5");
      const NetworkModel& f = models_.emplace_back(trained.network, trained.domain);
      const NetworkModel& d = models_.emplace_back(
          testing::random_network<double>(trained.domain, {12, 7}, InputFeatures::kPaper, 5), trained.domain);
      for (const std::string& method : testing::methods_of(kind)) {
        cases_.push_back({kind, method, &f, {}, std::string(to_string(kind)) + " " + method});
      }
      cases_.push_back({kind, "network", &d, {}, std::string(to_string(kind)) + " network (double)"});
      cases_.push_back(
          {kind, "network+newton:2", &d, {}, std::string(to_string(kind)) + " network+newton:2 (double)"});
      SearchOptions face;
      face.closest_point_on_face = true;
      cases_.push_back({kind, "newton:3", &f, face, std::string(to_string(kind)) + " newton:3 (whole face)"});
    }
  }
  [[nodiscard]] const std::vector<Case>& all() const { return cases_; }

 private:
  std::deque<NetworkModel> models_;  // stable addresses
  std::vector<Case> cases_;
};

const Cases& cases() {
  static const Cases c;
  return c;
}

TEST(KernelIsa, TheBuildHoldsItsVariantsAndTheCpuRunsBaseline) {
  const std::vector<KernelIsa> built = built_kernel_isas();
  ASSERT_FALSE(built.empty());
#if CONTACTNN_TEST_NATIVE
  EXPECT_EQ(built, std::vector<KernelIsa>{KernelIsa::kNative}) << "a CONTACTNN_NATIVE build has one variant";
#elif defined(__x86_64__)
  EXPECT_EQ(built, (std::vector<KernelIsa>{KernelIsa::kBaseline, KernelIsa::kAvx2, KernelIsa::kAvx512}));
  EXPECT_TRUE(cpu_runs(KernelIsa::kBaseline));
  EXPECT_FALSE(cpu_runs(KernelIsa::kNative)) << "not built";
  // The CPU's own word (each variant's key features) against cpu_runs.
  __builtin_cpu_init();
  EXPECT_EQ(cpu_runs(KernelIsa::kAvx2), __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"));
  EXPECT_EQ(cpu_runs(KernelIsa::kAvx512),
            __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl"));
#endif
  for (const KernelIsa isa : built) EXPECT_FALSE(to_string(isa).empty());
}

TEST(KernelIsa, UnforcedItIsTheWidestVariantTheCpuRuns) {
  const KernelIsa widest = runnable().back();
  for (const char* value : {static_cast<const char*>(nullptr), "", "auto"}) {
    const ScopedIsa scope(value);
    EXPECT_EQ(kernel_isa(), widest) << "CONTACTNN_ISA=" << (value ? value : "(unset)");
  }
  RecordProperty("widest", std::string(to_string(widest)));
}

TEST(KernelIsa, CONTACTNN_ISAForcesAVariantAndIsCheckedAtConstruction) {
  for (const KernelIsa isa : runnable()) {
    const ScopedIsa scope(std::string(to_string(isa)).c_str());
    EXPECT_EQ(kernel_isa(), isa);
    EXPECT_NO_THROW(LocalSearch(kBilinear, Method::parse("newton:3")));
  }
  // A name that is no variant, one this build lacks, one this CPU cannot run: refused where a LocalSearch is
  // made, never a silent fallback (nor SIGILL).
  std::vector<std::string> refused = {"sse9", "AVX2", "avx512 "};
  for (const KernelIsa isa :
       {KernelIsa::kBaseline, KernelIsa::kAvx2, KernelIsa::kAvx512, KernelIsa::kNative}) {
    if (!cpu_runs(isa)) refused.emplace_back(to_string(isa));
  }
  for (const std::string& value : refused) {
    const ScopedIsa scope(value.c_str());
    EXPECT_THROW((void)kernel_isa(), InvalidArgument) << value;
    EXPECT_THROW(LocalSearch(kBilinear, Method::parse("newton:3")), InvalidArgument) << value;
    try {
      (void)kernel_isa();
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("CONTACTNN_ISA=" + value), std::string::npos) << e.what();
    }
  }
}

/// Each case's results in each runnable variant, in double and float.
struct VariantResults {
  std::map<KernelIsa, std::vector<Output<double>>> in_double;
  std::map<KernelIsa, std::vector<Output<float>>> in_float;
};

const VariantResults& variant_results() {
  static const VariantResults r = [] {
    VariantResults out;
    for (const KernelIsa isa : runnable()) {
      const ScopedIsa scope(std::string(to_string(isa)).c_str());
      for (const Case& c : cases().all()) {
        const LocalSearch search(c.kind, Method::parse(c.method), c.options, c.network);
        const std::vector<double> raw = queries(c.kind);
        out.in_double[isa].push_back(run(search, raw));
        out.in_float[isa].push_back(run(search, std::vector<float>(raw.begin(), raw.end())));
      }
    }
    return out;
  }();
  return r;
}

/// The number of queries whose results differ in any bit.
template <class Real>
std::size_t differing(const Output<Real>& a, const Output<Real>& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.status.size(); ++i) {
    n += !(a.status[i] == b.status[i] && same_bits(a.param[2 * i], b.param[2 * i]) &&
           same_bits(a.param[2 * i + 1], b.param[2 * i + 1]) && same_bits(a.gap[i], b.gap[i]) &&
           a.iterations[i] == b.iterations[i] && a.location[i] == b.location[i]);
  }
  return n;
}

template <class Real>
void expect_same_bits(const std::vector<Output<Real>>& a, const std::vector<Output<Real>>& b,
                      const std::string& what) {
  for (std::size_t k = 0; k < cases().all().size(); ++k) {
    EXPECT_EQ(differing(a[k], b[k]), 0u) << cases().all()[k].name << ", " << what;
  }
}

TEST(KernelIsa, TheVariantsWithFmaGiveTheSameBits) {
  const VariantResults& r = variant_results();
  std::vector<KernelIsa> fma;
  for (const KernelIsa isa : runnable()) {
    if (has_fma(isa)) fma.push_back(isa);
  }
  if (fma.size() < 2) GTEST_SKIP() << "fewer than two variants with FMA run on this CPU";
  for (std::size_t v = 1; v < fma.size(); ++v) {
    const std::string what = std::string(to_string(fma[v])) + " against " + std::string(to_string(fma[0]));
    expect_same_bits(r.in_double.at(fma[v]), r.in_double.at(fma[0]), what + " (double)");
    expect_same_bits(r.in_float.at(fma[v]), r.in_float.at(fma[0]), what + " (float)");
  }
}

/// The largest distance between two nodes of row `row`.
double segment_size(const std::vector<double>& raw, SurfaceKind kind, std::size_t row) {
  const double* x = raw.data() + row * static_cast<std::size_t>(LocalSearch::raw_columns(kind));
  double size = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      size = std::max(
          size, std::hypot(x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]));
    }
  }
  return size;
}

template <class Real>
void expect_within_rounding(const std::vector<Output<Real>>& base, const std::vector<Output<Real>>& wide,
                            const std::string& what, std::size_t& differing_bits, std::size_t& total) {
  // A multiply-add rounded once or twice moves a result by a few ulps. Through a well-conditioned query that
  // changes no status and no result beyond rounding: the random queries of the paper's domains, the ties and
  // the tail. Not the spoiled rows (every seventh of the first 1000: far slaves, random boxes, extreme
  // scales), where Newton from a few ulps apart may end anywhere.
  for (std::size_t k = 0; k < cases().all().size(); ++k) {
    const Case& c = cases().all()[k];
    const std::vector<double> raw = queries(c.kind);
    // (u, v) within float rounding of the network's output where a float network or float queries take part,
    // else within many more ulps than a double's rounding makes through up to 50 Newton steps; the gap as (u,
    // v) times the segment's size.
    const bool in_float =
        sizeof(Real) == sizeof(float) || (Method::parse(c.method).needs_network() && c.network->is_float());
    const double tol = in_float ? 1e-5 : 1e-9;
    const Output<Real>& a = base[k];
    const Output<Real>& b = wide[k];
    std::size_t status_changes = 0, compared = 0;
    for (std::size_t i = 0; i < a.status.size(); ++i) {
      if (i < 1000 && i % 7 == 0) continue;  // spoiled (testing::spoil_rows)
      // Newton to convergence after many more steps than the 8.5 a random bilinear query takes on average: it
      // wandered over the extended surface, where a few ulps send it elsewhere (both variants end anywhere,
      // converged or not, in or outside the domain).
      if (c.method == "newton" && std::max(a.iterations[i], b.iterations[i]) > 30) continue;
      ++compared;
      if (a.status[i] != b.status[i]) {
        ++status_changes;
        continue;
      }
      // No converged point to compare: Newton's last iterate (no_convergence, degenerate), the centre
      // (invalid).
      if (b.status[i] != Status::kOk && b.status[i] != Status::kOutside &&
          b.status[i] != Status::kOutOfDomain)
        continue;
      // Newton to convergence may stop one step apart where a step lands at the tolerance.
      EXPECT_LE(std::abs(a.iterations[i] - b.iterations[i]), 1) << c.name << ", " << what << ", query " << i;
      for (int p = 0; p < 2; ++p) {
        const auto j = 2 * i + static_cast<std::size_t>(p);
        EXPECT_NEAR(a.param[j], b.param[j], tol) << c.name << ", " << what << ", query " << i;
      }
      EXPECT_NEAR(a.gap[i], b.gap[i], tol * (segment_size(raw, c.kind, i) + std::abs(b.gap[i])))
          << c.name << ", " << what << ", query " << i;
    }
    EXPECT_EQ(status_changes, 0u) << c.name << ", " << what << ": of " << compared << " queries";
    differing_bits += differing(a, b);
    total += a.status.size();
  }
}

TEST(KernelIsa, BaselineGivesTheStatusesOfTheVariantsWithFmaAndTheirResultsWithinRounding) {
  const std::vector<KernelIsa> all = runnable();
  if (all.front() != KernelIsa::kBaseline || all.size() < 2)
    GTEST_SKIP() << "no baseline and FMA variant to compare";
  const KernelIsa wide = all.back();
  const VariantResults& r = variant_results();
  std::size_t differing_bits = 0, total = 0;
  const std::string what = "baseline against " + std::string(to_string(wide));
  expect_within_rounding(r.in_double.at(KernelIsa::kBaseline), r.in_double.at(wide), what + " (double)",
                         differing_bits, total);
  expect_within_rounding(r.in_float.at(KernelIsa::kBaseline), r.in_float.at(wide), what + " (float)",
                         differing_bits, total);
  // Not the same bits: baseline really ran other code (CONTACTNN_ISA reached the kernels).
  EXPECT_GT(differing_bits, total / 100) << "baseline gave the FMA variant's bits almost everywhere";
  RecordProperty("baseline_differing_bits", std::to_string(differing_bits) + " of " + std::to_string(total));
}

TEST(KernelIsa, InEveryVariantAQueryAloneGivesItsBitsInABlock) {
  // The one-lane kernel (kernels_single.cpp, for the queries after the last whole block) must be the block
  // kernel's variant: baseline and FMA variants round differently. Every query of the first blocks, the ties
  // and the tail, alone.
  const VariantResults& r = variant_results();
  for (const KernelIsa isa : runnable()) {
    const ScopedIsa scope(std::string(to_string(isa)).c_str());
    for (std::size_t k = 0; k < cases().all().size(); ++k) {
      const Case& c = cases().all()[k];
      const LocalSearch search(c.kind, Method::parse(c.method), c.options, c.network);
      const std::vector<double> raw = queries(c.kind);
      const std::size_t n = r.in_double.at(isa)[k].status.size();
      std::vector<std::size_t> rows;
      for (std::size_t i = 0; i < 80; ++i) rows.push_back(i);
      for (std::size_t i = 1000; i < n; ++i) rows.push_back(i);  // the ties and the tail
      std::size_t mismatches = 0;
      for (const std::size_t i : rows) {
        const std::vector<double> row = testing::rows_of(raw, c.kind, i);
        const Output<double> one = run(search, row);
        const Output<float> one_f = run(search, std::vector<float>(row.begin(), row.end()));
        const Output<double>& all = r.in_double.at(isa)[k];
        const Output<float>& all_f = r.in_float.at(isa)[k];
        const bool same =
            one.status[0] == all.status[i] && same_bits(one.param[0], all.param[2 * i]) &&
            same_bits(one.param[1], all.param[2 * i + 1]) && same_bits(one.gap[0], all.gap[i]) &&
            one.iterations[0] == all.iterations[i] && one_f.status[0] == all_f.status[i] &&
            same_bits(one_f.param[0], all_f.param[2 * i]) &&
            same_bits(one_f.param[1], all_f.param[2 * i + 1]) && same_bits(one_f.gap[0], all_f.gap[i]);
        if (!same && ++mismatches <= 3) {
          ADD_FAILURE() << c.name << ", " << to_string(isa) << ", query " << i << " alone: " << one.param[0]
                        << " " << one.param[1] << " status " << to_string(one.status[0]) << ", in the block "
                        << all.param[2 * i] << " " << all.param[2 * i + 1] << " status "
                        << to_string(all.status[i]);
        }
      }
      EXPECT_EQ(mismatches, 0u) << c.name << ", " << to_string(isa);
    }
  }
}

}  // namespace
}  // namespace contactnn::search
