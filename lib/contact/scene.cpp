#include "contact/scene.hpp"

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

}  // namespace contactnn::contact
