// Description: the tri3 surface search against CGAL's AABB tree (issue 38) on the same surface and slave
// points in the same run, one thread, best of three. The surface is the large history's wavy block
// (scripts/make-large-history: FACES x FACES unit cells, top z = 0.2 sin(x / 5) cos(y / 7)) with every top
// quadrilateral cut into two triangles (the tops of two C3D6 wedges: (i,j) (i+1,j) (i+1,j+1) and (i,j)
// (i+1,j+1) (i,j+1), counter-clockwise seen from above); the slave nodes are its SLAVES x SLAVES layer
// (spacing 0.3, centred, 0.05 above the surface) under its prescribed motion (pressed 0.02 down per increment
// for the first third of the increments, slid 0.05 along x per increment, turned 0.05 degree per increment
// about the block's vertical centre line), in exact doubles (the .frd's five significant digits are not
// applied). The master stays fixed, as the block does.
//
// Timed, each as the best of --repeats runs:
//  - cgal_build: the triangles from the node coordinates, the AABB tree, its build and the k-d tree of its
//    accelerated distance queries (forced by one query);
//  - cgal_query: closest_point for every slave node at every increment;
//  - fresh: contact::ContactSearch without tracking, created from the faces and updated once, at every
//    increment (the handle's creation and the searcher's build included: what a user pays for one search);
//  - tracked: one ContactSearch with tracking over the increments; the increments after the first;
//  - fresh_reused (beside them): one ContactSearch without tracking updated at every increment, the
//  increments
//    after the first (a fresh search whose handle and buffers are warm).
// Measured for the floor (scripts/bench-cgal): the faces projected per slave node (surface_search's and
// SurfaceTracker's `candidates` on the handle's surface), one k-d tree descent per slave node
// (SurfaceSearcher:: faces_within with reach 0), the searcher's build, and the memory bandwidth of one large
// copy. Checked: every slave node's distance and closest point against CGAL's, fresh and tracked, at every
// increment (the largest differences, absolute and over the largest face size; `same_closest_points yes`
// where every one is within 1e-9 of the face size).
//
// --part fresh or tracked runs that search alone (no CGAL, no checks, no floor): what scripts/bench-cgal
// --profile records under perf (the tracked part's first increment is its fresh search).
//
// Output: one `key value` line per number (scripts/bench-cgal reads them). Exit status 0; 1 for a bug
// (a slave node without a point, an exception); 2 a usage error.
//
// Sample run: build/bench/bench_cgal --faces 200 --slaves 600 --increments 9 --repeats 3
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <omp.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact/contact_search.hpp"
#include "contact/surface_search.hpp"
#include "contact/tracking.hpp"

namespace {

using namespace contactnn;
using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

struct Args {
  int faces = 200;
  int slaves = 600;
  int increments = 9;
  int repeats = 3;
  std::string part = "all";  ///< all, or fresh / tracked alone (a profile's run: no CGAL, no checks)
};

/// Wall-clock and process CPU time (seconds): on a shared machine the CPU time is what the search itself
/// spent, the wall clock also what other processes took from it.
struct Stamp {
  double wall = 0.0;
  double cpu = 0.0;
};

Stamp now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return {std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(),
          static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec)};
}

/// Time summed over some spans (add), and the best of several such sums (best), wall and CPU separately.
struct Times {
  double wall = 0.0;
  double cpu = 0.0;
  void add(const Stamp& start) {
    const Stamp t = now();
    wall += t.wall - start.wall;
    cpu += t.cpu - start.cpu;
  }
};

struct Best {
  double wall = std::numeric_limits<double>::infinity();
  double cpu = std::numeric_limits<double>::infinity();
  void take(const Times& t) {
    wall = std::min(wall, t.wall);
    cpu = std::min(cpu, t.cpu);
  }
  /// Prints `key_ns_per_X` (wall) and `key_cpu_ns_per_X` for `count` units.
  void print(const char* key, const char* unit, double count) const {
    std::printf("%s_ns_per_%s %.2f\n%s_cpu_ns_per_%s %.2f\n", key, unit, wall / count * 1e9, key, unit,
                cpu / count * 1e9);
  }
};

double top(double x, double y) { return 0.2 * std::sin(x / 5.0) * std::cos(y / 7.0); }

