#include "contact/face_surface.hpp"

#include <cmath>

#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "projection/closest_point_on_quadratic_face.hpp"

namespace contactnn::contact::detail {

namespace {

/// The closest point of a face's surface (the overloads pick the projection of each face type).
template <geometry::Surface SurfaceT>
projection::FaceClosestPoint closest_on(const SurfaceT& surface, const Vec3& slave,
                                        const SearchOptions& options) {
  return projection::closest_point_on_face(surface, slave, options.projection);
}
projection::FaceClosestPoint closest_on(const geometry::SerendipityQuad& face, const Vec3& slave,
                                        const SearchOptions& options) {
  return projection::closest_point_on_serendipity_quad(face, slave, options.projection);
}
projection::FaceClosestPoint closest_on(const geometry::QuadraticTriangle& face, const Vec3& slave,
                                        const SearchOptions& options) {
  return projection::closest_point_on_quadratic_triangle(face, slave, options.projection);
}

/// The nearest point of a face's edge (the overloads: straight or cubic edges of quad4 faces, quadratic
/// ones).
template <geometry::Surface SurfaceT>
projection::EdgePoint edge_point_on(const SurfaceT& surface, int edge, const Vec3& p) {
  return projection::closest_point_on_edge(surface, edge, p);
}
projection::EdgePoint edge_point_on(const geometry::SerendipityQuad& face, int edge, const Vec3& p) {
  return projection::closest_point_on_quadratic_edge(face, edge, p);
}
projection::EdgePoint edge_point_on(const geometry::QuadraticTriangle& face, int edge, const Vec3& p) {
  return projection::closest_point_on_quadratic_edge(face, edge, p);
}

/// Parameters of corner k (A, B, C, D) of a quadrilateral face.
std::array<double, 2> corner_param(int k, ParamDomain d) {
  switch (k) {
    case 0: return {d.lo, d.lo};
    case 1: return {d.hi, d.lo};
    case 2: return {d.hi, d.hi};
    default: return {d.lo, d.hi};
  }
}

/// The angle between two tangents at a corner times the unit normal there (a vertex pseudo-normal's term).
Vec3 angle_weighted(const Vec3& t1, const Vec3& t2, const Vec3& normal) {
  return std::atan2(t1.cross(t2).norm(), t1.dot(t2)) * unit_or_zero(normal);
}

}  // namespace

SurfaceKind kind_of(const mesh::SurfaceMesh& master, const SearchOptions& options, int f) {
  return static_cast<std::size_t>(f) < master.segments.size() ? options.surface : SurfaceKind::kBilinear;
}

geometry::Configuration face_configuration(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                                           SurfaceKind kind, int f) {
  geometry::Configuration config;
  const std::span<const int> corners = master.face_corners(f);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto n = static_cast<std::size_t>(corners[i]);
    config.nodes[i] = master.positions[n];
    config.normals[i] = kind == SurfaceKind::kGregory ? normals[n] : Vec3::Zero();
  }
  return config;
}

std::array<Vec3, 3> triangle_nodes(const mesh::SurfaceMesh& master, int f) {
  const std::span<const int> c = master.face_corners(f);
  return {master.positions[static_cast<std::size_t>(c[0])], master.positions[static_cast<std::size_t>(c[1])],
          master.positions[static_cast<std::size_t>(c[2])]};
}

