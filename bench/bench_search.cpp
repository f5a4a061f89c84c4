// Description: every lib/search method on the same queries, side by side in one run (issue 11 item 2): random
// configurations of the paper's bilinear and Gregory domains (projecting inside their segment, as the paper's
// data sets) placed at random positions, orientations and scales in a random node order, fixed seed; the
// shipped networks of data/weights. For each method: ns per query one at a time (LocalSearch::run with
// count = 1, the call an FE code makes per pair) and batched (one call for all queries) at 1 and 2 threads,
// with its accuracy against the reference labels (for four_triangles, OpenRadioss's split of the quad into
// four triangles, a different surface from the bilinear facet the labels are on) and its floating-point work
// per query (search::flops_per_query); the exported C headers of bilinear-8 and gregory-48 (c-header rows:
// one call per query and the batched entry point, 1 thread); and Eigen's float and double matrix-product
// rates at 1 and 2 threads, for the floor. scripts/bench-search runs it with repetitions in random
// interleaving (so load drift is shared) and prints the table.
//
// Sample runs:
//   build/bench/bench_search --benchmark_filter=bilinear/newton:5
//   build/bench/bench_search --queries 8192 --benchmark_repetitions=5
//   --benchmark_enable_random_interleaving=true scripts/bench-search
//
// Flags of its own (before Google Benchmark's): --queries N (default 4096 per surface), --pairs FILE (a
// scene's labelled pairs, gen-configs --scene: that surface's queries are its pairs with a reference point,
// cycled to N in the file's order, instead of random ones), --weights DIR (default the source tree's
// data/weights), --seed S (default 1), --threads LIST (the thread counts of the batched rows and the matrix
// products, comma-separated; default 1,2; scripts/bench-search --threads 1,2,4,8,16 prints the scaling beyond
// the 2 cores of CI's machines). Writes Google Benchmark's report; each benchmark carries the counters
// flops_double, flops_float (per query), mean_error, p99_error, max_error (|error| per coordinate against the
// labels, over the queries the method did not fail), failures (the method's status not
// ok/outside/out_of_domain, or its estimate more than half a domain width outside the domain, as evaluate-net
// counts them), steps (mean Newton steps).
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "contactnn/contactnn.h"
#include "dataset/labeller.hpp"
#include "eval/evaluation_set.hpp"
#include "io/face_network_file.hpp"
#include "io/network_file.hpp"
#include "search/face_queries.hpp"
#include "search/face_search.hpp"
#include "search/flop_count.hpp"
#include "search/local_search.hpp"
#include "search/random_queries.hpp"
#include "search/search_plan.hpp"