/// The scene: the master's top nodes first (node i + side j), the slave nodes after them; coordinates of
/// every increment (the master's the same in each).
struct Scene {
  long master_nodes = 0;
  long slave_count = 0;
  std::vector<mesh::FaceType> types;
  std::vector<long> connectivity;
  std::vector<long> slave_ids;
  std::vector<std::vector<double>> coordinates;  ///< per increment, 3 per node
  double face_size = 0.0;                        ///< the longest triangle edge
};

Scene make_scene(const Args& a) {
  Scene s;
  const int side = a.faces + 1;
  s.master_nodes = static_cast<long>(side) * side;
  s.slave_count = static_cast<long>(a.slaves) * a.slaves;
  for (int j = 0; j < a.faces; ++j)
    for (int i = 0; i < a.faces; ++i) {
      const long n00 = i + static_cast<long>(side) * j, n10 = n00 + 1, n11 = n10 + side, n01 = n00 + side;
      for (long n : {n00, n10, n11, n00, n11, n01}) s.connectivity.push_back(n);
      s.types.insert(s.types.end(), 2, mesh::FaceType::kTri3);
    }
  std::vector<double> base(static_cast<std::size_t>(3 * (s.master_nodes + s.slave_count)));
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const std::size_t n = static_cast<std::size_t>(i + static_cast<long>(side) * j);
      base[3 * n] = i;
      base[3 * n + 1] = j;
      base[3 * n + 2] = top(i, j);
    }
  const double spacing = 0.3, extent = spacing * (a.slaves - 1), offset = 0.5 * (a.faces - extent);
  for (long k = 0; k < s.slave_count; ++k) {
    const double x = offset + spacing * static_cast<double>(k % a.slaves);
    const double y = offset + spacing * static_cast<double>(k / a.slaves);
    const std::size_t n = static_cast<std::size_t>(s.master_nodes + k);
    base[3 * n] = x;
    base[3 * n + 1] = y;
    base[3 * n + 2] = top(x, y) + 0.05;
    s.slave_ids.push_back(s.master_nodes + k);
  }
  const int press = std::max(1, a.increments / 3);
  const double centre = 0.5 * a.faces;
  double dz = 0.0, dx = 0.0, angle = 0.0;
  for (int inc = 1; inc <= a.increments; ++inc) {
    if (inc <= press)
      dz -= 0.02;
    else if (inc <= 2 * press)
      dx += 0.05;
    else
      angle += 0.05 * std::numbers::pi / 180.0;
    const double c = std::cos(angle), sn = std::sin(angle);
    std::vector<double> x = base;
    for (long k = 0; k < s.slave_count; ++k) {
      const std::size_t n = static_cast<std::size_t>(s.master_nodes + k);
      const double rx = base[3 * n] - centre, ry = base[3 * n + 1] - centre;
      x[3 * n] = centre + c * rx - sn * ry + dx;
      x[3 * n + 1] = centre + sn * rx + c * ry;
      x[3 * n + 2] = base[3 * n + 2] + dz;
    }
    s.coordinates.push_back(std::move(x));
  }
  double longest = 0.0;
  const auto& x0 = s.coordinates[0];
  for (std::size_t f = 0; f < s.types.size(); ++f)
    for (int e = 0; e < 3; ++e) {
      const auto p = static_cast<std::size_t>(s.connectivity[3 * f + e]);
      const auto q = static_cast<std::size_t>(s.connectivity[3 * f + (e + 1) % 3]);
      longest = std::max(longest, std::hypot(x0[3 * p] - x0[3 * q], x0[3 * p + 1] - x0[3 * q + 1],
                                             x0[3 * p + 2] - x0[3 * q + 2]));
    }
  s.face_size = longest;
  return s;
}

/// The closest points of one increment: 3 per slave node, and the distance.
struct Answers {
  std::vector<double> point;
  std::vector<double> distance;
};

