#include "contact/node_faces.hpp"

#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <vector>

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
  // Counted, then filled in face order. The nodes are split among the threads, each counting and filling its
  // own nodes' lists from every face in order: the serial lists at any thread count.
  const std::size_t nodes = master.positions.size();
  offsets_.resize(nodes + 1);
  offsets_[0] = 0;
  std::vector<int> ends;  // each thread's count, then the offset its nodes start at
#pragma omp parallel if (n >= 16384)
  {
    const auto threads = static_cast<std::size_t>(omp_get_num_threads());
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
#pragma omp single
    ends.assign(threads + 1, 0);
    const std::size_t lo = nodes * t / threads, hi = nodes * (t + 1) / threads;
    std::fill(offsets_.begin() + static_cast<std::ptrdiff_t>(lo + 1),
              offsets_.begin() + static_cast<std::ptrdiff_t>(hi + 1), 0);
    const auto mine = [&](int c) {
      return static_cast<std::size_t>(c) >= lo && static_cast<std::size_t>(c) < hi;
    };
    for (const int c : corners_)
      if (mine(c)) ++offsets_[static_cast<std::size_t>(c) + 1];
    int sum = 0;
    for (std::size_t i = lo; i < hi; ++i) {
      sum += offsets_[i + 1];
      offsets_[i + 1] = sum;
    }
    ends[t + 1] = sum;
#pragma omp barrier
#pragma omp single
    {
      for (std::size_t k = 1; k <= threads; ++k) ends[k] += ends[k - 1];
      faces_.resize(static_cast<std::size_t>(ends[threads]));
    }
    for (std::size_t i = lo; i < hi; ++i) offsets_[i + 1] += ends[t];
#pragma omp barrier
    std::vector<int> at(offsets_.begin() + static_cast<std::ptrdiff_t>(lo),
                        offsets_.begin() + static_cast<std::ptrdiff_t>(hi));
    for (std::size_t f = 0; f < n; ++f) {
      for (int k = corner_start_[f]; k < corner_start_[f + 1]; ++k) {
        const int c = corners_[static_cast<std::size_t>(k)];
        if (mine(c))
          faces_[static_cast<std::size_t>(at[static_cast<std::size_t>(c) - lo]++)] = static_cast<int>(f);
      }
    }
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