projection::FaceClosestPoint closest_on_face(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                                             const SearchOptions& options, int f, const Vec3& slave,
                                             const BilinearCertificate* certificate,
                                             const std::array<double, 2>* start, int* reference_count,
                                             const CurvedCertificate* curved, bool curved_convex) {
  if (certificate != nullptr && certificate->lambda_floor > 0.0) {
    if (auto p = certificate->closest_point(slave, options.projection, start)) return *p;
  }
  if (curved != nullptr && curved->lambda_floor > 0.0) {
    if (auto p = curved->closest_point(slave, options.projection, start, curved_convex)) return *p;
  }
  if (master.face_type(f) == mesh::FaceType::kTri3) {
    return projection::closest_point_on_triangle(triangle_nodes(master, f), slave);
  }
  if (reference_count != nullptr) ++*reference_count;
  // The projection at `at` (S, or S relative to a quad4's first node).
  const auto project = [&](const auto& surface, const Vec3& at) { return closest_on(surface, at, options); };
  projection::FaceClosestPoint none;
  if (master.face_type(f) != mesh::FaceType::kQuad4) {
    return with_face_surface(master, normals, options, f, none,
                             [&](const auto& surface) { return project(surface, slave); });
  }
  // A quad4: its configuration built and checked once, and its patch built relative to its first node, as
  // projection::closest_point_on_face would rebuild it (the same bits: it then has nothing to shift).
  const SurfaceKind kind = kind_of(master, options, f);
  geometry::Configuration config = face_configuration(master, normals, kind, f);
  if (const auto defect = geometry::surface_defect(config, kind)) {
    none.status = *defect;
    return none;
  }
  const Vec3 origin = config.nodes[0];
  if (!origin.allFinite()) {
    return geometry::with_surface(config, kind, [&](const auto& surface) { return project(surface, slave); });
  }
  for (Vec3& x : config.nodes) x -= origin;
  const Vec3 relative = slave - origin;
  projection::FaceClosestPoint p =
      geometry::with_surface(config, kind, [&](const auto& surface) { return project(surface, relative); });
  if (p.status == Status::kOk) p.point += origin;
  return p;
}

Vec3 unit_or_zero(const Vec3& n) {
  const double length = n.norm();
  return length > 0.0 && std::isfinite(length) ? Vec3(n / length) : Vec3(Vec3::Zero());
}

Vec3 normal_on_edge(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                    const SearchOptions& options, int f, int edge, const Vec3& p) {
  if (master.face_type(f) == mesh::FaceType::kTri3) {
    const auto x = triangle_nodes(master, f);
    return unit_or_zero((x[1] - x[0]).cross(x[2] - x[0]));
  }
  return with_face_surface(master, normals, options, f, Vec3(Vec3::Zero()), [&](const auto& surface) -> Vec3 {
    const auto q = edge_point_on(surface, edge, p);
    const geometry::SurfacePoint sp = surface.evaluate(q.param[0], q.param[1]);
    return unit_or_zero(sp.d_s.cross(sp.d_t));
  });
}

Vec3 weighted_corner_normal(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                            const SearchOptions& options, int f, int k) {
  const mesh::FaceType type = master.face_type(f);
  if (type == mesh::FaceType::kTri3) {
    const auto x = triangle_nodes(master, f);
    const Vec3 a = x[static_cast<std::size_t>((k + 1) % 3)] - x[static_cast<std::size_t>(k)];
    const Vec3 b = x[static_cast<std::size_t>((k + 2) % 3)] - x[static_cast<std::size_t>(k)];
    return angle_weighted(a, b, (x[1] - x[0]).cross(x[2] - x[0]));
  }
  if (type == mesh::FaceType::kTri6) {
    const geometry::QuadraticTriangle face(face_positions<6>(master, master.face_nodes(f)));
    // Corners (0,0), (1,0), (0,1); the directions in (r, s) of the two edges leaving each.
    static constexpr std::array<std::array<double, 2>, 3> kCorner = {{{0, 0}, {1, 0}, {0, 1}}};
    static constexpr std::array<std::array<double, 4>, 3> kDirections = {
        {{1, 0, 0, 1}, {-1, 1, -1, 0}, {0, -1, 1, -1}}};
    const auto& c = kCorner[static_cast<std::size_t>(k)];
    const auto& d = kDirections[static_cast<std::size_t>(k)];
    const geometry::SurfacePoint sp = face.evaluate(c[0], c[1]);
    return angle_weighted(d[0] * sp.d_s + d[1] * sp.d_t, d[2] * sp.d_s + d[3] * sp.d_t, sp.d_s.cross(sp.d_t));
  }
  const ParamDomain d =
      param_domain(type == mesh::FaceType::kQuad8 ? SurfaceKind::kBilinear : kind_of(master, options, f));
  return with_face_surface(master, normals, options, f, Vec3(Vec3::Zero()), [&](const auto& surface) -> Vec3 {
    const auto corner = corner_param(k, d);
    const geometry::SurfacePoint sp = surface.evaluate(corner[0], corner[1]);
    // Tangents pointing into the face from the corner.
    const Vec3 ts = (corner[0] == d.lo ? 1.0 : -1.0) * sp.d_s;
    const Vec3 tt = (corner[1] == d.lo ? 1.0 : -1.0) * sp.d_t;
    return angle_weighted(ts, tt, sp.d_s.cross(sp.d_t));
  });
}

}  // namespace contactnn::contact::detail
