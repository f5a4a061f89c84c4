// The faces at each node of a master surface: its topology, built once for a connectivity and kept while the
// connectivity does not change (a tracker's increments move the nodes, not the faces).
#pragma once

#include <span>
#include <vector>

#include "mesh/surface_mesh.hpp"

namespace contactnn::contact {

/// The faces at each surface node (as a corner), increasing: node i's are faces[offsets[i] .. offsets[i + 1])
/// (one flat list: a list per node cost 1e5 allocations per state of a large master). The faces sharing an
/// edge are those of its first corner that have it.
class NodeFaces {
 public:
  /// Built from `master`'s connectivity (its node count and every face's corners; not its positions).
  explicit NodeFaces(const mesh::SurfaceMesh& master);

  [[nodiscard]] std::span<const int> at(int node) const {
    const auto n = static_cast<std::size_t>(node);
    return {faces_.data() + offsets_[n], static_cast<std::size_t>(offsets_[n + 1] - offsets_[n])};
  }

  /// True when `master` has the connectivity this was built from (the same node count, the same corners of
  /// every face, in order): then this is its topology whatever its positions.
  [[nodiscard]] bool matches(const mesh::SurfaceMesh& master) const;

 private:
  std::vector<int> offsets_, faces_;
  std::vector<int> corners_;       ///< every face's corners, face after face
  std::vector<int> corner_start_;  ///< face f's in corners_[corner_start_[f] .. corner_start_[f + 1])
};

}  // namespace contactnn::contact
