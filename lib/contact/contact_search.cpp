#include "contact/contact_search.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>

#include "contact/narrow_phase.hpp"
#include "core/error.hpp"
#include "search/network_model.hpp"

namespace contactnn::contact {

int face_node_count(mesh::FaceType type) {
  switch (type) {
    case mesh::FaceType::kQuad4: return 4;
    case mesh::FaceType::kQuad8: return 8;
    case mesh::FaceType::kTri3: return 3;
    case mesh::FaceType::kTri6: return 6;
  }
  return 0;
}

namespace {

/// The most threads an update uses (the C interface's CONTACTNN_MAX_THREADS, the tools' --threads limit):
/// libgomp fails inside the parallel region when it cannot start the team an OMP_NUM_THREADS of 100000 asks
/// for.
constexpr int kMaxThreads = 1024;

/// Sets OpenMP's thread count for the calling thread's next parallel regions (`threads`, or where <= 0
/// OpenMP's default capped at kMaxThreads), and back when it goes.
class ThreadCount {
 public:
  explicit ThreadCount(int threads) : previous_(omp_get_max_threads()) {
    omp_set_num_threads(threads > 0 ? threads : std::clamp(previous_, 1, kMaxThreads));
  }
  ~ThreadCount() { omp_set_num_threads(previous_); }
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;

 private:
  int previous_;
};

}  // namespace

struct ContactSearch::Impl {
  ContactSearchOptions options;
  std::unique_ptr<const FaceLocator> locator;  ///< options.method's (null: the exact search)
  SearchOptions search;                        ///< its interior the locator
  long node_count = 0;
  bool free = false;
  mesh::SurfaceMesh surface;
  std::vector<int> caller_face;  ///< the caller's index of each face of `surface`
  std::vector<long> slave_ids;   ///< slave node ids, or 0 .. m-1 for free points
  std::vector<int> slave_nodes;  ///< coordinate-array index of each slave node (empty for free points)
  std::vector<Vec3> slave_positions;
  std::vector<Vec3> normals;  ///< Gregory node normals of the state
  SurfaceTracker tracker;
  SearchStorage storage;  ///< the fresh search's tables' memory (tracking off), kept between updates
  std::vector<Contact> contacts;
  TrackingCounts counts;

  Impl(const ContactSearchOptions& o, std::unique_ptr<const FaceLocator> l, const SearchOptions& s)
      : options(o), locator(std::move(l)), search(s), tracker(s) {}

  /// update's arguments' sizes (InvalidArgument naming the one that is not the handle's).
  void check_sizes(std::span<const double> coordinates, std::span<const double> free_points,
                   const ContactResults& out) const {
    const std::size_t n = slave_ids.size();
    CONTACTNN_REQUIRE_AS(InvalidArgument, coordinates.size() == 3 * static_cast<std::size_t>(node_count),
                         "contact search update: " << coordinates.size() << " coordinates, expected 3 x "
                                                   << node_count << " nodes = " << 3 * node_count);
    if (free) {
      CONTACTNN_REQUIRE_AS(InvalidArgument, free_points.size() == 3 * n,
                           "contact search update: " << free_points.size()
                                                     << " free-point coordinates, expected 3 x " << n
                                                     << " points = " << 3 * n);
    } else {
      CONTACTNN_REQUIRE_AS(
          InvalidArgument, free_points.empty(),
          "contact search update: " << free_points.size()
                                    << " free-point coordinates given to a search of slave nodes");
    }
    check_output_sizes("contact search update", out, n);
  }
};

namespace {

SearchOptions search_options(const ContactSearchOptions& o, const FaceLocator* locator) {
  SearchOptions s;
  s.surface = o.quad4;
  s.search = GlobalSearchKind::kSurface;
  if (o.capture_distance > 0.0) s.capture_distance = o.capture_distance;
  s.interior = locator;
  return s;
}

/// The face locator of options.method (null for the exact search): InvalidArgument naming the option for a
/// method the surface search cannot run, a network without a method or a network of the other surface.
std::unique_ptr<const FaceLocator> method_locator(const ContactSearchOptions& o) {
  if (o.method.empty()) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, o.network == nullptr,
                         "contact search: a network is given without a method (options.method is empty: "
                         "the exact search)");
    return nullptr;
  }
  if (o.network != nullptr) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, o.network->surface() == o.quad4,
                         "contact search: the network of method '"
                             << o.method << "' is a " << to_string(o.network->surface())
                             << " network, options.quad4 is " << to_string(o.quad4));
  }
  try {
    return std::make_unique<const FaceLocator>(o.method, o.network.get());
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(std::string("contact search: options.method: ") + e.what());
  }
}

}  // namespace

