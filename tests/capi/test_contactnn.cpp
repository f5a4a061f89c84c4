// Tests of lib/capi/contactnn.cpp: the C interface gives lib/search's own results bit for bit (the same
// method, options and network, called through search::LocalSearch directly), for every method, in double and
// float, for every option and from several threads on one handle; its messages are per thread.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "contactnn/contactnn.h"
#include "io/network_model_file.hpp"
#include "search/local_search.hpp"
#include "search/random_queries.hpp"

namespace {

using namespace contactnn;
using contactnn::testing::methods_of;
using contactnn::testing::mixed_queries;
using search::LocalSearch;
using search::Method;
using search::SearchOptions;

constexpr auto kBilinear = SurfaceKind::kBilinear;
constexpr auto kGregory = SurfaceKind::kGregory;

std::string network_path(SurfaceKind kind) {
  return std::string(CONTACTNN_SOURCE_DIR) + "/data/weights/" +
         (kind == kBilinear ? "bilinear-8.h5" : "gregory-48.h5");
}

/// The shipped network of `kind` as lib/search's model, read as the C interface reads it.
const search::NetworkModel& model(SurfaceKind kind) {
  static std::unique_ptr<search::NetworkModel> models[2];
  auto& m = models[static_cast<int>(kind)];
  if (!m) {
    m = io::read_network_model(network_path(kind));
  }
  return *m;
}

template <class Real>
struct Outputs {
  std::vector<Real> param, gap;
  std::vector<int> status, iterations;
  bool operator==(const Outputs& o) const {
    // Bitwise: NaN-free by contract, and -0.0 must stay -0.0.
    return param.size() == o.param.size() &&
           std::memcmp(param.data(), o.param.data(), param.size() * sizeof(Real)) == 0 &&
           std::memcmp(gap.data(), o.gap.data(), gap.size() * sizeof(Real)) == 0 && status == o.status &&
           iterations == o.iterations;
  }
};

/// `start`: what param holds when the run begins (start+newton:K reads it), else zeros.
template <class Real>
Outputs<Real> run_c(const contactnn_search* search, const std::vector<Real>& raw, std::size_t count,
                    const std::vector<Real>* start = nullptr) {
  Outputs<Real> out{start != nullptr ? *start : std::vector<Real>(2 * count), std::vector<Real>(count),
                    std::vector<int>(count), std::vector<int>(count)};
  int code = 0;
  if constexpr (std::is_same_v<Real, double>) {
    code = contactnn_search_run(search, count, raw.data(), out.param.data(), out.gap.data(),
                                out.status.data(), out.iterations.data());
  } else {
    code = contactnn_search_run_float(search, count, raw.data(), out.param.data(), out.gap.data(),
                                      out.status.data(), out.iterations.data());
  }
  EXPECT_EQ(code, CONTACTNN_SUCCESS) << contactnn_last_error();
  return out;
}

template <class Real>
Outputs<Real> run_library(const LocalSearch& search, const std::vector<Real>& raw, std::size_t count,
                          int threads, const std::vector<Real>* start = nullptr) {
  Outputs<Real> out{start != nullptr ? *start : std::vector<Real>(2 * count), std::vector<Real>(count),
                    std::vector<int>(count), std::vector<int>(count)};
  std::vector<Status> status(count);
  search.run(count, raw.data(),
             search::Results<Real>{out.param.data(), out.gap.data(), status.data(), out.iterations.data()},
             threads);
  for (std::size_t i = 0; i < count; ++i) out.status[i] = static_cast<int>(status[i]);
  return out;
}

/// The C options for `o` and `threads`.
contactnn_options c_options(const SearchOptions& o, int threads) {
  contactnn_options c{};
  EXPECT_EQ(contactnn_options_init(&c), CONTACTNN_SUCCESS);
  c.threads = threads;
  c.check_domain = o.check_domain ? 1 : 0;
  c.max_iterations = o.max_iterations;
  c.max_halvings = o.max_halvings;
  c.tol_param = o.tol_param;
  c.domain_margin = o.domain_margin;
  c.gregory_box_margin = o.gregory_box_margin;
  c.bilinear_box_margin = o.bilinear_box_margin;
  c.max_step_widths = o.max_step_widths;
  c.min_parallel_count = o.min_parallel_count;
  return c;
}

/// A C handle, destroyed at the end of the scope.
struct Handle {
  contactnn_search* search = nullptr;
  Handle(SurfaceKind kind, const std::string& method, const contactnn_options* options) {
    const std::string file = Method::parse(method).needs_network() ? network_path(kind) : "";
    EXPECT_EQ(contactnn_search_create(&search, static_cast<int>(kind), method.c_str(), file.c_str(), options),
              CONTACTNN_SUCCESS)
        << contactnn_last_error();
  }
  ~Handle() { contactnn_search_destroy(search); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
};

template <class Real>
std::vector<Real> as(const std::vector<double>& raw) {
  return std::vector<Real>(raw.begin(), raw.end());
}

TEST(CApi, GivesLibSearchsResultsBitForBitForEveryMethodInDoubleAndFloat) {
  // More queries than min_parallel_count, so that the runs are parallel (2 threads).
  constexpr std::size_t kCount = 700;
  for (const SurfaceKind kind : {kBilinear, kGregory}) {
    const std::vector<double> raw = mixed_queries(kind, kCount, 41);
    const contactnn_options options = c_options(SearchOptions{}, 2);
    for (const std::string& method : methods_of(kind)) {
      SCOPED_TRACE(std::string(to_string(kind)) + " " + method);
      const Handle c(kind, method, &options);
      const LocalSearch library(kind, Method::parse(method), {}, &model(kind));
      const Outputs<double> d = run_c(c.search, raw, kCount);
      EXPECT_TRUE(d == run_library(library, raw, kCount, 1));
      EXPECT_TRUE(run_c(c.search, as<float>(raw), kCount) == run_library(library, as<float>(raw), kCount, 1));
      // The hostile rows are there: ok and invalid both appear.
      const std::set<int> statuses(d.status.begin(), d.status.end());
      EXPECT_TRUE(statuses.count(CONTACTNN_STATUS_OK) && statuses.count(CONTACTNN_STATUS_INVALID));
    }
  }
}

TEST(CApi, AQueryAloneAndAFewGetTheBitsOfALargerBatch) {
  // contactnn_search_run keeps the statuses of at most 64 queries on the stack (an FE code's one pair per
  // call) and runs them on the calling thread: each query alone, and the first 64 in one call, must give the
  // bits of one call for all 65 (the heap path), in double and float.
  constexpr std::size_t kCount = 65;
  for (const SurfaceKind kind : {kBilinear, kGregory}) {
    const std::vector<double> raw = mixed_queries(kind, kCount, 43);
    const auto columns = static_cast<std::size_t>(LocalSearch::raw_columns(kind));
    const contactnn_options options = c_options(SearchOptions{}, 2);
    for (const std::string& method : methods_of(kind)) {
      if (Method::parse(method).needs_start()) continue;  // its own test: param holds the starts
      SCOPED_TRACE(std::string(to_string(kind)) + " " + method);
      const Handle c(kind, method, &options);
      const auto check = [&](const auto& rows) {
        using Real = typename std::decay_t<decltype(rows)>::value_type;
        const Outputs<Real> all = run_c(c.search, rows, kCount);
        const auto prefix = [&](const Outputs<Real>& o, std::size_t first, std::size_t n) {
          return Outputs<Real>{{o.param.begin() + 2 * first, o.param.begin() + 2 * (first + n)},
                               {o.gap.begin() + first, o.gap.begin() + first + n},
                               {o.status.begin() + first, o.status.begin() + first + n},
                               {o.iterations.begin() + first, o.iterations.begin() + first + n}};
        };
        const std::vector<Real> few(rows.begin(), rows.begin() + 64 * columns);
        EXPECT_TRUE(run_c(c.search, few, 64) == prefix(all, 0, 64));
        for (std::size_t i = 0; i < kCount; ++i) {
          const std::vector<Real> one(rows.begin() + i * columns, rows.begin() + (i + 1) * columns);
          EXPECT_TRUE(run_c(c.search, one, 1) == prefix(all, i, 1)) << "query " << i;
        }
      };
      check(raw);
      check(as<float>(raw));
    }
  }
}

TEST(CApi, StartPlusNewtonReadsEachQuerysStartFromParam) {
  constexpr std::size_t kCount = 700;
  for (const SurfaceKind kind : {kBilinear, kGregory}) {
    SCOPED_TRACE(to_string(kind));
    const std::vector<double> raw = mixed_queries(kind, kCount, 43);
    std::mt19937_64 rng(5);
    const ParamDomain d = param_domain(kind);
    std::uniform_real_distribution<double> inside(d.lo + 0.2 * (d.hi - d.lo), d.hi - 0.2 * (d.hi - d.lo));
    std::vector<double> start(2 * kCount);
    for (double& x : start) x = inside(rng);
    const contactnn_options options = c_options(SearchOptions{}, 2);
    const Handle c(kind, "start+newton:1", &options);
    const LocalSearch library(kind, Method::parse("start+newton:1"));
    const Outputs<double> from_start = run_c(c.search, raw, kCount, &start);
    EXPECT_TRUE(from_start == run_library(library, raw, kCount, 1, &start));
    const std::vector<float> start_f = as<float>(start);
    EXPECT_TRUE(run_c(c.search, as<float>(raw), kCount, &start_f) ==
                run_library(library, as<float>(raw), kCount, 1, &start_f));
    // One step from other starts ends elsewhere: the starts were read.
    const Outputs<double> from_zero = run_c(c.search, raw, kCount);
    int differ = 0;
    for (std::size_t i = 0; i < kCount; ++i)
      differ += from_start.param[2 * i] != from_zero.param[2 * i] ? 1 : 0;
    EXPECT_GT(differ, static_cast<int>(kCount / 2));
  }
}

TEST(CApi, OptionalOutputsMayBeLeftOut) {
  constexpr std::size_t kCount = 100;
  const std::vector<double> raw = mixed_queries(kGregory, kCount, 7);
  const Handle c(kGregory, "network+newton:2", nullptr);
  const Outputs<double> all = run_c(c.search, raw, kCount);
  std::vector<double> param(2 * kCount);
  std::vector<int> status(kCount);
  ASSERT_EQ(contactnn_search_run(c.search, kCount, raw.data(), param.data(), nullptr, status.data(), nullptr),
            CONTACTNN_SUCCESS);
  EXPECT_EQ(std::memcmp(param.data(), all.param.data(), param.size() * sizeof(double)), 0);
  EXPECT_EQ(status, all.status);
}

TEST(CApi, EveryOptionReachesTheSearch) {
  // Each option changed alone, on a method and surface where it changes some result: the C handle must give
  // the library's results with that option, and those must differ from the defaults' (else the option was
  // not tested).
  struct Case {
    const char* name;
    SurfaceKind kind;
    const char* method;
    void (*change)(SearchOptions&);
  };
  const Case cases[] = {
      {"check_domain", kGregory, "network", [](SearchOptions& o) { o.check_domain = false; }},
      {"max_iterations", kBilinear, "newton", [](SearchOptions& o) { o.max_iterations = 2; }},
      {"tol_param", kBilinear, "newton", [](SearchOptions& o) { o.tol_param = 1e-2; }},
      {"domain_margin", kBilinear, "newton:3", [](SearchOptions& o) { o.domain_margin = 0.5; }},
      {"gregory_box_margin", kGregory, "network+newton:2",
       [](SearchOptions& o) { o.gregory_box_margin = 0.1; }},
      {"bilinear_box_margin", kBilinear, "closed_form+newton:2",
       [](SearchOptions& o) { o.bilinear_box_margin = 0.0; }},
      {"max_step_widths", kBilinear, "closed_form+newton:2",
       [](SearchOptions& o) { o.max_step_widths = 1e-3; }},
      {"max_halvings", kGregory, "network+newton:2", [](SearchOptions& o) { o.max_halvings = 0; }},
  };
  constexpr std::size_t kCount = 1000;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::vector<double> raw = mixed_queries(c.kind, kCount, 5);
    SearchOptions changed;
    c.change(changed);
    const contactnn_options options = c_options(changed, 1);
    const Handle handle(c.kind, c.method, &options);
    const LocalSearch library(c.kind, Method::parse(c.method), changed, &model(c.kind));
    const LocalSearch defaults(c.kind, Method::parse(c.method), {}, &model(c.kind));
    const Outputs<double> got = run_c(handle.search, raw, kCount);
    EXPECT_TRUE(got == run_library(library, raw, kCount, 1));
    EXPECT_FALSE(got == run_library(defaults, raw, kCount, 1));
  }
}

TEST(CApi, DefaultOptionsAreTheLibrarysDefaults) {
  contactnn_options c{};
  ASSERT_EQ(contactnn_options_init(&c), CONTACTNN_SUCCESS);
  const SearchOptions d;
  EXPECT_EQ(c.threads, 0);
  EXPECT_EQ(c.check_domain != 0, d.check_domain);
  EXPECT_EQ(c.max_iterations, d.max_iterations);
  EXPECT_EQ(c.max_halvings, d.max_halvings);
  EXPECT_EQ(c.tol_param, d.tol_param);
  EXPECT_EQ(c.domain_margin, d.domain_margin);
  EXPECT_EQ(c.gregory_box_margin, d.gregory_box_margin);
  EXPECT_EQ(c.bilinear_box_margin, d.bilinear_box_margin);
  EXPECT_EQ(c.max_step_widths, d.max_step_widths);
  EXPECT_EQ(c.min_parallel_count, d.min_parallel_count);
}

TEST(CApi, ConcurrentRunsOnOneHandleGiveTheSequentialResults) {
  constexpr int kThreads = 4;
  constexpr int kRepeats = 10;
  constexpr std::size_t kCount = 300;
  const contactnn_options options = c_options(SearchOptions{}, 1);
  const Handle c(kGregory, "network+newton:2", &options);
  std::vector<std::vector<double>> raw;
  std::vector<Outputs<double>> expected;
  for (int t = 0; t < kThreads; ++t) {
    raw.push_back(mixed_queries(kGregory, kCount, 100 + static_cast<std::uint64_t>(t)));
    expected.push_back(run_c(c.search, raw.back(), kCount));
  }
  std::vector<int> mismatches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int r = 0; r < kRepeats; ++r) {
        if (!(run_c(c.search, raw[static_cast<std::size_t>(t)], kCount) ==
              expected[static_cast<std::size_t>(t)])) {
          ++mismatches[static_cast<std::size_t>(t)];
        }
      }
    });
  }
  for (auto& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(mismatches[static_cast<std::size_t>(t)], 0) << "thread " << t;
}