/// The largest differences of two searches' answers. A point that differs by more than 1e-9 of the face size
/// is a tie where the two distances agree to SPEC 9's tie band (1e-12 of the face size): two faces' points
/// equally near (a slave node a hair from a concave crease), of which the search reports the lower face's
/// and CGAL either one; otherwise it is a different answer.
struct Difference {
  double point = 0.0;     ///< over every slave node
  double distance = 0.0;  ///< over every slave node
  double point_not_tie = 0.0;
  long ties = 0;
  void add(const Answers& a, const Answers& b, double face_size) {
    for (std::size_t i = 0; i < a.distance.size(); ++i) {
      const double d = std::abs(a.distance[i] - b.distance[i]);
      const double q = std::hypot(a.point[3 * i] - b.point[3 * i], a.point[3 * i + 1] - b.point[3 * i + 1],
                                  a.point[3 * i + 2] - b.point[3 * i + 2]);
      distance = std::max(distance, d);
      point = std::max(point, q);
      if (q > 1e-9 * face_size) {
        if (d <= 1e-12 * face_size)
          ++ties;
        else
          point_not_tie = std::max(point_not_tie, q);
      }
    }
  }
};

/// CGAL: best build time, best query time over all increments, and its answers per increment.
struct CgalRun {
  Best build;
  Best query;
  std::vector<Answers> answers;
};

CgalRun run_cgal(const Scene& s, int repeats) {
  CgalRun run;
  run.answers.resize(s.coordinates.size());
  for (int r = 0; r < repeats; ++r) {
    const auto& x = s.coordinates[0];
    const auto point = [&](const std::vector<double>& c, long n) {
      const auto u = static_cast<std::size_t>(3 * n);
      return K::Point_3(c[u], c[u + 1], c[u + 2]);
    };
    Times build;
    Stamp t0 = now();
    Triangles triangles;
    triangles.reserve(s.types.size());
    for (std::size_t f = 0; f < s.types.size(); ++f)
      triangles.emplace_back(point(x, s.connectivity[3 * f]), point(x, s.connectivity[3 * f + 1]),
                             point(x, s.connectivity[3 * f + 2]));
    Tree tree(triangles.cbegin(), triangles.cend());
    tree.build();
    tree.accelerate_distance_queries();
    volatile double sink = tree.closest_point(point(x, s.slave_ids[0])).x();
    (void)sink;
    build.add(t0);
    run.build.take(build);
    Times query;
    for (std::size_t inc = 0; inc < s.coordinates.size(); ++inc) {
      const auto& c = s.coordinates[inc];
      Answers& a = run.answers[inc];
      a.point.resize(3 * s.slave_ids.size());
      a.distance.resize(s.slave_ids.size());
      t0 = now();
      for (std::size_t i = 0; i < s.slave_ids.size(); ++i) {
        const K::Point_3 p = point(c, s.slave_ids[i]);
        const K::Point_3 q = tree.closest_point(p);
        a.point[3 * i] = q.x();
        a.point[3 * i + 1] = q.y();
        a.point[3 * i + 2] = q.z();
        a.distance[i] = std::sqrt(CGAL::squared_distance(p, q));
      }
      query.add(t0);
    }
    run.query.take(query);
  }
  return run;
}

/// The handle's output arrays for the slave nodes.
struct Outputs : contact::ContactAnswers {
  using ContactAnswers::ContactAnswers;
  Answers answers() const {
    for (int st : status)
      if (st != 0) throw std::runtime_error("a slave node without a point");
    Answers a{point, gap};
    for (double& d : a.distance) d = std::abs(d);
    return a;
  }
};

contact::ContactSearch make_handle(const Scene& s, bool tracking) {
  contact::ContactSearchOptions options;
  options.threads = 1;
  options.tracking = tracking;
  const contact::NodeNumbering nodes{s.master_nodes + s.slave_count, 0, {}};
  return contact::ContactSearch(s.types, s.connectivity, nodes, contact::SlavePoints{s.slave_ids, 0},
                                options);
}

struct ContactRun {
  Best fresh;    ///< all increments, seconds
  Best create;   ///< the fresh runs' handle creations alone (part of `fresh`)
  Best reused;   ///< one handle without tracking updated at every increment: the increments after the first
  Best tracked;  ///< the increments after the first
  Difference fresh_difference, tracked_difference;
  contact::TrackingCounts counts;  ///< of the tracked run's last increment
};

/// `handle` updated at increment 0, then timed at every later increment, after(increment) following each
/// update.
template <class After>
Times later_increments(contact::ContactSearch& handle, const Scene& s, Outputs& out, const After& after) {
  handle.update(s.coordinates[0], {}, out.results());
  Times times;
  for (std::size_t inc = 1; inc < s.coordinates.size(); ++inc) {
    const Stamp t0 = now();
    handle.update(s.coordinates[inc], {}, out.results());
    times.add(t0);
    after(inc);
  }
  return times;
}