ContactSearch::ContactSearch(std::span<const mesh::FaceType> face_types, std::span<const long> connectivity,
                             const NodeNumbering& nodes, const SlavePoints& slaves,
                             const ContactSearchOptions& options) {
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       options.quad4 == SurfaceKind::kBilinear || options.quad4 == SurfaceKind::kGregory,
                       "contact search: quad4 surface " << static_cast<int>(options.quad4)
                                                        << ", expected bilinear (0) or Gregory (1)");
  CONTACTNN_REQUIRE_AS(InvalidArgument, std::isfinite(options.capture_distance),
                       "contact search: capture distance " << options.capture_distance << " is not finite");
  CONTACTNN_REQUIRE_AS(InvalidArgument, options.threads <= kMaxThreads,
                       "contact search: " << options.threads << " threads, at most " << kMaxThreads
                                          << " (0 or less: OpenMP's default)");
  CONTACTNN_REQUIRE_AS(InvalidArgument, !face_types.empty(), "contact search: no master faces");
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, face_types.size() <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
      "contact search: " << face_types.size() << " faces, at most " << std::numeric_limits<int>::max());
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, nodes.count > 0 && nodes.count <= std::numeric_limits<int>::max(),
      "contact search: node count " << nodes.count << ", expected 1 to " << std::numeric_limits<int>::max());
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       nodes.ids.empty() || nodes.ids.size() == static_cast<std::size_t>(nodes.count),
                       "contact search: " << nodes.ids.size() << " node ids for " << nodes.count << " nodes");
  const bool free = slaves.nodes.empty();
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, (free && slaves.free_points > 0) || (!free && slaves.free_points == 0),
      "contact search: " << slaves.nodes.size() << " slave nodes and " << slaves.free_points
                         << " free points; expected slave nodes or free points, one of the two");
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       slaves.free_points >= 0 && slaves.free_points <= std::numeric_limits<int>::max(),
                       "contact search: free point count " << slaves.free_points << ", expected 0 to "
                                                           << std::numeric_limits<int>::max());
  std::unique_ptr<const FaceLocator> locator = method_locator(options);
  const SearchOptions search = search_options(options, locator.get());
  impl_ = std::make_unique<Impl>(options, std::move(locator), search);
  Impl& m = *impl_;
  m.node_count = nodes.count;
  m.free = free;

  // Node ids to coordinate-array indices.
  std::unordered_map<long, int> by_id;
  if (!nodes.ids.empty()) {
    by_id.reserve(nodes.ids.size());
    for (std::size_t i = 0; i < nodes.ids.size(); ++i) {
      const auto [at, inserted] = by_id.emplace(nodes.ids[i], static_cast<int>(i));
      CONTACTNN_REQUIRE_AS(InvalidArgument, inserted,
                           "contact search: node id " << nodes.ids[i] << " given twice (nodes " << at->second
                                                      << " and " << i << " of the coordinate array)");
    }
  }
  const auto index_of = [&](long id, const auto& what) {
    if (nodes.ids.empty()) {
      const long i = id - nodes.base;
      CONTACTNN_REQUIRE_AS(InvalidArgument, id >= nodes.base && i < nodes.count,
                           "contact search: " << what() << " names node " << id
                                              << ", which does not exist (ids " << nodes.base << " to "
                                              << nodes.base + nodes.count - 1 << ")");
      return static_cast<int>(i);
    }
    const auto at = by_id.find(id);
    CONTACTNN_REQUIRE_AS(InvalidArgument, at != by_id.end(),
                         "contact search: " << what() << " names node " << id << ", which is not among the "
                                            << nodes.count << " node ids");
    return at->second;
  };

  // The faces: their types, their nodes as coordinate-array indices, the connectivity's length.
  std::size_t total = 0;
  for (std::size_t f = 0; f < face_types.size(); ++f) {
    const int k = face_node_count(face_types[f]);
    CONTACTNN_REQUIRE_AS(InvalidArgument, k > 0,
                         "contact search: face " << f << " has type " << static_cast<int>(face_types[f])
                                                 << ", expected quad4, quad8, tri3 or tri6");
    total += static_cast<std::size_t>(k);
  }
  CONTACTNN_REQUIRE_AS(InvalidArgument, connectivity.size() == total,
                       "contact search: connectivity of " << connectivity.size() << " node ids, the "
                                                          << face_types.size() << " faces' types need "
                                                          << total);
  std::vector<std::array<int, 8>> face_nodes(face_types.size());
  std::vector<char> used(static_cast<std::size_t>(nodes.count), 0);
  std::size_t at = 0;
  for (std::size_t f = 0; f < face_types.size(); ++f) {
    const int k = face_node_count(face_types[f]);
    face_nodes[f].fill(-1);
    for (int j = 0; j < k; ++j) {
      const long id = connectivity[at++];
      const int i =
          index_of(id, [&] { return "face " + std::to_string(f) + " (node " + std::to_string(j + 1) + ")"; });
      for (int q = 0; q < j; ++q) {
        CONTACTNN_REQUIRE_AS(InvalidArgument, face_nodes[f][static_cast<std::size_t>(q)] != i,
                             "contact search: face " << f << " names node " << id << " twice (its nodes "
                                                     << q + 1 << " and " << j + 1 << ")");
      }
      face_nodes[f][static_cast<std::size_t>(j)] = i;
      used[static_cast<std::size_t>(i)] = 1;
    }
  }

  // The surface's nodes: the faces' nodes in coordinate-array order.
  mesh::SurfaceMesh& s = m.surface;
  std::vector<int> local(static_cast<std::size_t>(nodes.count), -1);
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (used[i] == 0) continue;
    local[i] = static_cast<int>(s.mesh_nodes.size());
    s.mesh_nodes.push_back(static_cast<int>(i));
    s.node_ids.push_back(nodes.ids.empty() ? nodes.base + static_cast<long>(i) : nodes.ids[i]);
  }
  s.positions.assign(s.mesh_nodes.size(), Vec3::Zero());
  // Quadrilaterals as segments, triangles as extra faces, each in the caller's order; the caller's index
  // stands in for the element id of SPEC 9's tie rule (face number 1 for all).
  bool quad8 = false, tri6 = false;
  for (std::size_t f = 0; f < face_types.size(); ++f) {
    quad8 = quad8 || face_types[f] == mesh::FaceType::kQuad8;
    tri6 = tri6 || face_types[f] == mesh::FaceType::kTri6;
  }
  std::vector<int> quads, triangles;
  for (std::size_t f = 0; f < face_types.size(); ++f) {
    const mesh::FaceType type = face_types[f];
    const bool quad = type == mesh::FaceType::kQuad4 || type == mesh::FaceType::kQuad8;
    (quad ? quads : triangles).push_back(static_cast<int>(f));
  }
  const auto to_local = [&](const std::array<int, 8>& n, int first, int count) {
    std::array<int, 4> out{-1, -1, -1, -1};
    for (int j = 0; j < count; ++j) {
      const int node = n[static_cast<std::size_t>(first + j)];
      out[static_cast<std::size_t>(j)] = node < 0 ? -1 : local[static_cast<std::size_t>(node)];
    }
    return out;
  };
  // Faces `list` with `corners` corners into the surface's lists (corners, element faces, element ids,
  // mid-side nodes: those of a face of type `quadratic`, none for the others, kept only when
  // `any_quadratic`).
  const auto add_faces = [&](const std::vector<int>& list, int corners, mesh::FaceType quadratic,
                             bool any_quadratic, auto& faces, auto& element_faces, auto& element_ids,
                             auto& midsides) {
    for (const int f : list) {
      const auto& n = face_nodes[static_cast<std::size_t>(f)];
      faces.push_back(to_local(n, 0, corners));
      element_faces.push_back({f, 1});
      element_ids.push_back(f);
      if (any_quadratic)
        midsides.push_back(
            to_local(n, corners, face_types[static_cast<std::size_t>(f)] == quadratic ? corners : 0));
      m.caller_face.push_back(f);
    }
  };
  add_faces(quads, 4, mesh::FaceType::kQuad8, quad8, s.segments, s.segment_faces, s.segment_element_ids,
            s.segment_midsides);
  add_faces(triangles, 3, mesh::FaceType::kTri6, tri6, s.extra_faces, s.extra_face_faces,
            s.extra_face_element_ids, s.extra_face_midsides);
  // The segments at each node (mesh::node_normals reads them), increasing, as build_surface_mesh makes them.
  mesh::set_adjacency(s);

  // The slave points.
  if (free) {
    for (long i = 0; i < slaves.free_points; ++i) m.slave_ids.push_back(i);
  } else {
    for (std::size_t i = 0; i < slaves.nodes.size(); ++i) {
      m.slave_ids.push_back(slaves.nodes[i]);
      m.slave_nodes.push_back(index_of(slaves.nodes[i], [&] { return "slave node " + std::to_string(i); }));
    }
  }
  m.slave_positions.assign(m.slave_ids.size(), Vec3::Zero());
}

