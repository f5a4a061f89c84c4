#pragma once
// The geometry of one master face as the surface search sees it (surface_search.cpp's steps 2-4): the surface
// a face is searched on, its closest point to a slave point, and its unit normals on an edge and at a corner
// (the pseudo-normal's terms). Internal to lib/contact (surface_search.cpp), not part of its interface.

#include <array>
#include <cstddef>
#include <span>

#include "contact/bilinear_certificate.hpp"
#include "contact/curved_certificate.hpp"
#include "contact/surface_search.hpp"
#include "geometry/configuration.hpp"
#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "geometry/surface_of.hpp"
#include "mesh/surface_mesh.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::contact::detail {

/// The surface kind a quad4 face f is searched on: the segments (C3D8) on the search's own surface, the extra
/// faces (wedge quadrilaterals) always as bilinear facets (their nodes need not have Eq 26 normals).
SurfaceKind kind_of(const mesh::SurfaceMesh& master, const SearchOptions& options, int f);

/// The configuration of quadrilateral face f's corners in its own node order (Gregory: with the master's node
/// normals).
geometry::Configuration face_configuration(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                                           SurfaceKind kind, int f);

/// Triangle f's three corners.
std::array<Vec3, 3> triangle_nodes(const mesh::SurfaceMesh& master, int f);

template <std::size_t N>
std::array<Vec3, N> face_positions(const mesh::SurfaceMesh& master, const mesh::FaceNodes& nodes) {
  std::array<Vec3, N> x;
  for (std::size_t i = 0; i < N; ++i) x[i] = master.positions[static_cast<std::size_t>(nodes.nodes[i])];
  return x;
}

/// Returns fn(surface) for face f's surface, a face that is not a flat triangle: a BilinearPatch or a
/// GregoryPatch (quad4, kind_of), a SerendipityQuad (quad8) or a QuadraticTriangle (tri6; under either
/// --surface, a quadratic face is its own surface). `fallback` where a Gregory patch does not exist (its
/// defect, e.g. a zero node normal).
template <class R, class Fn>
R with_face_surface(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                    const SearchOptions& options, int f, const R& fallback, Fn&& fn) {
  const mesh::FaceNodes nodes = master.face_nodes(f);
  if (nodes.type == mesh::FaceType::kQuad8)
    return fn(geometry::SerendipityQuad(face_positions<8>(master, nodes)));
  if (nodes.type == mesh::FaceType::kTri6)
    return fn(geometry::QuadraticTriangle(face_positions<6>(master, nodes)));
  const SurfaceKind kind = kind_of(master, options, f);
  const geometry::Configuration config = face_configuration(master, normals, kind, f);
  if (geometry::surface_defect(config, kind)) return fallback;
  return geometry::with_surface(config, kind, [&](const auto& surface) -> R { return fn(surface); });
}

/// The closest point of face f to `slave` (closest_point_on_triangle for a flat triangle, else the projection
/// of its face type). With `certificate` (a checked bilinear face's, NarrowPhase::kCertified) or `curved`
/// (a quad8, tri6 or Gregory face's, CurvedCertificate): its certified
/// Newton run first, from `start` (a tracked node's previous point on the face, in its own order) or the
/// centre. Otherwise, or where the certificate does not hold, the reference (its grid of starts, never a warm
/// start: a warm run can end on another stationary point than the face's nearest, on its boundary or, on a
/// curved face, inside; issue 39), and *reference_count counts the face. `curved_convex`: the caller has
/// found `curved`'s convex_for true for this slave.
projection::FaceClosestPoint closest_on_face(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                                             const SearchOptions& options, int f, const Vec3& slave,
                                             const BilinearCertificate* certificate = nullptr,
                                             const std::array<double, 2>* start = nullptr,
                                             int* reference_count = nullptr,
                                             const CurvedCertificate* curved = nullptr,
                                             bool curved_convex = false);

/// n / |n|, or zero where |n| is zero or not finite.
Vec3 unit_or_zero(const Vec3& n);

/// Face f's unit normal at the point of its edge `edge` nearest `p` (a point of that edge).
Vec3 normal_on_edge(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                    const SearchOptions& options, int f, int edge, const Vec3& p);

/// Face f's corner angle at its corner k times its unit normal there (a vertex pseudo-normal's term). The
/// angle is between the tangents of the face's two edges at the corner (curved edges: their tangents there).
Vec3 weighted_corner_normal(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                            const SearchOptions& options, int f, int k);

}  // namespace contactnn::contact::detail