namespace {

using namespace contactnn;

struct Args {
  std::size_t queries = 4096;
  std::string pairs;  ///< a scene's labelled pairs (gen-configs --scene): its surface's queries instead of
                      ///< random ones
  std::string weights = std::string(CONTACTNN_SOURCE_DIR) + "/data/weights";
  std::uint64_t seed = 1;
  std::vector<int> threads = {1, 2};
};

/// Random queries of the paper's domain of `kind` whose reference label is ok, and the labels.
struct QuerySet {
  SurfaceKind kind = SurfaceKind::kBilinear;
  std::vector<double> raw;
  std::vector<dataset::Label> labels;
  std::size_t count() const { return labels.size(); }
};

QuerySet make_queries(SurfaceKind kind, std::size_t count, std::uint64_t seed) {
  QuerySet set;
  set.kind = kind;
  const auto stride = static_cast<std::size_t>(search::LocalSearch::raw_columns(kind));
  std::uint64_t batch_seed = seed;
  while (set.count() < count) {
    const std::vector<double> raw = testing::random_queries(kind, count, batch_seed++);
    for (std::size_t i = 0; i < count && set.count() < count; ++i) {
      const dataset::Label label =
          dataset::label_configuration(testing::configuration_of(raw.data(), kind, i), kind);
      if (label.status != Status::kOk) continue;
      set.raw.insert(set.raw.end(), raw.begin() + static_cast<std::ptrdiff_t>(i * stride),
                     raw.begin() + static_cast<std::ptrdiff_t>((i + 1) * stride));
      set.labels.push_back(label);
    }
  }
  return set;
}

/// The rows of a labelled RAW.csv (gen-configs --scene, label mode) whose reference has a point (ok,
/// outside), cycled to `count` queries in the file's order: a real deck's pairs, placed as the deck has them.
/// The surface is the file's: Gregory when it has node-normal columns.
QuerySet queries_from_pairs(const std::string& path, std::size_t count) {
  std::ifstream in(path);
  std::string header;
  if (!in || !std::getline(in, header)) {
    std::fprintf(stderr, "bench_search: cannot read --pairs '%s'\n", path.c_str());
    std::exit(2);
  }
  const SurfaceKind kind =
      header.find("nax") != std::string::npos ? SurfaceKind::kGregory : SurfaceKind::kBilinear;
  eval::EvaluationSet pairs;
  try {
    pairs = eval::set_from_labelled_csv(path, kind);
  } catch (const std::exception& e) {  // the reader's message names file, line and column
    std::fprintf(stderr, "bench_search: %s\n", e.what());
    std::exit(2);
  }
  const auto stride = static_cast<std::size_t>(search::LocalSearch::raw_columns(kind));
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < static_cast<std::size_t>(pairs.rows()); ++r) {
    if (pairs.label_status[r] == Status::kOk || pairs.label_status[r] == Status::kOutside) rows.push_back(r);
  }
  if (rows.empty()) {
    std::fprintf(stderr, "bench_search: --pairs '%s' has no pair with a reference point\n", path.c_str());
    std::exit(2);
  }
  QuerySet set;
  set.kind = kind;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t r = rows[i % rows.size()];
    set.raw.insert(set.raw.end(), pairs.raw.begin() + static_cast<std::ptrdiff_t>(r * stride),
                   pairs.raw.begin() + static_cast<std::ptrdiff_t>((r + 1) * stride));
    dataset::Label label;
    label.param = {pairs.labels(static_cast<Eigen::Index>(r), 0),
                   pairs.labels(static_cast<Eigen::Index>(r), 1)};
    label.status = pairs.label_status[r];
    set.labels.push_back(label);
  }
  return set;
}

/// Accuracy of one batched run against the labels.
struct Accuracy {
  double mean = 0.0, p99 = 0.0, max = 0.0, steps = 0.0;
  int failures = 0;
};

Accuracy accuracy_from(const QuerySet& set, const std::vector<double>& param,
                       const std::vector<Status>& status, const std::vector<std::int32_t>& steps) {
  const std::size_t n = set.count();
  Accuracy a;
  std::vector<double> errors;
  double step_sum = 0.0;
  // A failure, counted and never averaged in, as evaluate-net counts it: a status other than ok, outside or
  // out_of_domain, or an estimate more than half a domain width outside the domain.
  const ParamDomain d = param_domain(set.kind);
  const double reach = 0.5 * (d.hi - d.lo);
  for (std::size_t i = 0; i < n; ++i) {
    step_sum += steps[i];
    const bool usable =
        status[i] == Status::kOk || status[i] == Status::kOutside || status[i] == Status::kOutOfDomain;
    const bool near = param[2 * i] >= d.lo - reach && param[2 * i] <= d.hi + reach &&
                      param[2 * i + 1] >= d.lo - reach && param[2 * i + 1] <= d.hi + reach;
    if (!usable || !near) {
      ++a.failures;
      continue;
    }
    for (int c = 0; c < 2; ++c)
      errors.push_back(std::abs(param[2 * i + static_cast<std::size_t>(c)] -
                                set.labels[i].param[static_cast<std::size_t>(c)]));
  }
  a.steps = step_sum / static_cast<double>(n);
  if (!errors.empty()) {
    double sum = 0.0;
    for (const double e : errors) sum += e;
    a.mean = sum / static_cast<double>(errors.size());
    std::sort(errors.begin(), errors.end());
    a.p99 = errors[static_cast<std::size_t>(0.99 * static_cast<double>(errors.size() - 1))];
    a.max = errors.back();
  }
  return a;
}