ContactSearch::~ContactSearch() = default;

long ContactSearch::face_count() const { return static_cast<long>(impl_->caller_face.size()); }
long ContactSearch::slave_count() const { return static_cast<long>(impl_->slave_ids.size()); }
long ContactSearch::node_count() const { return impl_->node_count; }
bool ContactSearch::free_points() const { return impl_->free; }
const TrackingCounts& ContactSearch::counts() const { return impl_->counts; }
const mesh::SurfaceMesh& ContactSearch::surface() const { return impl_->surface; }

void ContactSearch::update(std::span<const double> coordinates, std::span<const double> free_points,
                           const ContactResults& out) {
  Impl& m = *impl_;
  const std::size_t n = m.slave_ids.size();
  // Every argument checked before the caller's arrays are written or the tracker moves.
  m.check_sizes(coordinates, free_points, out);
  const auto node_at = [&](int i) {
    const auto u = 3 * static_cast<std::size_t>(i);
    return Vec3(coordinates[u], coordinates[u + 1], coordinates[u + 2]);
  };
  const auto id_of = [&](int i) {
    const auto at = std::find(m.surface.mesh_nodes.begin(), m.surface.mesh_nodes.end(), i);
    return at != m.surface.mesh_nodes.end()
               ? m.surface.node_ids[static_cast<std::size_t>(at - m.surface.mesh_nodes.begin())]
               : m.slave_ids[static_cast<std::size_t>(
                     std::find(m.slave_nodes.begin(), m.slave_nodes.end(), i) - m.slave_nodes.begin())];
  };
  const auto require_finite = [&](const Vec3& x, const auto& what) {
    if (x.allFinite()) return;
    std::ostringstream os;
    os << "contact search update: " << what() << " has a non-finite coordinate (" << x.x() << ", " << x.y()
       << ", " << x.z() << ")";
    throw NumericalError(os.str());
  };
  // The passes over the points below run on the handle's threads (a million slave points are three serial
  // passes otherwise: the search's own 2-thread speed-up would be lost in them).
  const ThreadCount team(m.options.threads);
  const auto master_count = static_cast<long>(m.surface.mesh_nodes.size());
  const auto point_count = static_cast<long>(n);
  const auto slave_at = [&](std::size_t i) {
    return m.free ? Vec3(free_points[3 * i], free_points[3 * i + 1], free_points[3 * i + 2])
                  : node_at(m.slave_nodes[i]);
  };
  // The state's positions, copied in, and the first point (in order) with a non-finite coordinate, found in
  // the same parallel pass and named serially. A failure leaves the caller's arrays as they were and the
  // tracker where it was (the next update copies every position again).
  long bad_node = master_count, bad_point = point_count;
#pragma omp parallel for reduction(min : bad_node) schedule(static) if (master_count >= 65536)
  for (long i = 0; i < master_count; ++i) {
    const auto u = static_cast<std::size_t>(i);
    m.surface.positions[u] = node_at(m.surface.mesh_nodes[u]);
    if (!m.surface.positions[u].allFinite()) bad_node = std::min(bad_node, i);
  }
#pragma omp parallel for reduction(min : bad_point) schedule(static) if (point_count >= 65536)
  for (long i = 0; i < point_count; ++i) {
    const auto u = static_cast<std::size_t>(i);
    m.slave_positions[u] = slave_at(u);
    if (!m.slave_positions[u].allFinite()) bad_point = std::min(bad_point, i);
  }
  if (bad_node < master_count) {
    const auto i = static_cast<std::size_t>(bad_node);
    require_finite(m.surface.positions[i], [&] { return "node " + std::to_string(m.surface.node_ids[i]); });
  }
  if (bad_point < point_count) {
    const auto i = static_cast<std::size_t>(bad_point);
    require_finite(m.slave_positions[i], [&] {
      return m.free ? "free point " + std::to_string(i)
                    : "slave node " + std::to_string(id_of(m.slave_nodes[i]));
    });
  }
  try {
    if (m.options.quad4 == SurfaceKind::kGregory) m.normals = mesh::node_normals(m.surface);
    m.counts = TrackingCounts{};
    if (m.options.tracking) {
      m.tracker.step(m.surface, m.normals, m.slave_ids, m.slave_positions, m.contacts, &m.counts);
    } else {
      surface_search(m.surface, m.normals, m.slave_ids, m.slave_positions, m.search, m.contacts, &m.storage);
    }
  } catch (...) {
    m.tracker.reset();
    throw;
  }

  // The caller's arrays.
#pragma omp parallel for schedule(static) if (point_count >= 65536)
  for (long at = 0; at < point_count; ++at) {
    const auto i = static_cast<std::size_t>(at);
    const Contact& p = m.contacts[i];
    const bool found = p.status == PairStatus::kFound;
    out.status[i] = static_cast<int>(found ? Status::kOk : Status::kNoSegment);
    out.face[i] = found ? m.caller_face[static_cast<std::size_t>(p.face)] : -1;
    if (!out.location.empty()) out.location[i] = found ? static_cast<int>(p.location) : -1;
    for (std::size_t k = 0; k < 2 && !out.param.empty(); ++k) out.param[2 * i + k] = found ? p.param[k] : 0.0;
    for (std::size_t k = 0; k < 3; ++k) {
      const auto e = static_cast<Eigen::Index>(k);
      if (!out.point.empty()) out.point[3 * i + k] = found ? p.point[e] : 0.0;
      if (!out.normal.empty()) out.normal[3 * i + k] = found ? p.normal[e] : 0.0;
    }
    if (!out.gap.empty()) out.gap[i] = found ? p.gap : 0.0;
  }
}

}  // namespace contactnn::contact
