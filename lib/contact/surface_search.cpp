#include "contact/surface_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nanoflann.hpp>
#include <unordered_map>
#include <utility>

#include "core/error.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/surface_of.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::contact {

namespace {

/// Distances within this fraction of the face size count as equal (SPEC 9's tie rule applies).
constexpr double kTieTolerance = 1e-12;

/// nanoflann's dataset adaptor over the face centres.
struct Centres {
  const std::vector<Vec3>* points = nullptr;
  [[nodiscard]] std::size_t kdtree_get_point_count() const { return points->size(); }
  [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return (*points)[i][static_cast<Eigen::Index>(dim)];
  }
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox&) const {
    return false;
  }
};
using CentreTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Centres>, Centres, 3, std::uint32_t>;

/// The configuration of face `s` in its own node order (Gregory: with the master's unit node normals).
geometry::Configuration face_configuration(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                                           bool gregory, int s) {
  geometry::Configuration config;
  const auto& quad = master.segments[static_cast<std::size_t>(s)];
  for (std::size_t i = 0; i < 4; ++i) {
    const auto n = static_cast<std::size_t>(quad[i]);
    config.nodes[i] = master.positions[n];
    config.normals[i] = gregory ? normals[n] : Vec3::Zero();
  }
  return config;
}

/// Everything the search needs of the faces, built once: centres, bounding radii, sizes, edge adjacency.
struct FaceIndex {
  std::vector<Vec3> centres;
  std::vector<double> radii;  ///< bounding-sphere radius about the centre
  std::vector<double> sizes;  ///< longest node distance
  /// Faces sharing each edge, by its two surface nodes (smaller first): (face, edge 0..3) pairs.
  std::unordered_map<std::uint64_t, std::vector<std::pair<int, int>>> edges;

  static std::uint64_t edge_key(int a, int b) {
    const auto lo = static_cast<std::uint64_t>(std::min(a, b));
    const auto hi = static_cast<std::uint64_t>(std::max(a, b));
    return (lo << 32U) | hi;
  }
};

FaceIndex index_faces(const mesh::SurfaceMesh& master, std::span<const Vec3> normals, bool gregory) {
  FaceIndex index;
  const std::size_t n = master.segments.size();
  index.centres.resize(n);
  index.radii.resize(n);
  index.sizes.resize(n);
  for (std::size_t s = 0; s < n; ++s) {
    const geometry::Configuration config = face_configuration(master, normals, gregory, static_cast<int>(s));
    const Vec3 centre = 0.25 * ((config.nodes[0] + config.nodes[1]) + (config.nodes[2] + config.nodes[3]));
    double radius = 0.0;
    for (const Vec3& x : config.nodes) radius = std::max(radius, (x - centre).norm());
    if (gregory && !geometry::surface_defect(config, SurfaceKind::kGregory)) {
      // The patch lies in the convex hull of its control points (each interior point is a convex mix of two).
      const geometry::GregoryPatch patch(config.nodes, config.normals);
      for (const Vec3& x : patch.control_points()) radius = std::max(radius, (x - centre).norm());
    }
    index.centres[s] = centre;
    index.radii[s] = radius;
    index.sizes[s] = geometry::max_node_distance(config.nodes);
    const auto& quad = master.segments[s];
    for (int e = 0; e < 4; ++e) {
      index.edges[FaceIndex::edge_key(quad[static_cast<std::size_t>(e)], quad[static_cast<std::size_t>((e + 1) % 4)])]
          .emplace_back(static_cast<int>(s), e);
    }
  }
  return index;
}

/// Parameters of corner k (A, B, C, D) of a quadrilateral face.
std::array<double, 2> corner_param(int k, ParamDomain d) {
  switch (k) {
    case 0: return {d.lo, d.lo};
    case 1: return {d.hi, d.lo};
    case 2: return {d.hi, d.hi};
    default: return {d.lo, d.hi};
  }
}

