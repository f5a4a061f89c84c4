#include "contact/global_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/nearest_node.hpp"
#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "geometry/segment_checks.hpp"
#include "geometry/surface_of.hpp"

namespace contactnn::contact {

namespace {

/// |S - P| with P the surface point at the label's parameters clamped to the domain: the distance from S
/// to the segment along the projection. Infinite when the label has no parameters.
double distance_to_segment(const geometry::Configuration& config, const dataset::Label& label,
                           SurfaceKind kind) {
  if (label.status != Status::kOk && label.status != Status::kOutside)
    return std::numeric_limits<double>::infinity();
  if (geometry::surface_defect(config, kind)) return std::numeric_limits<double>::infinity();
  const ParamDomain d = param_domain(kind);
  const double s = std::clamp(label.param[0], d.lo, d.hi);
  const double t = std::clamp(label.param[1], d.lo, d.hi);
  return geometry::with_surface(
      config, kind, [&](const auto& surface) { return (config.slave - surface.position(s, t)).norm(); });
}

}  // namespace

NodeSegmentPair pair_at_nearest_node(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                                     long slave_id, const Vec3& slave, int nearest_node,
                                     const SearchOptions& options) {
  const bool gregory = options.surface == SurfaceKind::kGregory;
  CONTACTNN_REQUIRE(!gregory || master_normals.size() == master.positions.size(),
                    "Gregory search needs one node normal per master node: "
                        << master_normals.size() << " for " << master.positions.size());
  NodeSegmentPair best;
  best.slave_id = slave_id;
  best.nearest_node = nearest_node;
  if (nearest_node < 0) return best;
  const auto at = [&](int n) -> const Vec3& { return master.positions[static_cast<std::size_t>(n)]; };

  double best_distance = std::numeric_limits<double>::infinity();
  bool best_inside = false;
  for (int s : master.segments_of(nearest_node)) {
    const auto& quad = master.segments[static_cast<std::size_t>(s)];
    const auto k = static_cast<int>(std::find(quad.begin(), quad.end(), nearest_node) - quad.begin());
    std::array<int, 4> nodes{};
    for (int i = 0; i < 4; ++i)
      nodes[static_cast<std::size_t>(i)] = quad[static_cast<std::size_t>((k + i) % 4)];
    if (!geometry::passes_segment_test(at(nodes[0]), at(nodes[1]), at(nodes[3]), slave,
                                       options.segment_test_tolerance)) {
      continue;
    }
    ++best.candidates;
    NodeSegmentPair candidate;
    candidate.nodes = nodes;
    candidate.segment = s;
    for (int i = 0; i < 4; ++i) {
      const auto n = static_cast<std::size_t>(nodes[static_cast<std::size_t>(i)]);
      candidate.config.nodes[static_cast<std::size_t>(i)] = master.positions[n];
      candidate.config.normals[static_cast<std::size_t>(i)] = gregory ? master_normals[n] : Vec3::Zero();
    }
    candidate.config.slave = slave;
    candidate.label = dataset::label_configuration(candidate.config, options.surface, options.projection);
    const bool inside = candidate.label.status == Status::kOk;
    const double distance = distance_to_segment(candidate.config, candidate.label, options.surface);
    double longest_edge = 0.0;
    for (int i = 0; i < 4; ++i) {
      longest_edge = std::max(
          longest_edge,
          (at(nodes[static_cast<std::size_t>(i)]) - at(nodes[static_cast<std::size_t>((i + 1) % 4)])).norm());
    }
    // Inside beats outside; then strictly nearer (beyond the tie tolerance) wins; ties keep the earlier.
    const bool better =
        best.segment < 0 || (inside && !best_inside) ||
        (inside == best_inside && distance < best_distance - options.distance_tie_tolerance * longest_edge);
    if (better) {
      const int candidates = best.candidates;
      best.segment = candidate.segment;
      best.nodes = candidate.nodes;
      best.config = candidate.config;
      best.label = candidate.label;
      best.candidates = candidates;
      best_distance = distance;
      best_inside = inside;
    }
  }
  best.status = best.segment >= 0 ? PairStatus::kFound : PairStatus::kNoSegment;
  return best;
}

std::vector<NodeSegmentPair> global_search(const mesh::SurfaceMesh& master,
                                           std::span<const Vec3> master_normals,
                                           std::span<const long> slave_ids,
                                           std::span<const Vec3> slave_positions,
                                           const SearchOptions& options) {
  CONTACTNN_REQUIRE(slave_ids.size() == slave_positions.size(),
                    slave_ids.size() << " slave ids for " << slave_positions.size() << " positions");
  // Checked here: an exception must not leave the parallel loop.
  CONTACTNN_REQUIRE(
      options.surface != SurfaceKind::kGregory || master_normals.size() == master.positions.size(),
      "Gregory search needs one node normal per master node: " << master_normals.size() << " for "
                                                               << master.positions.size());
  // In the working unit (surface_search.hpp): a copy of the master and the slave nodes where it is not 1.
  const double unit = working_unit(master);
  if (unit != 1.0) {
    std::vector<Vec3> slaves(slave_positions.begin(), slave_positions.end());
    for (Vec3& x : slaves) x /= unit;
    std::vector<NodeSegmentPair> pairs =
        global_search(in_unit(master, unit), master_normals, slave_ids, slaves, in_unit(options, unit));
    for (std::size_t i = 0; i < pairs.size(); ++i) to_world(pairs[i], unit, slave_positions[i]);
    return pairs;
  }
  const auto n = static_cast<long>(slave_ids.size());
  std::vector<NodeSegmentPair> pairs(static_cast<std::size_t>(n));
  const bool tree = options.nearest == NearestNodeMethod::kTree;
  // The paper's search pairs with segments: the nearest node among the nodes that have one (the surface's
  // other faces, SPEC 9's triangles, are the surface search's).
  std::vector<int> segment_nodes;
  std::vector<Vec3> segment_positions;
  for (int node = 0; node < master.node_count(); ++node) {
    if (master.segments_of(node).empty()) continue;
    segment_nodes.push_back(node);
    segment_positions.push_back(master.positions[static_cast<std::size_t>(node)]);
  }
  const NearestPointTree index(tree ? std::span<const Vec3>(segment_positions) : std::span<const Vec3>());
#pragma omp parallel for schedule(dynamic, 16)
  for (long i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const int k = tree ? index.nearest(slave_positions[u])
                       : nearest_point_brute_force(segment_positions, slave_positions[u]);
    const int nearest = k < 0 ? -1 : segment_nodes[static_cast<std::size_t>(k)];
    pairs[u] =
        pair_at_nearest_node(master, master_normals, slave_ids[u], slave_positions[u], nearest, options);
  }
  return pairs;
}

}  // namespace contactnn::contact
