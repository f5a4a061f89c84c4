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
// history/fresh and history/tracked: the large history's geometry and motion (scripts/make-large-history: a
// wavy top of 320 x 320 unit quad4 faces, z = 0.2 sin(x / 5) cos(y / 7); --history-slaves N x N slave nodes
// at spacing 0.3, 0.05 above it; 9 increments pressed 0.02 down, slid 0.05 along x, turned 0.05 degree),
// in exact doubles and without the deck or the .frd: one iteration is the whole history, fresh at every
// increment (surface_search) or tracked (SurfaceTracker) over the increments after the first; ns_per_slave
// is per slave node and increment. Arguments: surface 0 bilinear, 1 Gregory; narrow 0 the search, 1 the
// search before the grid and the certificate (NarrowPhase::kReference: a k-d tree, the reference projection
// on every face, the tracker's lists). scripts/bench-surface runs them and writes results/surface-search.md.
//
// quadratic/quad8_fresh, quadratic/tri6_fresh and their _tracked: the surface search and the tracker (as
// global/surface and global/surface_tracked) on a wavy sheet of quadratic faces (Issue 38: the
// CurvedCertificate) in the manner of the large history: 120 x 120 unit quad8 faces (C3D20 tops) or cells
// of two tri6 each (C3D10 tops), every node (mid-side nodes included) on z = 0.2 sin(x / 5) cos(y / 7); a
// square grid of at least --slaves slave nodes at spacing 0.3 over its middle, 0.05 above it; tracked: moved
// 0.001 down per increment. Arguments: threads; narrow 0 certified, 1 the reference on every face.
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
#include <utility>
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
long g_history_slaves = 1000;

template <class Answer>
void report(benchmark::State& state, const std::vector<Answer>& pairs);

/// The large history (header): the master, its normals, the slave ids and the positions per increment.
struct History {
  mesh::SurfaceMesh master;
  std::vector<geometry::Vec3> normals;
  std::vector<long> ids;
  std::vector<std::vector<geometry::Vec3>> positions;
};

const History& history() {
  static const History h = [] {
    constexpr int kFaces = 320, kIncrements = 9;
    const auto top = [](double x, double y) { return 0.2 * std::sin(x / 5.0) * std::cos(y / 7.0); };
    History s;
    s.master = testing::searched_grid_surface(
        kFaces, kFaces, [&](double i, double j) { return geometry::Vec3(i, j, top(i, j)); });
    s.normals = mesh::node_normals(s.master);
    const long n = g_history_slaves;
    const double spacing = 0.3, offset = 0.5 * (kFaces - spacing * static_cast<double>(n - 1));
    std::vector<geometry::Vec3> base;
    for (long k = 0; k < n * n; ++k) {
      const double x = offset + spacing * static_cast<double>(k % n),
                   y = offset + spacing * static_cast<double>(k / n);
      base.emplace_back(x, y, top(x, y) + 0.05);
      s.ids.push_back(k + 1);
    }
    const int press = kIncrements / 3;
    const double centre = 0.5 * kFaces;
    double dz = 0.0, dx = 0.0, angle = 0.0;
    for (int inc = 1; inc <= kIncrements; ++inc) {
      if (inc <= press)
        dz -= 0.02;
      else if (inc <= 2 * press)
        dx += 0.05;
      else
        angle += 0.05 * 3.14159265358979323846 / 180.0;
      const double c = std::cos(angle), sn = std::sin(angle);
      std::vector<geometry::Vec3> x = base;
      for (auto& p : x) {
        const double rx = p.x() - centre, ry = p.y() - centre;
        p = geometry::Vec3(centre + c * rx - sn * ry + dx, centre + sn * rx + c * ry, p.z() + dz);
      }
      s.positions.push_back(std::move(x));
    }
    return s;
  }();
  return h;
}

contact::SearchOptions history_options(const benchmark::State& state) {
  contact::SearchOptions options;
  options.surface =
      state.range(1) == 0 ? contactnn::SurfaceKind::kBilinear : contactnn::SurfaceKind::kGregory;
  options.narrow = state.range(2) == 0 ? contact::NarrowPhase::kCertified : contact::NarrowPhase::kReference;
  return options;
}