TEST(CApi, LastErrorIsPerThreadAndKeptBySuccesses) {
  contactnn_search* s = nullptr;
  ASSERT_EQ(contactnn_search_create(&s, 0, "no-such-method", nullptr, nullptr),
            CONTACTNN_ERROR_INVALID_ARGUMENT);
  const std::string mine = contactnn_last_error();
  EXPECT_NE(mine.find("no-such-method"), std::string::npos);
  std::string theirs_before, theirs_after;
  std::thread other([&] {
    theirs_before = contactnn_last_error();
    contactnn_search* t = nullptr;
    EXPECT_EQ(contactnn_search_create(&t, 5, "newton", nullptr, nullptr), CONTACTNN_ERROR_INVALID_ARGUMENT);
    theirs_after = contactnn_last_error();
  });
  other.join();
  EXPECT_EQ(theirs_before, "");
  EXPECT_NE(theirs_after.find("surface = 5"), std::string::npos);
  EXPECT_EQ(contactnn_last_error(), mine);
  const Handle ok(kBilinear, "newton:2", nullptr);
  EXPECT_EQ(contactnn_last_error(), mine);
}

TEST(CApi, RefusesFourTrianglesOnGregoryAndStepCountsAboveTheLimit) {
  // four_triangles exists for bilinear segments only; K of any "...newton:K" is at most 1000.
  const struct {
    int surface;
    const char* method;
    const char* says;
  } refused[] = {{CONTACTNN_SURFACE_GREGORY, "four_triangles", "four_triangles"},
                 {CONTACTNN_SURFACE_BILINEAR, "newton:1001", "limit of 1000"},
                 {CONTACTNN_SURFACE_GREGORY, "closed_form+newton:100000000", "limit of 1000"}};
  for (const auto& r : refused) {
    contactnn_search* s = nullptr;
    EXPECT_EQ(contactnn_search_create(&s, r.surface, r.method, nullptr, nullptr),
              CONTACTNN_ERROR_INVALID_ARGUMENT)
        << r.method;
    EXPECT_EQ(s, nullptr) << r.method;
    EXPECT_NE(std::string(contactnn_last_error()).find(r.says), std::string::npos) << contactnn_last_error();
  }
  const Handle ok(kBilinear, "four_triangles", nullptr);
  EXPECT_EQ(contactnn_search_surface(ok.search), CONTACTNN_SURFACE_BILINEAR);
}

TEST(CApi, StatusNamesAndNumbersAreContactnnsOwn) {
  for (int s = 0; s < kStatusCount; ++s) {
    EXPECT_EQ(std::string(contactnn_status_name(s)), std::string(to_string(static_cast<Status>(s))));
  }
  EXPECT_EQ(std::string(contactnn_status_name(kStatusCount)), "unknown");
  EXPECT_EQ(contactnn_raw_columns(CONTACTNN_SURFACE_GREGORY), LocalSearch::raw_columns(kGregory));
}

}  // namespace
