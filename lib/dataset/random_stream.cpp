#include "dataset/random_stream.hpp"

#include <cmath>

namespace contactnn::dataset {

std::array<geometry::Vec3, 4> random_node_normals(const std::array<geometry::Vec3, 4>& nodes,
                                                  double max_tangent, RandomStream& random) {
  std::array<geometry::Vec3, 4> normals;
  for (int i = 0; i < 4; ++i) {
    const geometry::Vec3 corner =
        (nodes[(i + 1) % 4] - nodes[i]).cross(nodes[(i + 3) % 4] - nodes[i]).normalized();
    const geometry::Vec3 t1 = corner.unitOrthogonal();
    const geometry::Vec3 t2 = corner.cross(t1);
    const double tangent = max_tangent * random.uniform01();
    const double phi = 2.0 * M_PI * random.uniform01();
    normals[i] = (corner + tangent * (std::cos(phi) * t1 + std::sin(phi) * t2)).normalized();
  }
  return normals;
}

}  // namespace contactnn::dataset
