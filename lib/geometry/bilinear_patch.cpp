#include "geometry/bilinear_patch.hpp"

#include <algorithm>
#include <cmath>

namespace contactnn::geometry {

double max_node_distance(const std::array<Vec3, 4>& nodes) {
  return max_node_distance(std::span<const Vec3>(nodes));
}

double max_node_distance(std::span<const Vec3> nodes) {
  // The largest squared distance, then one square root: sqrt is correctly rounded and monotone, so it is the
  // largest norm bit for bit (a NaN distance is passed over either way).
  double longest = 0.0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (std::size_t j = i + 1; j < nodes.size(); ++j)
      longest = std::max(longest, (nodes[i] - nodes[j]).squaredNorm());
  }
  return std::sqrt(longest);
}

double BilinearPatch::characteristic_length() const { return max_node_distance(nodes_); }

}  // namespace contactnn::geometry
