#include "geometry/bilinear_patch.hpp"

#include <algorithm>

namespace contactnn::geometry {

double max_node_distance(const std::array<Vec3, 4>& nodes) {
  double longest = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) longest = std::max(longest, (nodes[i] - nodes[j]).norm());
  }
  return longest;
}

double BilinearPatch::characteristic_length() const { return max_node_distance(nodes_); }

}  // namespace contactnn::geometry
