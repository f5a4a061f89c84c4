// Description: the global search's cost per slave node on a generated scene of at least 1e5 slave nodes: the
// surface search of SPEC 9 (k-d tree over face centres, the closest point of every candidate face with edges
// and vertices, pseudo-normal gap) beside the paper's nearest-node search of SPEC 7 (k-d tree over master
// nodes, the segment test, the reference projection on each segment at the node), both labelling with the
// same reference projection, at 1 and 2 threads. The master surface is a wavy sheet of 300 x 300 bilinear
// faces (node z = 0.3 sin(x / 7) cos(y / 5), unit spacing); the slave nodes lie at random above and below it
// (|z| offset up to half an element), a fixed seed.
//
// Sample runs:
//   build/bench/bench_surface_search
//   build/bench/bench_surface_search --slaves 200000 --benchmark_repetitions=3
//
// Counters per benchmark: ns_per_slave (wall time / slave nodes), candidates (mean faces whose closest point
// was computed per slave node for the surface search; segments that passed the segment test for the
// nearest-node search), found (slave nodes with a point).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "contact/global_search.hpp"
#include "contact/surface_search.hpp"
#include "contact/tracking.hpp"
#include "mesh/grid_surface.hpp"

namespace {

using namespace contactnn;

struct Scene {
  mesh::SurfaceMesh master;
  std::vector<geometry::Vec3> normals;
  std::vector<long> ids;
  std::vector<geometry::Vec3> slaves;
};

Scene make_scene(long slave_count) {
  constexpr int kFaces = 300;
  const auto height = [](double x, double y) { return 0.3 * std::sin(x / 7.0) * std::cos(y / 5.0); };
  Scene s;
  s.master = testing::grid_surface(kFaces, kFaces,
                                   [&](double i, double j) { return geometry::Vec3(i, j, height(i, j)); });
  for (std::size_t q = 0; q < s.master.segments.size(); ++q) {
    s.master.segment_faces.push_back({static_cast<int>(q), 1});
    s.master.segment_element_ids.push_back(static_cast<long>(q) + 1);
  }
  s.normals = mesh::node_normals(s.master);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> xy(0.0, kFaces), dz(-0.5, 0.5);
  for (long i = 0; i < slave_count; ++i) {
    const double x = xy(rng), y = xy(rng);
    s.ids.push_back(i + 1);
    s.slaves.emplace_back(x, y, height(x, y) + dz(rng));
  }
  return s;
}

long g_slaves = 100000;

const Scene& scene() {
  static const Scene s = make_scene(g_slaves);
  return s;
}

void report(benchmark::State& state, const std::vector<contact::NodeSegmentPair>& pairs) {
  double candidates = 0.0, reference = 0.0;
  long found = 0;
  for (const auto& p : pairs) {
    candidates += p.candidates;
    reference += p.reference_faces;
    found += p.status == contact::PairStatus::kFound;
  }
  const double n = static_cast<double>(pairs.size());
  state.counters["candidates"] = candidates / n;
  state.counters["reference_faces"] = reference / n;
  state.counters["found"] = static_cast<double>(found);
  state.counters["ns_per_slave"] = benchmark::Counter(
      n * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// The surface search with the narrow phase state.range(1) (0: certified, 1: the reference on every face).
void surface(benchmark::State& state) {
  const Scene& s = scene();
  omp_set_num_threads(static_cast<int>(state.range(0)));
  contact::SearchOptions options;
  options.narrow = state.range(1) == 0 ? contact::NarrowPhase::kCertified : contact::NarrowPhase::kReference;
  std::vector<contact::NodeSegmentPair> pairs;
  for (auto _ : state) {
    contact::surface_search(s.master, s.normals, s.ids, s.slaves, options, pairs);
    benchmark::DoNotOptimize(pairs.data());
  }
  report(state, pairs);
}

/// The per-state part alone: the searcher's face index (spheres, boxes, certificates, node-to-face lists) for
/// the 90,000 faces; counters per slave node of the scene as the searches', and per face.
void searcher_build(benchmark::State& state) {
  const Scene& s = scene();
  contact::SearchOptions options;
  for (auto _ : state) {
    const contact::SurfaceSearcher searcher(s.master, s.normals, options);
    benchmark::DoNotOptimize(searcher.capture());
  }
  state.counters["ns_per_slave"] =
      benchmark::Counter(static_cast<double>(s.ids.size()) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["ns_per_face"] =
      benchmark::Counter(static_cast<double>(s.master.face_count()) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// The tracked search (contact::SurfaceTracker): the slave nodes move by 0.001 (1e-3 of a face) in z per
/// increment; one iteration is one increment after the first.
void surface_tracked(benchmark::State& state) {
  const Scene& s = scene();
  omp_set_num_threads(static_cast<int>(state.range(0)));
  contact::SearchOptions options;
  options.narrow = state.range(1) == 0 ? contact::NarrowPhase::kCertified : contact::NarrowPhase::kReference;
  contact::SurfaceTracker tracker(options);
  std::vector<geometry::Vec3> slaves = s.slaves;
  std::vector<contact::NodeSegmentPair> pairs;
  tracker.step(s.master, s.normals, s.ids, slaves, pairs);
  for (auto _ : state) {
    for (auto& x : slaves) x.z() += 0.001;
    tracker.step(s.master, s.normals, s.ids, slaves, pairs);
    benchmark::DoNotOptimize(pairs.data());
  }
  report(state, pairs);
}

void nearest_node(benchmark::State& state) {
  const Scene& s = scene();
  omp_set_num_threads(static_cast<int>(state.range(0)));
  contact::SearchOptions options;
  std::vector<contact::NodeSegmentPair> pairs;
  for (auto _ : state) {
    pairs = contact::global_search(s.master, s.normals, s.ids, s.slaves, options);
    benchmark::DoNotOptimize(pairs.data());
  }
  report(state, pairs);
}

}  // namespace

int main(int argc, char** argv) {
  // Our own flag first: --slaves N (default 100000).
  std::vector<char*> rest = {argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--slaves") == 0 && i + 1 < argc) {
      g_slaves = std::strtol(argv[++i], nullptr, 10);
      if (g_slaves < 1) {
        std::fprintf(stderr, "bench_surface_search: --slaves wants a positive count, got '%s'\n", argv[i]);
        return 2;
      }
    } else {
      rest.push_back(argv[i]);
    }
  }
  int rest_count = static_cast<int>(rest.size());
  benchmark::Initialize(&rest_count, rest.data());
  benchmark::RegisterBenchmark("global/searcher_build", searcher_build)
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  for (int threads : {1, 2}) {
    for (int narrow : {0, 1}) {
      const char* name = narrow == 0 ? "global/surface" : "global/surface_reference";
      const char* tracked = narrow == 0 ? "global/surface_tracked" : "global/surface_tracked_reference";
      for (const auto& [label, run] : {std::pair{name, &surface}, std::pair{tracked, &surface_tracked}}) {
        benchmark::RegisterBenchmark(label, run)
            ->Args({threads, narrow})
            ->ArgNames({"threads", "narrow"})
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
      }
    }
    benchmark::RegisterBenchmark("global/nearest_node", nearest_node)
        ->Arg(threads)
        ->ArgName("threads")
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
