// The nodes and solid elements of a finite-element deck, addressed by index, with their deck ids.
#pragma once

#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "geometry/surface_point.hpp"
#include "mesh/element_type.hpp"

namespace contactnn::mesh {

using geometry::Vec3;

/// Nodes (id, position) and elements (id, type, nodes) in the order they were added. Ids are the deck's
/// (positive, unique per kind); everything else refers to nodes and elements by 0-based index.
class SolidMesh {
 public:
  /// Adds a node; returns its index. InvalidArgument if `id` is already a node (the reader checks first).
  int add_node(long id, const Vec3& position);
  /// Adds an element whose nodes are given by index; returns its index. InvalidArgument if `id` is already
  /// an element, a node index is out of range, or `node_indices` has not type.node_count entries (when
  /// that count is known).
  int add_element(long id, const ElementType& type, std::span<const int> node_indices);

  [[nodiscard]] int node_count() const { return static_cast<int>(node_ids_.size()); }
  [[nodiscard]] int element_count() const { return static_cast<int>(element_ids_.size()); }

  /// Index of node / element `id`, or -1 if there is none.
  [[nodiscard]] int find_node(long id) const;
  [[nodiscard]] int find_element(long id) const;

  [[nodiscard]] long node_id(int node) const { return node_ids_[static_cast<std::size_t>(node)]; }
  [[nodiscard]] const Vec3& position(int node) const { return positions_[static_cast<std::size_t>(node)]; }
  /// The position the node was added with (the deck's coordinates), whatever set_position did since: what
  /// decides which faces are collapsed (build_surface_mesh), so that a history keeps one set of faces.
  [[nodiscard]] const Vec3& deck_position(int node) const {
    return (deck_positions_.empty() ? positions_ : deck_positions_)[static_cast<std::size_t>(node)];
  }
  /// Moves node `node` (an index) to `position` (e.g. a solver's deformed configuration). InvalidArgument if
  /// `node` is out of range or `position` is not finite.
  void set_position(int node, const Vec3& position);
  [[nodiscard]] long element_id(int element) const { return element_ids_[static_cast<std::size_t>(element)]; }
  [[nodiscard]] const ElementType& element_type(int element) const;
  /// Node indices of an element, in the deck's order.
  [[nodiscard]] std::span<const int> element_nodes(int element) const;

 private:
  std::vector<long> node_ids_;
  std::vector<Vec3> positions_;
  std::vector<Vec3> deck_positions_;  ///< a copy of positions_ made by the first set_position; empty before
  std::unordered_map<long, int> node_index_;
  std::vector<long> element_ids_;
  std::vector<int> element_type_;   ///< index into types_
  std::vector<ElementType> types_;  ///< each distinct type once
  std::vector<std::size_t> node_offsets_{
      0};  ///< element e's nodes: element_nodes_[offsets[e] .. offsets[e+1])
  std::vector<int> element_nodes_;
  std::unordered_map<long, int> element_index_;
};

}  // namespace contactnn::mesh
