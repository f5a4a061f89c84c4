#include "contact/node_faces.hpp"

#include <algorithm>
#include <cstddef>

namespace contactnn::contact {

NodeFaces::NodeFaces(const mesh::SurfaceMesh& master) {
  const auto n = static_cast<std::size_t>(master.face_count());
  corner_start_.assign(n + 1, 0);
  for (std::size_t f = 0; f < n; ++f) {
    const std::span<const int> corners = master.face_corners(static_cast<int>(f));
    corners_.insert(corners_.end(), corners.begin(), corners.end());
    corner_start_[f + 1] = static_cast<int>(corners_.size());
  }
  // Counted, then filled in face order.
  offsets_.assign(master.positions.size() + 1, 0);
  for (const int c : corners_) ++offsets_[static_cast<std::size_t>(c) + 1];
  for (std::size_t i = 1; i < offsets_.size(); ++i) offsets_[i] += offsets_[i - 1];
  faces_.resize(static_cast<std::size_t>(offsets_.back()));
  std::vector<int> at(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t f = 0; f < n; ++f) {
    for (int k = corner_start_[f]; k < corner_start_[f + 1]; ++k)
      faces_[static_cast<std::size_t>(
          at[static_cast<std::size_t>(corners_[static_cast<std::size_t>(k)])]++)] = static_cast<int>(f);
  }
}

bool NodeFaces::matches(const mesh::SurfaceMesh& master) const {
  const auto n = static_cast<std::size_t>(master.face_count());
  if (n + 1 != corner_start_.size() || master.positions.size() + 1 != offsets_.size()) return false;
  bool same = true;
#pragma omp parallel for reduction(&& : same) schedule(static) if (n >= 16384)
  for (std::size_t f = 0; f < n; ++f) {
    const std::span<const int> corners = master.face_corners(static_cast<int>(f));
    const auto* mine = corners_.data() + corner_start_[f];
    same = same && static_cast<int>(corners.size()) == corner_start_[f + 1] - corner_start_[f] &&
           std::equal(corners.begin(), corners.end(), mine);
  }
  return same;
}

}  // namespace contactnn::contact