/// The fresh and the tracked runs (either alone for a profile); checked against `cgal` where given.
ContactRun run_contactnn(const Scene& s, const CgalRun* cgal, int repeats, const std::string& part) {
  ContactRun run;
  Outputs out(s.slave_ids.size());
  for (int r = 0; r < repeats; ++r) {
    Times fresh, create;
    for (std::size_t inc = 0; inc < s.coordinates.size() && part != "tracked"; ++inc) {
      const Stamp t0 = now();
      contact::ContactSearch handle = make_handle(s, false);
      create.add(t0);
      handle.update(s.coordinates[inc], {}, out.results());
      fresh.add(t0);
      if (r == 0 && cgal != nullptr) run.fresh_difference.add(out.answers(), cgal->answers[inc], s.face_size);
    }
    run.fresh.take(fresh);
    run.create.take(create);
    if (part == "fresh") continue;
    if (part == "all") {
      contact::ContactSearch again = make_handle(s, false);
      run.reused.take(later_increments(again, s, out, [](std::size_t) {}));
    }
    contact::ContactSearch handle = make_handle(s, true);
    run.tracked.take(later_increments(handle, s, out, [&](std::size_t inc) {
      if (r == 0 && cgal != nullptr)
        run.tracked_difference.add(out.answers(), cgal->answers[inc], s.face_size);
    }));
    run.counts = handle.counts();
  }
  return run;
}

std::vector<geometry::Vec3> slave_positions(const Scene& s, std::size_t inc) {
  std::vector<geometry::Vec3> p;
  const auto& c = s.coordinates[inc];
  for (long id : s.slave_ids) {
    const auto u = static_cast<std::size_t>(3 * id);
    p.emplace_back(c[u], c[u + 1], c[u + 2]);
  }
  return p;
}

/// The candidate search's floor: a uniform grid of cubic cells (the largest face size) holding each face in
/// every cell its bounding box meets, in one array (the bucket sort of OpenRadioss's i7buce); a query reads
/// the list of the node's cell (and sums its faces' indices, so that the list is read). What a bucket search
/// costs per node at least; the search proper would also visit the neighbouring cells within its reach.
class FaceGrid {
  using Vec3 = geometry::Vec3;

 public:
  FaceGrid(const mesh::SurfaceMesh& surface, double cell) : cell_(cell) {
    const int faces = surface.face_count();
    const Vec3 none = Vec3::Constant(std::numeric_limits<double>::infinity());
    lo_ = none;
    Vec3 hi = -none;
    std::vector<std::array<Vec3, 2>> boxes(static_cast<std::size_t>(faces));
    for (int f = 0; f < faces; ++f) {
      auto& [a, b] = boxes[static_cast<std::size_t>(f)];
      a = none;
      b = -none;
      for (int node : surface.face_corners(f)) {
        if (node < 0) continue;
        a = a.cwiseMin(surface.positions[static_cast<std::size_t>(node)]);
        b = b.cwiseMax(surface.positions[static_cast<std::size_t>(node)]);
      }
      lo_ = lo_.cwiseMin(a);
      hi = hi.cwiseMax(b);
    }
    for (int k = 0; k < 3; ++k) dims_[k] = static_cast<long>((hi[k] - lo_[k]) / cell_) + 1;
    start_.assign(static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2] + 1), 0);
    for (int pass = 0; pass < 2; ++pass) {
      for (int f = 0; f < faces; ++f) {
        const auto& [a, b] = boxes[static_cast<std::size_t>(f)];
        const auto c0 = cell_of(a), c1 = cell_of(b);
        for (long z = c0[2]; z <= c1[2]; ++z)
          for (long y = c0[1]; y <= c1[1]; ++y)
            for (long x = c0[0]; x <= c1[0]; ++x) {
              const auto c = static_cast<std::size_t>(x + dims_[0] * (y + dims_[1] * z));
              if (pass == 0)
                ++start_[c + 1];
              else
                faces_[static_cast<std::size_t>(fill_[c]++)] = f;
            }
      }
      if (pass == 0) {
        for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
        faces_.resize(static_cast<std::size_t>(start_.back()));
        fill_.assign(start_.begin(), start_.end() - 1);
      }
    }
  }
  /// The faces listed in x's cell (0 outside the grid), their indices summed into a sink.
  long touch(const Vec3& x) const {
    const auto c = cell_of(x);
    for (int k = 0; k < 3; ++k)
      if (c[k] < 0 || c[k] >= dims_[k]) return 0;
    const auto u = static_cast<std::size_t>(c[0] + dims_[0] * (c[1] + dims_[1] * c[2]));
    long sum = 0;
    for (long i = start_[u]; i < start_[u + 1]; ++i) sum += faces_[static_cast<std::size_t>(i)];
    sink_ += sum;
    return start_[u + 1] - start_[u];
  }

 private:
  std::array<long, 3> cell_of(const Vec3& x) const {
    std::array<long, 3> c{};
    for (int k = 0; k < 3; ++k) c[k] = static_cast<long>(std::floor((x[k] - lo_[k]) / cell_));
    return c;
  }
  double cell_;
  Vec3 lo_;
  std::array<long, 3> dims_{};
  std::vector<long> start_, fill_;
  std::vector<int> faces_;
  mutable long sink_ = 0;
};