/// `start`: what param holds when the run begins (start+newton:K reads it; empty: zeros).
Accuracy accuracy_of(const search::LocalSearch& search, const QuerySet& set,
                     const std::vector<double>& start) {
  const std::size_t n = set.count();
  std::vector<double> param = start.empty() ? std::vector<double>(2 * n) : start;
  std::vector<Status> status(n);
  std::vector<std::int32_t> steps(n);
  search.run(n, set.raw.data(), search::Results<double>{param.data(), nullptr, status.data(), steps.data()},
             1);
  return accuracy_from(set, param, status, steps);
}

// The exported C headers of bilinear-8 and gregory-48 (c_header_entry.c): one call per query, and the batch.
extern "C" void cnn_bench_c_header_one(int gregory, std::size_t n, const double* raw, double* out,
                                       int* status);
extern "C" void cnn_bench_c_header_batch(int gregory, std::size_t n, const double* raw, double* out,
                                         int* status);

/// The header's accuracy, its return codes read as statuses (0 ok, 1 degenerate or invalid, 2 out of domain).
Accuracy c_header_accuracy(const QuerySet& set) {
  const std::size_t n = set.count();
  std::vector<double> param(2 * n);
  std::vector<int> code(n);
  cnn_bench_c_header_batch(set.kind == SurfaceKind::kGregory ? 1 : 0, n, set.raw.data(), param.data(),
                           code.data());
  std::vector<Status> status(n);
  for (std::size_t i = 0; i < n; ++i) {
    status[i] = code[i] == 0 ? Status::kOk : code[i] == 2 ? Status::kOutOfDomain : Status::kDegenerate;
  }
  return accuracy_from(set, param, status, std::vector<std::int32_t>(n, 0));
}

/// One method to time.
struct Case {
  SurfaceKind kind;
  std::string method;
  std::string network;  ///< file name in the weights folder, or empty
  bool check_domain = true;
  double start_offset =
      0.0;  ///< start+newton:K: the starts are the labels moved this far (a time step's drift)
  bool whole_face = false;   ///< SearchOptions::closest_point_on_face (the boundary step for answers outside)
  bool inside_only = false;  ///< on the queries this method (without the boundary step) answers inside
};

std::string case_name(const Case& c) {
  std::string name = std::string(to_string(c.kind)) + "/" + c.method;
  if (!c.network.empty())
    name += "[" + c.network.substr(0, c.network.find(".h5")) + (c.check_domain ? "" : ",no-domain") + "]";
  if (search::Method::parse(c.method).needs_start()) {
    char offset[32];
    std::snprintf(offset, sizeof offset, "[%g off]", c.start_offset);
    name += offset;
  }
  if (c.whole_face) name += "[whole-face]";
  if (c.inside_only) name += "[inside]";
  return name;
}

/// The queries of `set` that case `c`'s method, without the boundary step, answers with status ok.
QuerySet answered_inside(const QuerySet& set, const Case& c, const search::NetworkModel* model) {
  search::SearchOptions options;
  options.check_domain = c.check_domain;
  const search::LocalSearch plain(c.kind, search::Method::parse(c.method), options, model);
  const std::size_t n = set.count();
  std::vector<double> param(2 * n);
  std::vector<Status> status(n);
  plain.run(n, set.raw.data(), search::Results<double>{param.data(), nullptr, status.data()}, 1);
  QuerySet inside;
  inside.kind = set.kind;
  const auto stride = static_cast<std::size_t>(search::LocalSearch::raw_columns(set.kind));
  for (std::size_t i = 0; i < n; ++i) {
    if (status[i] != Status::kOk) continue;
    inside.raw.insert(inside.raw.end(), set.raw.begin() + static_cast<std::ptrdiff_t>(i * stride),
                      set.raw.begin() + static_cast<std::ptrdiff_t>((i + 1) * stride));
    inside.labels.push_back(set.labels[i]);
  }
  return inside;
}

