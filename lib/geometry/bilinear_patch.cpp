#include "geometry/bilinear_patch.hpp"

#include <algorithm>

namespace contactnn::geometry {

double max_node_distance(const std::array<Vec3, 4>& nodes) {
  return max_node_distance(std::span<const Vec3>(nodes));
}

double max_node_distance(std::span<const Vec3> nodes) {
  double longest = 0.0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (std::size_t j = i + 1; j < nodes.size(); ++j)
      longest = std::max(longest, (nodes[i] - nodes[j]).norm());
  }
  return longest;
}

double BilinearPatch::characteristic_length() const { return max_node_distance(nodes_); }

}  // namespace contactnn::geometry