/// The floor's inputs: faces projected per slave node (fresh at the first increment; tracked over the later
/// ones), one k-d tree descent per node, the searcher's build, the memory bandwidth.
void measure_floor(const Scene& s, int repeats) {
  contact::ContactSearch handle = make_handle(s, false);
  Outputs out(s.slave_ids.size());
  handle.update(s.coordinates[0], {}, out.results());
  const mesh::SurfaceMesh& surface = handle.surface();  // the master is fixed: the same at every increment
  const contact::SearchOptions options;
  const double n = static_cast<double>(s.slave_ids.size());
  std::vector<contact::NodeSegmentPair> pairs;
  const auto first = slave_positions(s, 0);
  contact::surface_search(surface, {}, s.slave_ids, first, options, pairs);
  double projected = 0.0;
  for (const auto& p : pairs) projected += p.candidates;
  std::printf("fresh_faces_per_node %.4f\n", projected / n);
  contact::SurfaceTracker tracker(options);
  tracker.step(surface, {}, s.slave_ids, first, pairs);
  projected = 0.0;
  for (std::size_t inc = 1; inc < s.coordinates.size(); ++inc) {
    tracker.step(surface, {}, s.slave_ids, slave_positions(s, inc), pairs);
    for (const auto& p : pairs) projected += p.candidates;
  }
  std::printf("tracked_faces_per_node %.4f\n",
              projected / (n * static_cast<double>(s.coordinates.size() - 1)));

  Best build, descent, bucket, copy;
  std::vector<std::pair<double, int>> found;
  std::vector<std::pair<std::uint32_t, double>> scratch;
  long hits = 0, bucket_hits = 0;
  const FaceGrid grid(surface, s.face_size);
  for (int r = 0; r < repeats; ++r) {
    Times t;
    Stamp t0 = now();
    const contact::SurfaceSearcher searcher(surface, {}, options);
    t.add(t0);
    build.take(t);
    t = {};
    t0 = now();
    hits = 0;
    for (const auto& x : first) {
      found.clear();
      searcher.faces_within(x, 0.0, found, scratch);
      hits += static_cast<long>(found.size());
    }
    t.add(t0);
    descent.take(t);
    t = {};
    t0 = now();
    bucket_hits = 0;
    for (const auto& x : first) bucket_hits += grid.touch(x);
    t.add(t0);
    bucket.take(t);
  }
  build.print("searcher_build", "node", n);
  descent.print("descent", "node", n);
  std::printf("descent_faces_per_node %.4f\n", static_cast<double>(hits) / n);
  bucket.print("bucket", "node", n);
  std::printf("bucket_faces_per_node %.4f\n", static_cast<double>(bucket_hits) / n);
  // Memory bandwidth: one copy of 256 MiB (read and written: twice its bytes over the time).
  std::vector<double> from(std::size_t{1} << 25, 1.0), to(from.size(), 0.0);
  for (int r = 0; r < repeats; ++r) {
    Times t;
    const Stamp t0 = now();
    std::memcpy(to.data(), from.data(), from.size() * sizeof(double));
    t.add(t0);
    copy.take(t);
  }
  const double bytes = 2.0 * static_cast<double>(from.size() * sizeof(double));
  std::printf("bandwidth_gb_per_s %.2f\nbandwidth_cpu_gb_per_s %.2f\n", bytes / copy.wall * 1e-9,
              bytes / copy.cpu * 1e-9);
}