void set_counters(benchmark::State& state, const search::FlopCount& flops, const Accuracy& a) {
  state.counters["flops_double"] = flops.in_double;
  state.counters["flops_float"] = flops.in_float;
  state.counters["mean_error"] = a.mean;
  state.counters["p99_error"] = a.p99;
  state.counters["max_error"] = a.max;
  state.counters["failures"] = a.failures;
  state.counters["steps"] = a.steps;
}

/// Registers the benchmark `name` of a method over `n` queries: `setup` (outside the timing) gives the pass,
/// a callable that answers the n queries once with the buffers it holds; each iteration runs it and
/// clobbers memory. Items are the queries, with the method's counters; real time, in microseconds.
template <class Setup>
void register_passes(const std::string& name, std::size_t n, const search::FlopCount& flops,
                     const Accuracy& acc, Setup setup) {
  benchmark::RegisterBenchmark(name.c_str(),
                               [=](benchmark::State& state) {
                                 auto pass = setup();
                                 for (auto _ : state) {
                                   pass();
                                   benchmark::ClobberMemory();
                                 }
                                 state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
                                 set_counters(state, flops, acc);
                               })
      ->UseRealTime()
      ->Unit(benchmark::kMicrosecond);
}

template <class Real>
void gemm(benchmark::State& state, int threads) {
  const int n = 768;
  Eigen::setNbThreads(threads);
  using M = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>;
  const M a = M::Random(n, n), b = M::Random(n, n);
  M c(n, n);
  for (auto _ : state) {
    c.noalias() = a * b;
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  // items = flops: items_per_second is the rate.
  state.SetItemsProcessed(state.iterations() *
                          static_cast<std::int64_t>(2.0 * n * n * static_cast<double>(n)));
  Eigen::setNbThreads(0);
}

/// Where a network method's time goes (search::detail::network_stages, which runs in the kernels' own
/// translation unit): its stages cumulatively over the same blocks as LocalSearch::run, one thread.
void network_parts(benchmark::State& state, const std::vector<double>& raw, const search::NetworkModel& model,
                   int stage) {
  const auto stride = static_cast<std::size_t>(search::LocalSearch::raw_columns(model.surface()));
  const std::size_t count = raw.size() / stride;
  double sink = 0.0;
  std::size_t done = 0;
  for (auto _ : state) {
    done = 0;
    sink += search::detail::network_stages(model, raw.data(), count, stage, done);
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(done));
}

Args parse_own_flags(int& argc, char** argv) {
  Args a;
  int out = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if ((k == "--queries" || k == "--weights" || k == "--seed" || k == "--threads" || k == "--pairs") &&
        i + 1 < argc) {
      const std::string v = argv[++i];
      if (k == "--threads") {
        a.threads.clear();
        for (std::size_t at = 0; at < v.size();) {
          const std::size_t comma = std::min(v.find(',', at), v.size());
          const int t = std::atoi(v.substr(at, comma - at).c_str());
          if (t < 1) {
            std::fprintf(
                stderr,
                "bench_search: --threads wants positive thread counts separated by commas, got '%s'\n",
                v.c_str());
            std::exit(2);
          }
          a.threads.push_back(t);
          at = comma + 1;
        }
      }
      if (k == "--queries") a.queries = static_cast<std::size_t>(std::atol(v.c_str()));
      if (k == "--weights") a.weights = v;
      if (k == "--seed") a.seed = static_cast<std::uint64_t>(std::atoll(v.c_str()));
      if (k == "--pairs") a.pairs = v;
    } else {
      argv[out++] = argv[i];
    }
  }
  argc = out;
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = parse_own_flags(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;

  // 1. The queries and the networks, shared by every method.
  static const std::map<SurfaceKind, QuerySet> sets = [&] {
    std::map<SurfaceKind, QuerySet> m;
    QuerySet scene;
    if (!args.pairs.empty()) scene = queries_from_pairs(args.pairs, args.queries);
    for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
      m[kind] =
          !args.pairs.empty() && scene.kind == kind ? scene : make_queries(kind, args.queries, args.seed);
    }
    return m;
  }();
  static std::map<std::string, std::unique_ptr<search::NetworkModel>> networks;
  for (const char* file : {"bilinear-8.h5", "bilinear-32-32.h5", "gregory-48.h5", "gregory-32.h5"}) {
    const io::TrainedNetwork<float> trained = io::read_network<float>(args.weights + "/" + file);
    networks[file] = std::make_unique<search::NetworkModel>(trained.network, trained.domain);
  }

  // 2. The methods.
  const SurfaceKind bl = SurfaceKind::kBilinear, gr = SurfaceKind::kGregory;
  // Each surface's cold methods (in the table's order: bilinear first), then its networks.
  std::vector<Case> cases;
  const auto cold = [&](SurfaceKind kind, std::initializer_list<const char*> extra) {
    for (const char* method : {"newton:1", "newton:3", "newton:5", "newton:10", "newton", "closed_form",
                               "closed_form+newton:1", "closed_form+newton:2"}) {
      cases.push_back({kind, method, ""});
    }
    for (const char* method : extra) cases.push_back({kind, method, ""});
  };
  cold(bl, {"closed_form+newton:3", "four_triangles"});
  for (const Case& c : std::vector<Case>{{bl, "network", "bilinear-8.h5"},
                                         {bl, "network", "bilinear-8.h5", false},
                                         {bl, "network", "bilinear-32-32.h5"},
                                         {bl, "network+newton:1", "bilinear-8.h5"},
                                         {bl, "network+newton:3", "bilinear-8.h5"},
                                         {bl, "network+newton:1", "bilinear-32-32.h5"},
                                         {bl, "network+newton:3", "bilinear-32-32.h5"}}) {
    cases.push_back(c);
  }
  cold(gr, {});
  for (const Case& c : std::vector<Case>{{gr, "network", "gregory-48.h5"},
                                         {gr, "network", "gregory-48.h5", false},
                                         {gr, "network", "gregory-32.h5"},
                                         {gr, "network+newton:1", "gregory-48.h5"},
                                         {gr, "network+newton:2", "gregory-48.h5"},
                                         {gr, "network+newton:3", "gregory-48.h5"}}) {
    cases.push_back(c);
  }
  // The caller's own starts (an FE code's previous time step), 0.01 off: after the others, so that the table
  // keeps its order; one per surface and K.
  for (const SurfaceKind kind : {bl, gr}) {
    for (const char* method : {"start+newton:1", "start+newton:2", "start+newton:3"}) {
      cases.push_back({kind, method, "", true, 0.01});
    }
  }
  // The closest point of the whole face (the surface search's): what the boundary step costs queries whose
  // answers lie inside (the paper's data sets), beside the same methods without it.
  // Side by side on the queries the method answers inside (ok), with and without the step: the acceptance's
  // "at most 10% on answers inside a face"; and with the step on all queries.
  for (const Case& c : std::vector<Case>{{bl, "newton:5", ""},
                                         {bl, "closed_form", ""},
                                         {bl, "network", "bilinear-8.h5"},
                                         {bl, "four_triangles", ""},
                                         {gr, "newton:5", ""},
                                         {gr, "network", "gregory-48.h5"}}) {
    for (const bool whole : {false, true}) {
      Case inside = c;
      inside.inside_only = true;
      inside.whole_face = whole;
      cases.push_back(inside);
    }
    Case all = c;
    all.whole_face = true;
    cases.push_back(all);
  }

  // 3. One benchmark per method and mode; accuracy once per method.
  for (const Case& c : cases) {
    search::SearchOptions options;
    options.check_domain = c.check_domain;
    options.closest_point_on_face = c.whole_face;
    const search::NetworkModel* model = c.network.empty() ? nullptr : networks.at(c.network).get();
    auto search =
        std::make_shared<const search::LocalSearch>(c.kind, search::Method::parse(c.method), options, model);
    static std::deque<QuerySet> subsets;  // references to them stay valid while the benchmarks run
    const QuerySet& set =
        c.inside_only ? subsets.emplace_back(answered_inside(sets.at(c.kind), c, model)) : sets.at(c.kind);
    // start+newton:K overwrites its starts: each run copies them in first (2 doubles per query, in the time).
    const std::vector<double> start = search->method().needs_start()
                                          ? testing::starts_near(set.labels, set.kind, c.start_offset, 11)
                                          : std::vector<double>{};
    const Accuracy acc = accuracy_of(*search, set, start);
    const search::FlopCount flops = search::flops_per_query(c.kind, search->method(), model, acc.steps);
    const std::size_t n = set.count();
    const auto stride = static_cast<std::size_t>(search::LocalSearch::raw_columns(c.kind));

    register_passes(case_name(c) + "/one", n, flops, acc, [=, &set] {
      return [=, &set, param = std::vector<double>(2 * n), status = std::vector<Status>(n)]() mutable {
        for (std::size_t i = 0; i < n; ++i) {
          if (!start.empty()) {
            param[2 * i] = start[2 * i];
            param[2 * i + 1] = start[2 * i + 1];
          }
          search->run(1, set.raw.data() + i * stride,
                      search::Results<double>{param.data() + 2 * i, nullptr, status.data() + i}, 1);
        }
      };
    });
    // The same one at a time through the C interface (contactnn_search_run, count = 1: the call an FE code
    // makes per pair), for the methods a handle takes as they are (no caller's starts, no whole-face step,
    // the domain checked); scripts/bench-search's table leaves these rows out.
    if (!search->method().needs_start() && !c.whole_face && !c.inside_only && c.check_domain) {
      const std::string file = c.network.empty() ? std::string() : args.weights + "/" + c.network;
      benchmark::RegisterBenchmark(
          (case_name(c) + "/c-api-one").c_str(),
          [=, &set](benchmark::State& state) {
            contactnn_options copts;
            contactnn_options_init(&copts);
            copts.threads = 1;
            contactnn_search* handle = nullptr;
            if (contactnn_search_create(&handle, static_cast<int>(c.kind), c.method.c_str(), file.c_str(),
                                        &copts) != 0) {
              state.SkipWithError(contactnn_last_error());
              return;
            }
            std::vector<double> param(2 * n);
            std::vector<int> status(n);
            for (auto _ : state) {
              for (std::size_t i = 0; i < n; ++i) {
                contactnn_search_run(handle, 1, set.raw.data() + i * stride, param.data() + 2 * i, nullptr,
                                     status.data() + i, nullptr);
              }
              benchmark::ClobberMemory();
            }
            contactnn_search_destroy(handle);
            state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
            set_counters(state, flops, acc);
          })
          ->UseRealTime()
          ->Unit(benchmark::kMicrosecond);
    }
    for (const int threads : args.threads) {
      register_passes(case_name(c) + "/batched/threads:" + std::to_string(threads), n, flops, acc, [=, &set] {
        return [=, &set, param = std::vector<double>(2 * n), status = std::vector<Status>(n)]() mutable {
          if (!start.empty()) std::copy(start.begin(), start.end(), param.begin());
          search->run(n, set.raw.data(), search::Results<double>{param.data(), nullptr, status.data()},
                      threads);
        };
      });
    }
  }
  // 3b. The exported C headers of the two paper networks (the network method's flops: the same arithmetic).
  for (const auto& [kind, file] : {std::pair{SurfaceKind::kBilinear, "bilinear-8.h5"},
                                   std::pair{SurfaceKind::kGregory, "gregory-48.h5"}}) {
    const QuerySet& set = sets.at(kind);
    const Accuracy acc = c_header_accuracy(set);
    const search::NetworkModel* model = networks.at(file).get();
    const search::FlopCount flops =
        search::flops_per_query(kind, search::Method::parse("network"), model, 0.0);
    const std::string name = std::string(to_string(kind)) + "/c-header[" +
                             std::string(file).substr(0, std::string(file).find(".h5")) + "]";
    const int gregory = kind == SurfaceKind::kGregory ? 1 : 0;
    const std::size_t n = set.count();
    for (const bool batched : {false, true}) {
      register_passes(name + (batched ? "/batched/threads:1" : "/one"), n, flops, acc, [=, &set] {
        return [=, &set, param = std::vector<double>(2 * n), code = std::vector<int>(n)]() mutable {
          (batched ? cnn_bench_c_header_batch : cnn_bench_c_header_one)(gregory, n, set.raw.data(),
                                                                        param.data(), code.data());
        };
      });
    }
  }
  // 3c. FaceSearch on the other faces of SPEC 9 (tri3, tri6, quad8): random faces of unit size, corners
  // warped by
  //     0.15, mid-side nodes up to 0.1 of their edge off its midpoint, at a random position, orientation and
  //     scale, S within 0.1 of the face over a foot inside it (tests/search/face_queries.hpp); the reference
  //     is the projection's closest point on the true face (the queries whose point lies inside it).
  for (const search::FaceKind kind :
       {search::FaceKind::kTri3, search::FaceKind::kTri6, search::FaceKind::kQuad8}) {
    static std::deque<std::pair<std::vector<double>, std::vector<double>>> face_sets;  // raw rows, labels
    auto& [raw, labels] = face_sets.emplace_back();
    std::mt19937_64 rng(args.seed + 100 + static_cast<std::uint64_t>(kind));
    while (labels.size() < 2 * args.queries) {
      const testing::FaceQuery q = testing::random_face_query(kind, rng);
      const projection::FaceClosestPoint ref = testing::reference_point(kind, q);
      if (ref.status != Status::kOk || ref.location != Location::kFace) continue;
      testing::append_row(q, raw);
      labels.insert(labels.end(), {ref.param[0], ref.param[1]});
    }
    const std::size_t n = args.queries;
    const auto stride = static_cast<std::size_t>(search::face_raw_columns(kind));
    const std::vector<std::string> methods = kind == search::FaceKind::kTri3
                                                 ? std::vector<std::string>{"closed_form", "newton:1"}
                                                 : std::vector<std::string>{"closed_form",
                                                                            "newton:1",
                                                                            "newton:2",
                                                                            "newton:3",
                                                                            "newton:5",
                                                                            "newton",
                                                                            "closed_form+newton:1",
                                                                            "closed_form+newton:2",
                                                                            "closed_form+newton:3"};
    // The shipped general network of the face type (data/weights/<kind>-48-48.h5, scripts/face-table --ship).
    static std::deque<std::unique_ptr<search::FaceNetwork>> face_networks;
    const search::FaceNetwork* net = nullptr;
    std::vector<std::string> all = methods;
    if (kind != search::FaceKind::kTri3) {
      face_networks.push_back(
          io::load_face_network(args.weights + "/" + std::string(search::to_string(kind)) + "-48-48.h5"));
      net = face_networks.back().get();
      for (const char* m : {"network", "network+newton:1", "network+newton:2"}) all.emplace_back(m);
    }
    for (const std::string& method : all) {
      const bool uses = search::Method::parse(method).needs_network();
      auto search = std::make_shared<const search::FaceSearch>(kind, search::Method::parse(method),
                                                               search::SearchOptions{}, uses ? net : nullptr);
      std::vector<double> param(2 * n);
      std::vector<Status> status(n);
      std::vector<std::int32_t> steps(n);
      search->run<double>(n, raw.data(),
                          search::Results<double>{param.data(), nullptr, status.data(), steps.data()}, 1);
      Accuracy acc;
      std::vector<double> errors;
      double step_sum = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        step_sum += steps[i];
        if (status[i] != Status::kOk && status[i] != Status::kOutOfDomain) {
          ++acc.failures;
          continue;
        }
        errors.push_back(std::max(std::fabs(param[2 * i] - labels[2 * i]),
                                  std::fabs(param[2 * i + 1] - labels[2 * i + 1])));
      }
      std::sort(errors.begin(), errors.end());
      for (const double e : errors)
        acc.mean += e / static_cast<double>(std::max<std::size_t>(errors.size(), 1));
      acc.max = errors.empty() ? 0.0 : errors.back();
      acc.p99 = errors.empty() ? 0.0 : errors[std::min(errors.size() - 1, errors.size() * 99 / 100)];
      acc.steps = step_sum / static_cast<double>(n);
      const search::FlopCount flops =
          search::face_flops_per_query(kind, search->method(), uses ? net : nullptr, acc.steps);
      const std::string name = std::string(search::to_string(kind)) + "/" + method +
                               (uses ? "[" + std::string(search::to_string(kind)) + "-48-48]" : "");
      const std::vector<double>* rows = &raw;
      register_passes(name + "/one", n, flops, acc, [=] {
        return [=, p = std::vector<double>(2 * n), st = std::vector<Status>(n)]() mutable {
          for (std::size_t i = 0; i < n; ++i) {
            search->run<double>(1, rows->data() + i * stride,
                                search::Results<double>{p.data() + 2 * i, nullptr, st.data() + i}, 1);
          }
        };
      });
      for (const int threads : args.threads) {
        register_passes(name + "/batched/threads:" + std::to_string(threads), n, flops, acc, [=] {
          return [=, p = std::vector<double>(2 * n), st = std::vector<Status>(n)]() mutable {
            search->run<double>(n, rows->data(), search::Results<double>{p.data(), nullptr, st.data()},
                                threads);
          };
        });
      }
    }
  }
  // 4. The stages of the two paper networks (parts/<surface>/<network>/<stage>; scripts/bench-search prints
  //    the differences).
  const char* stages[] = {"", "1-load", "2-frame", "3-domain", "4-network"};
  for (int stage = 1; stage <= 4; ++stage) {
    const std::string suffix = std::string("/") + stages[stage];
    benchmark::RegisterBenchmark(("parts/bilinear/bilinear-8" + suffix).c_str(),
                                 [stage](benchmark::State& state) {
                                   network_parts(state, sets.at(SurfaceKind::kBilinear).raw,
                                                 *networks.at("bilinear-8.h5"), stage);
                                 })
        ->UseRealTime()
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("parts/gregory/gregory-48" + suffix).c_str(),
                                 [stage](benchmark::State& state) {
                                   network_parts(state, sets.at(SurfaceKind::kGregory).raw,
                                                 *networks.at("gregory-48.h5"), stage);
                                 })
        ->UseRealTime()
        ->Unit(benchmark::kMicrosecond);
  }
  for (const int threads : args.threads) {
    benchmark::RegisterBenchmark(("gemm/float/threads:" + std::to_string(threads)).c_str(), gemm<float>,
                                 threads)
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("gemm/double/threads:" + std::to_string(threads)).c_str(), gemm<double>,
                                 threads)
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
  }
  std::fprintf(stderr, "bench_search: %zu bilinear and %zu Gregory queries (labels ok), seed %llu%s%s\n",
               sets.at(bl).count(), sets.at(gr).count(), static_cast<unsigned long long>(args.seed),
               args.pairs.empty() ? "" : "; pairs of ", args.pairs.c_str());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
