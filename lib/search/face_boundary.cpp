#include "search/face_boundary.hpp"

#include <cmath>
#include <limits>

#include "geometry/bilinear_patch.hpp"
#include "geometry/configuration.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/surface_of.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::search::detail {

template <class Real>
void move_to_face_boundary(SurfaceKind kind, const Real* raw, Real* param, Real* gap, Status* status,
                           Location* location) {
  geometry::Configuration config;
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 3; ++k) {
      config.nodes[static_cast<std::size_t>(i)][k] = static_cast<double>(raw[3 * i + k]);
      config.normals[static_cast<std::size_t>(i)][k] =
          kind == SurfaceKind::kGregory ? static_cast<double>(raw[15 + 3 * i + k]) : 0.0;
    }
  }
  for (int k = 0; k < 3; ++k) config.slave[k] = static_cast<double>(raw[12 + k]);
  if (geometry::surface_defect(config, kind)) return;
  // Relative to the first node, as projection::closest_point_on_face computes (the same arithmetic).
  const geometry::Vec3 origin = config.nodes[0];
  for (geometry::Vec3& x : config.nodes) x -= origin;
  config.slave -= origin;
  geometry::with_surface(config, kind, [&](const auto& surface) {
    const ParamDomain d = param_domain(kind);
    projection::EdgePoint best;
    best.distance = std::numeric_limits<double>::infinity();
    for (int edge = 0; edge < projection::kQuadEdges; ++edge) {
      const projection::EdgePoint e = projection::closest_point_on_edge(surface, edge, config.slave);
      if (e.distance < best.distance) best = e;
    }
    if (!std::isfinite(best.distance)) return;
    const geometry::SurfacePoint p = surface.evaluate(best.param[0], best.param[1]);
    const geometry::Vec3 n = p.d_s.cross(p.d_t);
    const bool below = n.dot(config.slave - p.position) < 0.0;
    param[0] = static_cast<Real>(best.param[0]);
    param[1] = static_cast<Real>(best.param[1]);
    if (gap != nullptr) {
      const double g = below ? -best.distance : best.distance;
      const double largest = static_cast<double>(std::numeric_limits<Real>::max());
      *gap = static_cast<Real>(std::isfinite(g) && std::abs(g) <= largest ? g : std::copysign(largest, g));
    }
    *status = Status::kOk;
    if (location != nullptr) {
      const auto at_end = [&](double x) { return x == d.lo || x == d.hi; };
      *location = at_end(best.param[0]) && at_end(best.param[1]) ? Location::kVertex : Location::kEdge;
    }
  });
}

template void move_to_face_boundary<float>(SurfaceKind, const float*, float*, float*, Status*, Location*);
template void move_to_face_boundary<double>(SurfaceKind, const double*, double*, double*, Status*, Location*);

}  // namespace contactnn::search::detail