/// One history benchmark: `run(options, pairs)` is one iteration over `states` slave-node states.
template <class Run>
void history_run(benchmark::State& state, std::size_t states, Run&& run) {
  const History& h = history();
  omp_set_num_threads(static_cast<int>(state.range(0)));
  const contact::SearchOptions options = history_options(state);
  std::vector<contact::Contact> pairs;  // the answers an FE code's handle reads
  for (auto _ : state) {
    run(options, pairs);
    benchmark::DoNotOptimize(pairs.data());
  }
  report(state, pairs);  // the last increment's counters; ns_per_slave over them all
  state.counters["ns_per_slave"] =
      benchmark::Counter(static_cast<double>(h.ids.size() * states) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void history_fresh(benchmark::State& state) {
  const History& h = history();
  // The faces' tables' memory, kept from one increment to the next (as an FE code's handle keeps it).
  contact::SearchStorage storage;
  history_run(state, h.positions.size(), [&](const contact::SearchOptions& options, auto& pairs) {
    for (const auto& x : h.positions)
      contact::surface_search(h.master, h.normals, h.ids, x, options, pairs, &storage);
  });
}

/// The increments after the first (the first, the tracker's fresh search, untimed).
void history_tracked(benchmark::State& state) {
  const History& h = history();
  history_run(state, h.positions.size() - 1, [&](const contact::SearchOptions& options, auto& pairs) {
    state.PauseTiming();
    contact::SurfaceTracker tracker(options);
    tracker.step(h.master, h.normals, h.ids, h.positions[0], pairs);
    state.ResumeTiming();
    for (std::size_t i = 1; i < h.positions.size(); ++i)
      tracker.step(h.master, h.normals, h.ids, h.positions[i], pairs);
  });
}

/// The quadratic sheet (header): quad8 faces (`triangles` false) or tri6 faces, nodes on the doubled grid.
Scene make_quadratic_scene(long slave_count, bool triangles) {
  const int cells = 120;
  const auto height = [](double x, double y) { return 0.2 * std::sin(x / 5.0) * std::cos(y / 7.0); };
  Scene s;
  mesh::SurfaceMesh& m = s.master;
  // Node (a, b) of the doubled grid at (a / 2, b / 2); a quad8 sheet has no node at a cell's centre.
  const int n = 2 * cells + 1;
  std::vector<int> index(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), -1);
  for (int b = 0; b < n; ++b) {
    for (int a = 0; a < n; ++a) {
      if (!triangles && a % 2 == 1 && b % 2 == 1) continue;
      index[static_cast<std::size_t>(a + n * b)] = m.node_count();
      m.node_ids.push_back(static_cast<long>(m.node_ids.size()) + 1);
      m.mesh_nodes.push_back(static_cast<int>(m.mesh_nodes.size()));
      m.positions.emplace_back(0.5 * a, 0.5 * b, height(0.5 * a, 0.5 * b));
    }
  }
  const auto at = [&](int a, int b) { return index[static_cast<std::size_t>(a + n * b)]; };
  long element = 1;
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const int a = 2 * i, b = 2 * j;
      if (!triangles) {
        m.segments.push_back({at(a, b), at(a + 2, b), at(a + 2, b + 2), at(a, b + 2)});
        m.segment_midsides.push_back({at(a + 1, b), at(a + 2, b + 1), at(a + 1, b + 2), at(a, b + 1)});
        m.segment_faces.push_back({static_cast<int>(element - 1), 2});
        m.segment_element_ids.push_back(element++);
        continue;
      }
      // Two triangles across the diagonal (a, b)-(a + 2, b + 2), its mid-side node the cell's centre.
      m.extra_faces.push_back({at(a, b), at(a + 2, b), at(a + 2, b + 2), -1});
      m.extra_face_midsides.push_back({at(a + 1, b), at(a + 2, b + 1), at(a + 1, b + 1), -1});
      m.extra_faces.push_back({at(a, b), at(a + 2, b + 2), at(a, b + 2), -1});
      m.extra_face_midsides.push_back({at(a + 1, b + 1), at(a + 1, b + 2), at(a, b + 1), -1});
      for (int k = 0; k < 2; ++k) {
        m.extra_face_faces.push_back({static_cast<int>(element - 1), 1});
        m.extra_face_element_ids.push_back(element++);
      }
    }
  }
  mesh::set_adjacency(m);
  s.normals = mesh::node_normals(m);
  const auto side = static_cast<long>(std::ceil(std::sqrt(static_cast<double>(slave_count))));
  const double spacing = 0.3, offset = 0.5 * (cells - spacing * static_cast<double>(side - 1));
  for (long k = 0; k < side * side; ++k) {
    const double x = offset + spacing * static_cast<double>(k % side),
                 y = offset + spacing * static_cast<double>(k / side);
    s.ids.push_back(k + 1);
    s.slaves.emplace_back(x, y, height(x, y) + 0.05);
  }
  return s;
}

const Scene& quadratic_scene(bool triangles) {
  static const Scene quad8 = make_quadratic_scene(g_slaves, false);
  static const Scene tri6 = make_quadratic_scene(g_slaves, true);
  return triangles ? tri6 : quad8;
}

const Scene& scene() {
  static const Scene s = make_scene(g_slaves);
  return s;
}