/// The pseudo-normal direction (not normalised) at the closest point `p` of face `s` (header, step 4).
Vec3 pseudo_normal(const mesh::SurfaceMesh& master, std::span<const Vec3> normals, const SearchOptions& options,
                   const FaceIndex& index, int s, const projection::FaceClosestPoint& p) {
  const bool gregory = options.surface == SurfaceKind::kGregory;
  if (p.location == Location::kFace) return p.normal;
  const ParamDomain d = param_domain(options.surface);
  const auto& quad = master.segments[static_cast<std::size_t>(s)];
  Vec3 sum = Vec3::Zero();
  if (p.location == Location::kEdge) {
    const auto e = static_cast<std::size_t>(p.feature);
    for (const auto& [face, edge] : index.edges.at(FaceIndex::edge_key(quad[e], quad[(e + 1) % 4]))) {
      if (face == s) {
        sum += p.normal;
        continue;
      }
      const geometry::Configuration config = face_configuration(master, normals, gregory, face);
      if (geometry::surface_defect(config, options.surface)) continue;
      sum += geometry::with_surface(config, options.surface, [&](const auto& surface) -> Vec3 {
        const auto q = projection::closest_point_on_edge(surface, edge, p.point);
        const geometry::SurfacePoint sp = surface.evaluate(q.param[0], q.param[1]);
        const Vec3 n = sp.d_s.cross(sp.d_t);
        const double length = n.norm();
        return length > 0.0 ? Vec3(n / length) : Vec3(Vec3::Zero());
      });
    }
    return sum;
  }
  // A vertex: every face at the node, weighted by its corner angle there.
  const int node = quad[static_cast<std::size_t>(p.feature)];
  for (int face : master.segments_of(node)) {
    const auto& other = master.segments[static_cast<std::size_t>(face)];
    const auto k = static_cast<int>(std::find(other.begin(), other.end(), node) - other.begin());
    const geometry::Configuration config = face_configuration(master, normals, gregory, face);
    if (geometry::surface_defect(config, options.surface)) continue;
    sum += geometry::with_surface(config, options.surface, [&](const auto& surface) -> Vec3 {
      const auto c = corner_param(k, d);
      const geometry::SurfacePoint sp = surface.evaluate(c[0], c[1]);
      // Tangents pointing into the face from the corner.
      const Vec3 ts = (c[0] == d.lo ? 1.0 : -1.0) * sp.d_s;
      const Vec3 tt = (c[1] == d.lo ? 1.0 : -1.0) * sp.d_t;
      const Vec3 n = sp.d_s.cross(sp.d_t);
      const double length = n.norm();
      if (!(length > 0.0)) return Vec3::Zero();
      const double angle = std::atan2(ts.cross(tt).norm(), ts.dot(tt));
      return angle * (n / length);
    });
  }
  return sum;
}

/// (xi, eta) or (u, v) of a face's point after the face's corners are relabelled to start at corner k
/// (A' = old corner k, then on counter-clockwise): k cyclic steps of (s, t) -> (t, -s) about the centre.
std::array<double, 2> rotate_param(std::array<double, 2> p, int k, SurfaceKind kind) {
  const bool bilinear = kind == SurfaceKind::kBilinear;
  for (int i = 0; i < k; ++i) p = bilinear ? std::array<double, 2>{p[1], -p[0]} : std::array<double, 2>{p[1], 1.0 - p[0]};
  return p;
}

/// Steps 2-4 of the header for one slave node, given its candidate faces (unordered).
NodeSegmentPair search_one(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                           const SearchOptions& options, const FaceIndex& index, double capture, long slave_id,
                           const Vec3& slave, std::vector<std::pair<double, int>>& candidates) {
  const bool gregory = options.surface == SurfaceKind::kGregory;
  NodeSegmentPair best;
  best.slave_id = slave_id;
  // Nearest sphere first; equal bounds in face order, so the scan is the same whatever the tree returned.
  std::sort(candidates.begin(), candidates.end());
  double best_distance = std::numeric_limits<double>::infinity();
  projection::FaceClosestPoint best_point;
  for (const auto& [bound, s] : candidates) {
    if (bound > capture) break;
    // A face whose sphere is beyond the best point (and its tie band) cannot beat it.
    if (bound > best_distance + kTieTolerance * index.sizes[static_cast<std::size_t>(s)]) break;
    const geometry::Configuration config = face_configuration(master, normals, gregory, s);
    if (geometry::surface_defect(config, options.surface)) continue;
    const projection::FaceClosestPoint p = geometry::with_surface(config, options.surface, [&](const auto& surface) {
      return projection::closest_point_on_face(surface, slave, options.projection);
    });
    if (p.status != Status::kOk) continue;
    ++best.candidates;
    const double tie = kTieTolerance * index.sizes[static_cast<std::size_t>(s)];
    bool better = best.segment < 0 || p.distance < best_distance - tie;
    if (!better && p.distance <= best_distance + tie) {
      const auto key = [&](int f) {
        return std::pair(master.segment_element_ids[static_cast<std::size_t>(f)],
                         master.segment_faces[static_cast<std::size_t>(f)].face);
      };
      better = key(s) < key(best.segment);
    }
    if (better) {
      best.segment = s;
      best_distance = p.distance;
      best_point = p;
    }
  }
  if (best.segment < 0 || best_distance > capture) {
    best.segment = -1;
    best.candidates = 0;
    return best;
  }

  // The pair in SPEC 7's node order: A the corner nearest S (ties: the first in the face's order).
  const auto& quad = master.segments[static_cast<std::size_t>(best.segment)];
  int k = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const double d2 = (master.positions[static_cast<std::size_t>(quad[static_cast<std::size_t>(i)])] - slave).squaredNorm();
    if (d2 < nearest) {
      nearest = d2;
      k = i;
    }
  }
  best.status = PairStatus::kFound;
  for (int i = 0; i < 4; ++i) best.nodes[static_cast<std::size_t>(i)] = quad[static_cast<std::size_t>((k + i) % 4)];
  best.nearest_node = best.nodes[0];
  const geometry::Configuration own = face_configuration(master, normals, gregory, best.segment);
  for (std::size_t i = 0; i < 4; ++i) {
    best.config.nodes[i] = own.nodes[(static_cast<std::size_t>(k) + i) % 4];
    best.config.normals[i] = own.normals[(static_cast<std::size_t>(k) + i) % 4];
  }
  best.config.slave = slave;
  best.location = best_point.location;
  best.point = best_point.point;

  dataset::Label& label = best.label;
  label.status = Status::kOk;
  label.iterations = best_point.iterations;
  label.param = rotate_param(best_point.param, k, options.surface);
  const Vec3 n = pseudo_normal(master, normals, options, index, best.segment, best_point);
  const double side = (slave - best_point.point).dot(n);
  label.gap = side < 0.0 ? -best_point.distance : best_point.distance;
  return best;
}

}  // namespace

