// The surface search's lengths (surface_search.hpp): the working unit, the conversions into and out of it,
// and the capture distance.
#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/surface_search.hpp"

namespace contactnn::contact {

double working_unit(const mesh::SurfaceMesh& m) {
  double largest = 0.0;  // a maximum: the same at any thread count
  const auto n = static_cast<long>(m.positions.size());
#pragma omp parallel for reduction(max : largest) schedule(static) if (n >= 16384)
  for (long i = 0; i < n; ++i) {
    const double a = m.positions[static_cast<std::size_t>(i)].cwiseAbs().maxCoeff();
    if (std::isfinite(a)) largest = std::max(largest, a);
  }
  if (!(largest >= std::numeric_limits<double>::min())) return 1.0;
  int exponent = 0;
  (void)std::frexp(largest, &exponent);
  return exponent >= -40 && exponent <= 40 ? 1.0 : std::ldexp(1.0, exponent - 1);
}

mesh::SurfaceMesh in_unit(const mesh::SurfaceMesh& master, double unit) {
  mesh::SurfaceMesh copy = master;
  for (Vec3& x : copy.positions) x /= unit;
  return copy;
}

SearchOptions in_unit(SearchOptions options, double unit) {
  options.capture_distance /= unit;
  return options;
}

void to_world(NodeSegmentPair& pair, double unit, const Vec3& slave) {
  pair.point *= unit;
  pair.label.gap *= unit;
  for (Vec3& x : pair.config.nodes) x *= unit;
  pair.config.slave = slave;
}

double capture_distance(const mesh::SurfaceMesh& master, const SearchOptions& options) {
  if (options.capture_distance > 0.0) return options.capture_distance;
  double largest = 0.0;
  for (int f = 0; f < master.face_count(); ++f) {
    for (int a : master.face_corners(f)) {
      for (int b : master.face_corners(f)) {
        largest = std::max(largest, (master.positions[static_cast<std::size_t>(a)] -
                                     master.positions[static_cast<std::size_t>(b)])
                                        .norm());
      }
    }
  }
  return options.capture_relative * largest;
}

}  // namespace contactnn::contact