int usage(const char* message) {
  std::fprintf(stderr,
               "bench_cgal: %s\nusage: bench_cgal [--faces 200] [--slaves 600] [--increments 9] [--repeats "
               "3] [--part all|fresh|tracked]\n",
               message);
  return 2;
}

bool parse(int argc, char** argv, Args& a) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--part") == 0 && i + 1 < argc) {
      a.part = argv[++i];
      if (a.part != "all" && a.part != "fresh" && a.part != "tracked") return false;
      continue;
    }
    int* target = nullptr;
    int lo = 1, hi = 5000;
    if (std::strcmp(argv[i], "--faces") == 0) {
      target = &a.faces;
      lo = 2;
    } else if (std::strcmp(argv[i], "--slaves") == 0) {
      target = &a.slaves;
      lo = 2;
    } else if (std::strcmp(argv[i], "--increments") == 0) {
      target = &a.increments;
      lo = 2;
      hi = 100;
    } else if (std::strcmp(argv[i], "--repeats") == 0) {
      target = &a.repeats;
      hi = 100;
    }
    if (target == nullptr || i + 1 >= argc) return false;
    char* end = nullptr;
    const long v = std::strtol(argv[++i], &end, 10);
    if (*end != '\0' || v < lo || v > hi) return false;
    *target = static_cast<int>(v);
  }
  return 0.3 * (a.slaves - 1) <= a.faces - 2;
}

/// The whole comparison (--part all): CGAL, contactnn fresh and tracked, the checks, the floor's inputs.
void compare(const Scene& s, const Args& a) {
  const double n = static_cast<double>(s.slave_count), tris = static_cast<double>(s.types.size());
  const double incs = static_cast<double>(a.increments);
  const CgalRun cgal = run_cgal(s, a.repeats);
  cgal.build.print("cgal_build", "triangle", tris);
  cgal.build.print("cgal_build", "node", n);
  cgal.query.print("cgal_query", "node", n * incs);
  const ContactRun run = run_contactnn(s, &cgal, a.repeats, a.part);
  run.fresh.print("fresh", "node", n * incs);
  run.create.print("fresh_create", "node", n * incs);
  run.reused.print("fresh_reused", "node", n * (incs - 1));
  run.tracked.print("tracked", "node", n * (incs - 1));
  std::printf("tracked_refreshed_last %ld\ntracked_list_faces_last %.4f\n", run.counts.fresh,
              static_cast<double>(run.counts.list_faces) / n);
  std::printf("fresh_max_point_difference %.3e\nfresh_max_distance_difference %.3e\n",
              run.fresh_difference.point, run.fresh_difference.distance);
  std::printf("tracked_max_point_difference %.3e\ntracked_max_distance_difference %.3e\n",
              run.tracked_difference.point, run.tracked_difference.distance);
  std::printf("fresh_point_ties %ld\ntracked_point_ties %ld\n", run.fresh_difference.ties,
              run.tracked_difference.ties);
  const double largest = std::max({run.fresh_difference.point_not_tie, run.fresh_difference.distance,
                                   run.tracked_difference.point_not_tie, run.tracked_difference.distance});
  std::printf("max_difference_over_face_size %.3e\nsame_closest_points %s\n", largest / s.face_size,
              largest <= 1e-9 * s.face_size ? "yes" : "no");
  measure_floor(s, a.repeats);
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  if (!parse(argc, argv, a))
    return usage(
        "bad arguments (integers; 0.3 (slaves - 1) must be at most faces - 2; increments >= 2; --part "
        "all, fresh or tracked)");
  omp_set_num_threads(1);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each number as soon as it is measured
  try {
    const Scene s = make_scene(a);
    std::printf("triangles %zu\nslave_nodes %ld\nincrements %d\nrepeats %d\nface_size %.6f\n", s.types.size(),
                s.slave_count, a.increments, a.repeats, s.face_size);
    if (a.part == "all") {
      compare(s, a);
    } else {
      const ContactRun run = run_contactnn(s, nullptr, a.repeats, a.part);
      const double n = static_cast<double>(s.slave_count), incs = static_cast<double>(a.increments);
      if (a.part == "fresh")
        run.fresh.print("fresh", "node", n * incs);
      else
        run.tracked.print("tracked", "node", n * (incs - 1));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_cgal: %s\n", e.what());
    return 1;
  }
  return 0;
}