double capture_distance(const mesh::SurfaceMesh& master, const SearchOptions& options) {
  if (options.capture_distance > 0.0) return options.capture_distance;
  double largest = 0.0;
  for (const auto& quad : master.segments) {
    std::array<Vec3, 4> nodes;
    for (std::size_t i = 0; i < 4; ++i) nodes[i] = master.positions[static_cast<std::size_t>(quad[i])];
    largest = std::max(largest, geometry::max_node_distance(nodes));
  }
  return options.capture_relative * largest;
}

std::vector<NodeSegmentPair> surface_search(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                                            std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                                            const SearchOptions& options) {
  CONTACTNN_REQUIRE(slave_ids.size() == slave_positions.size(),
                    slave_ids.size() << " slave ids for " << slave_positions.size() << " positions");
  const bool gregory = options.surface == SurfaceKind::kGregory;
  CONTACTNN_REQUIRE(!gregory || master_normals.size() == master.positions.size(),
                    "Gregory search needs one node normal per master node: " << master_normals.size() << " for "
                                                                              << master.positions.size());
  CONTACTNN_REQUIRE(master.segment_element_ids.size() == master.segments.size(),
                    master.segment_element_ids.size() << " element ids for " << master.segments.size() << " faces");
  const FaceIndex index = index_faces(master, master_normals, gregory);
  const double capture = capture_distance(master, options);
  const double largest_radius = index.radii.empty() ? 0.0 : *std::max_element(index.radii.begin(), index.radii.end());
  const Centres cloud{&index.centres};
  const CentreTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));

  const auto n = static_cast<long>(slave_ids.size());
  std::vector<NodeSegmentPair> pairs(static_cast<std::size_t>(n));
#pragma omp parallel
  {
    std::vector<std::pair<double, int>> candidates;
    std::vector<std::pair<std::uint32_t, double>> found;
#pragma omp for schedule(dynamic, 16)
    for (long i = 0; i < n; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const Vec3& slave = slave_positions[u];
      candidates.clear();
      if (slave.allFinite() && !index.centres.empty()) {
        const auto bound = [&](std::size_t s) { return (slave - index.centres[s]).norm() - index.radii[s]; };
        if (options.brute_force_faces) {
          for (std::size_t s = 0; s < index.centres.size(); ++s) candidates.emplace_back(bound(s), static_cast<int>(s));
        } else {
          // Every centre within capture + the largest radius, then each face by its own sphere.
          const double reach = capture + largest_radius;
          const double q[3] = {slave.x(), slave.y(), slave.z()};
          found.clear();
          tree.radiusSearch(q, reach * reach * (1.0 + 1e-12), found, nanoflann::SearchParams(32, 0.0F, false));
          for (const auto& item : found) candidates.emplace_back(bound(item.first), static_cast<int>(item.first));
        }
      }
      pairs[u] = search_one(master, master_normals, options, index, capture, slave_ids[u], slave, candidates);
    }
  }
  return pairs;
}

}  // namespace contactnn::contact
