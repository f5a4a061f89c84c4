#include "mesh/solid_mesh.hpp"

#include "core/error.hpp"

namespace contactnn::mesh {

int SolidMesh::add_node(long id, const Vec3& position) {
  const int index = node_count();
  const bool inserted = node_index_.emplace(id, index).second;
  CONTACTNN_REQUIRE(inserted, "node " << id << " is defined twice");
  node_ids_.push_back(id);
  positions_.push_back(position);
  if (!deck_positions_.empty()) deck_positions_.push_back(position);
  return index;
}

void SolidMesh::set_position(int node, const Vec3& position) {
  CONTACTNN_REQUIRE(node >= 0 && node < node_count(),
                    "node index " << node << " outside [0, " << node_count() << ")");
  CONTACTNN_REQUIRE(position.allFinite(),
                    "node " << node_id(node) << ": position (" << position.transpose() << ") is not finite");
  if (deck_positions_.empty()) deck_positions_ = positions_;
  positions_[static_cast<std::size_t>(node)] = position;
}

int SolidMesh::add_element(long id, const ElementType& type, std::span<const int> node_indices) {
  CONTACTNN_REQUIRE(type.node_count == 0 || static_cast<int>(node_indices.size()) == type.node_count,
                    "element " << id << " of type " << type.name << " has " << node_indices.size()
                               << " nodes, expected " << type.node_count);
  for (int n : node_indices) {
    CONTACTNN_REQUIRE(n >= 0 && n < node_count(),
                      "element " << id << ": node index " << n << " outside [0, " << node_count() << ")");
  }
  const int index = element_count();
  const bool inserted = element_index_.emplace(id, index).second;
  CONTACTNN_REQUIRE(inserted, "element " << id << " is defined twice");
  int type_index = -1;
  for (std::size_t t = 0; t < types_.size(); ++t) {
    if (types_[t].name == type.name) type_index = static_cast<int>(t);
  }
  if (type_index < 0) {
    type_index = static_cast<int>(types_.size());
    types_.push_back(type);
  }
  element_ids_.push_back(id);
  element_type_.push_back(type_index);
  element_nodes_.insert(element_nodes_.end(), node_indices.begin(), node_indices.end());
  node_offsets_.push_back(element_nodes_.size());
  return index;
}

int SolidMesh::find_node(long id) const {
  const auto it = node_index_.find(id);
  return it == node_index_.end() ? -1 : it->second;
}

int SolidMesh::find_element(long id) const {
  const auto it = element_index_.find(id);
  return it == element_index_.end() ? -1 : it->second;
}

const ElementType& SolidMesh::element_type(int element) const {
  return types_[static_cast<std::size_t>(element_type_[static_cast<std::size_t>(element)])];
}

std::span<const int> SolidMesh::element_nodes(int element) const {
  const auto e = static_cast<std::size_t>(element);
  return {element_nodes_.data() + node_offsets_[e], node_offsets_[e + 1] - node_offsets_[e]};
}

}  // namespace contactnn::mesh