template <class Answer>
void report(benchmark::State& state, const std::vector<Answer>& pairs) {
  double candidates = 0.0, reference = 0.0, iterations = 0.0;
  long found = 0;
  for (const auto& p : pairs) {
    candidates += p.candidates;
    reference += p.reference_faces;
    found += p.status == contact::PairStatus::kFound;
    if constexpr (requires { p.iterations; }) iterations += p.iterations;
  }
  const double n = static_cast<double>(pairs.size());
  state.counters["candidates"] = candidates / n;
  if (iterations > 0.0) state.counters["iterations"] = iterations / n;
  state.counters["reference_faces"] = reference / n;
  state.counters["found"] = static_cast<double>(found);
  state.counters["ns_per_slave"] = benchmark::Counter(
      n * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// The scene benchmarks' options: the threads state.range(0) (set here), the narrow phase state.range(1) (0:
/// certified, 1: the reference on every face).
contact::SearchOptions scene_options(const benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  contact::SearchOptions options;
  options.narrow = state.range(1) == 0 ? contact::NarrowPhase::kCertified : contact::NarrowPhase::kReference;
  return options;
}

/// The surface search of scene `s` (scene_options), its answers as `Answer`s.
template <class Answer>
void scene_fresh(benchmark::State& state, const Scene& s) {
  const contact::SearchOptions options = scene_options(state);
  std::vector<Answer> pairs;
  contact::SearchStorage storage;
  // One search untimed first, as an FE code's increments after its first (and as the tracked benchmarks):
  // its answers' buffer and the faces' tables (storage) warm. A single cold call took 499 ns per node on the
  // quad8 sheet where warm calls take 382.
  contact::surface_search(s.master, s.normals, s.ids, s.slaves, options, pairs, &storage);
  for (auto _ : state) {
    contact::surface_search(s.master, s.normals, s.ids, s.slaves, options, pairs, &storage);
    benchmark::DoNotOptimize(pairs.data());
  }
  report(state, pairs);
}

/// The tracked search of scene `s` (contact::SurfaceTracker): its slave nodes move by `dz` in z per
/// increment; one iteration is one increment after the first.
template <class Answer>
void scene_tracked(benchmark::State& state, const Scene& s, double dz) {
  contact::SurfaceTracker tracker(scene_options(state));
  std::vector<geometry::Vec3> slaves = s.slaves;
  std::vector<Answer> pairs;
  tracker.step(s.master, s.normals, s.ids, slaves, pairs);
  for (auto _ : state) {
    for (auto& x : slaves) x.z() += dz;
    tracker.step(s.master, s.normals, s.ids, slaves, pairs);
    benchmark::DoNotOptimize(pairs.data());
  }
  report(state, pairs);
}

/// The surface search with the narrow phase state.range(1) (0: certified, 1: the reference on every face).
void surface(benchmark::State& state) { scene_fresh<contact::NodeSegmentPair>(state, scene()); }

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

/// The tracked search: the slave nodes move by 0.001 (1e-3 of a face) up per increment.
void surface_tracked(benchmark::State& state) {
  scene_tracked<contact::NodeSegmentPair>(state, scene(), 0.001);
}

/// The quadratic sheet's fresh search (`triangles`: tri6, else quad8), narrow state.range(1).
void quadratic_fresh(benchmark::State& state, bool triangles) {
  scene_fresh<contact::Contact>(state, quadratic_scene(triangles));
}

/// The same tracked: the slave nodes move 0.001 down per increment.
void quadratic_tracked(benchmark::State& state, bool triangles) {
  scene_tracked<contact::Contact>(state, quadratic_scene(triangles), -0.001);
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
    } else if (std::strcmp(argv[i], "--history-slaves") == 0 && i + 1 < argc) {
      g_history_slaves = std::strtol(argv[++i], nullptr, 10);
      if (g_history_slaves < 1) {
        std::fprintf(stderr, "bench_surface_search: --history-slaves wants a positive count, got '%s'\n",
                     argv[i]);
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
  // narrow 1: the search before the grid and the certificate (NarrowPhase::kReference), measured beside.
  for (int threads : {1, 2}) {
    for (int surface : {0, 1}) {
      for (int narrow : {0, 1}) {
        for (const auto& [name, fn] :
             {std::pair<const char*, void (*)(benchmark::State&)>{"history/fresh", history_fresh},
              {"history/tracked", history_tracked}}) {
          benchmark::RegisterBenchmark(name, fn)
              ->Args({threads, surface, narrow})
              ->ArgNames({"threads", "surface", "narrow"})
              ->UseRealTime()
              ->Unit(benchmark::kMillisecond);
        }
      }
    }
  }
  // Issue 38: the quadratic sheets, one thread, certified (narrow 0) beside the reference (narrow 1).
  for (const bool triangles : {false, true}) {
    for (const bool tracked : {false, true}) {
      const std::string name =
          std::string("quadratic/") + (triangles ? "tri6" : "quad8") + (tracked ? "_tracked" : "_fresh");
      for (int narrow : {0, 1}) {
        const auto run = [triangles, tracked](benchmark::State& state) {
          if (tracked) {
            quadratic_tracked(state, triangles);
          } else {
            quadratic_fresh(state, triangles);
          }
        };
        benchmark::RegisterBenchmark(name.c_str(), run)
            ->Args({1, narrow})
            ->ArgNames({"threads", "narrow"})
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
      }
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
