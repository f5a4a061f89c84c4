#include "contact/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace contactnn::contact {

Scene make_scene(const mesh::ContactModel& model, int k) {
  Scene scene;
  const mesh::ContactPairDefinition& pair = mesh::contact_pair(model, k);
  scene.pair = k;
  scene.slave_name = pair.slave_name;
  scene.master_name = pair.master_name;
  scene.where = pair.where;
  scene.master = mesh::master_surface(model, k);
  scene.master_normals = mesh::node_normals(scene.master);
  scene.slaves = mesh::slave_nodes(model, k, scene.master);
  for (int n : scene.slaves.nodes) {
    scene.slave_ids.push_back(model.mesh.node_id(n));
    scene.slave_positions.push_back(model.mesh.position(n));
  }
  return scene;
}

SceneResult search_scene(const Scene& scene, const SearchOptions& options) {
  SceneResult result;
  result.pairs = global_search(scene.master, scene.master_normals, scene.slave_ids, scene.slave_positions, options);
  for (const NodeSegmentPair& p : result.pairs) {
    if (p.status == PairStatus::kFound) {
      ++result.found;
      ++result.label_status_counts[static_cast<std::size_t>(p.label.status)];
    } else {
      ++result.no_segment;
    }
  }
  result.statistics = shape_statistics(result.pairs, options.surface);
  return result;
}

double largest_relative_offset(const SceneResult& result) {
  double largest = 0.0;
  for (const NodeSegmentPair& p : result.pairs) {
    if (p.status != PairStatus::kFound) continue;
    if (p.label.status != Status::kOk && p.label.status != Status::kOutside) continue;
    double shortest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) shortest = std::min(shortest, (p.config.nodes[(i + 1) % 4] - p.config.nodes[i]).norm());
    if (shortest > 0.0) largest = std::max(largest, std::abs(p.label.gap) / shortest);
  }
  return largest;
}

}  // namespace contactnn::contact
