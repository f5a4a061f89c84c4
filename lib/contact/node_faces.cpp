#include "contact/node_faces.hpp"

#include <algorithm>
#include <cstddef>
#include <vector>

#include "contact/parallel_lists.hpp"

namespace contactnn::contact {

NodeFaces::NodeFaces(const mesh::SurfaceMesh& master) {
  const auto n = static_cast<std::size_t>(master.face_count());
  corner_start_.resize(n + 1);
  corner_start_[0] = 0;
  for (std::size_t f = 0; f < n; ++f)
    corner_start_[f + 1] =
        corner_start_[f] + static_cast<int>(master.face_corners(static_cast<int>(f)).size());
  corners_.resize(static_cast<std::size_t>(corner_start_[n]));
#pragma omp parallel for schedule(static) if (n >= 16384)
  for (std::size_t f = 0; f < n; ++f) {
    const std::span<const int> corners = master.face_corners(static_cast<int>(f));
    std::copy(corners.begin(), corners.end(), corners_.begin() + corner_start_[f]);
  }
  // Counted, then filled in face order, in parallel with the serial layout (fill_lists): the nodes split
  // evenly among the threads.
  const std::size_t nodes = master.positions.size();
  const auto split = [&](std::size_t threads) {
    std::vector<std::size_t> bounds(threads + 1);
    for (std::size_t t = 0; t <= threads; ++t) bounds[t] = nodes * t / threads;
    return bounds;
  };
  // fn(node) for each of face f's corners in [lo, hi), in the face's order.
  const auto own_corners = [&](std::size_t f, std::size_t lo, std::size_t hi, auto&& fn) {
    for (int k = corner_start_[f]; k < corner_start_[f + 1]; ++k) {
      const auto c = static_cast<std::size_t>(corners_[static_cast<std::size_t>(k)]);
      if (c >= lo && c < hi) fn(c);
    }
  };
  fill_lists(n, nodes, n >= 16384, split, own_corners, offsets_, faces_);
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
