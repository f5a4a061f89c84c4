// The closest point of a whole master face to a slave node: its interior, its edges and its vertices
// (SPEC 9 "Closest point on a face"). The reference the surface search labels with.
#pragma once

#include <array>

#include "core/conventions.hpp"
#include "geometry/surface_point.hpp"
#include "projection/newton_projection.hpp"

namespace contactnn::projection {

/// Edges of a quadrilateral face in its own node order: 0 = A->B, 1 = B->C, 2 = C->D, 3 = D->A; vertices
/// 0..3 = A, B, C, D. In the parameters (s, t) of [lo, hi]^2 edge 0 is t = lo, edge 1 s = hi, edge 2 t = hi,
/// edge 3 s = lo.
inline constexpr int kQuadEdges = 4;

/// Parameters of the point t in [lo, hi] of edge `edge` of the quadrilateral domain d (t increases with the
/// free parameter, whatever the edge's direction in the node order: the nearest point does not depend on it).
[[nodiscard]] constexpr std::array<double, 2> domain_edge_param(int edge, double t, ParamDomain d) {
  switch (edge) {
    case 0: return {t, d.lo};
    case 1: return {d.hi, t};
    case 2: return {t, d.hi};
    default: return {d.lo, t};
  }
}

/// The closest point P of a face to S.
struct [[nodiscard]] FaceClosestPoint {
  std::array<double, 2> param{0.0, 0.0};  ///< (xi, eta) or (u, v) of P, inside the closed domain
  Vec3 point = Vec3::Zero();              ///< P, world coordinates
  Vec3 normal = Vec3::Zero();             ///< unit P_s x P_t at P (zero where it vanishes)
  double distance = 0.0;                  ///< |S - P|
  Location location = Location::kFace;    ///< where P lies: face interior, an edge, a vertex
  int feature = -1;                  ///< the edge (0..3) or vertex (0..3) for kEdge / kVertex; -1 for kFace
  int iterations = 0;                ///< Newton iterations of the interior projection
  Status status = Status::kInvalid;  ///< ok (a point was found), degenerate or invalid (no point)
  bool by_method =
      false;  ///< the point of a method of the user's choice (contact::FaceLocator), not the exact one
};

/// How far from the boundary, in parameter units, a point still counts as on it (relative to the domain's
/// width): the reference projection's default domain margin, so an interior stationary point that the
/// labels call inside by the margin and an edge point agree on where they are.
inline constexpr double kOnBoundaryTolerance = 1e-10;

/// Sets out.location and out.feature from out.param, a point of the quadrilateral domain [d.lo, d.hi]^2: a
/// coordinate within kOnBoundaryTolerance x the width of a bound is on it; none: face, one: edge, two:
/// vertex.
void locate_on_quad(ParamDomain d, FaceClosestPoint& out);
/// Sets out.location and out.feature from out.param = (r, s) of a triangle (edges A->B, B->C, C->A; vertices
/// A, B, C): on an edge where s, 1 - r - s or r is within kOnBoundaryTolerance of 0.
void locate_on_triangle(FaceClosestPoint& out);

/// The report of the face point at out.param (located already) from the face's evaluation `at` there: its
/// point, distance to `slave`, unit normal (zero where d_s x d_t is), status ok unless the distance is not
/// finite. Every exact projection ends with it; a caller that has just evaluated the face at its answer
/// passes that evaluation instead of making it again.
void report_at(const geometry::SurfacePoint& at, const Vec3& slave, FaceClosestPoint& out);

/// The closest point of `surface` (the closed parameter domain [lo, hi]^2) to `slave`.
///  1. Interior: the reference projection (project_point, with `options`); a result with status ok is a
///     candidate.
///  2. Each edge: the nearest point of the boundary curve (straight for the bilinear facet: exact; a cubic
///     Bezier curve for the Gregory patch: the best of 33 samples, refined by safeguarded 1-D Newton on
///     every sampled local minimum), its ends included (the vertices).
///  3. The nearest candidate wins (ties: the interior, then the lower edge). Its location follows from its
///     parameters (the interior's clamped to the closed domain): a coordinate within kOnBoundaryTolerance x
///     width of a bound is on that bound; none: face, one: edge, two: vertex.
/// Computed relative to the face's first node (the point is reported in the caller's coordinates).
/// Status: invalid for a non-finite slave or surface value; degenerate for a collapsed face
/// (geometry::is_degenerate_segment of its nodes); ok otherwise. Limits: the interior search is the reference
/// projection's (a local method from a grid of starts).
template <geometry::Surface SurfaceT>
[[nodiscard]] FaceClosestPoint closest_point_on_face(const SurfaceT& surface, const Vec3& slave,
                                                     const ProjectionOptions& options = {});

/// Steps 2 and 3 above, given step 1's answer: `interior` the interior stationary point's parameters (clamped
/// to the closed domain here; null: none) and `iterations` its Newton iterations. The nearest of it and the
/// four edge points (strictly nearer replaces), located and reported as closest_point_on_face does; status
/// invalid where a surface value is not finite. `from_interior` (optional): whether the interior point won.
/// For closest_point_on_face and for faster interior solvers that must answer as it does (lib/contact's
/// BilinearCertificate). `edges_farther`: the caller has proved every edge point farther than the interior
/// one by more than the rounding of either distance (a strictly convex f, the point well inside): the
/// edges are not computed, and the answer is the one they would have lost to.
template <geometry::Surface SurfaceT>
[[nodiscard]] FaceClosestPoint nearest_of_interior_and_edges(const SurfaceT& surface, const Vec3& slave,
                                                             const std::array<double, 2>* interior,
                                                             int iterations, bool* from_interior = nullptr,
                                                             bool edges_farther = false);

/// The nearest point of edge `edge` (0..3) of `surface` to `slave` (step 2 above): its parameters on the
/// face and |S - P|. For tests and the surface search's own use.
struct EdgePoint {
  std::array<double, 2> param{0.0, 0.0};
  double distance = 0.0;
};
template <geometry::Surface SurfaceT>
[[nodiscard]] EdgePoint closest_point_on_edge(const SurfaceT& surface, int edge, const Vec3& slave);

/// The closest point of the flat triangle A, B, C (tri3, SPEC 9) to `slave`, exact (no iteration): the
/// projection onto the plane where it lies inside, else the nearest of the three clamped edge points.
/// param = (r, s) with P = A + r (B - A) + s (C - A); edges 0 = A->B, 1 = B->C, 2 = C->A, vertices 0..2 = A,
/// B, C; location as for quadrilaterals with kOnBoundaryTolerance on r, s and 1 - r - s. Status: invalid for
/// a non-finite input; degenerate when |(B - A) x (C - A)| is at most 1e-12 of its longest edge squared.
[[nodiscard]] FaceClosestPoint closest_point_on_triangle(const std::array<Vec3, 3>& nodes, const Vec3& slave);

/// What closest_point_on_triangle computes of the triangle alone, computed once (a search's master face at
/// one state): its edges, their Gram system, its unit normal; status invalid or degenerate as there.
struct PreparedTriangle {
  std::array<Vec3, 3> nodes;
  std::array<Vec3, 3> chords;  ///< B - A, C - B, A - C
  Vec3 normal = Vec3::Zero();  ///< unit (B - A) x (C - A)
  double g11 = 0.0, g12 = 0.0, g22 = 0.0, det = 0.0;
  Status status = Status::kInvalid;
};
[[nodiscard]] PreparedTriangle prepare_triangle(const std::array<Vec3, 3>& nodes);
/// closest_point_on_triangle(triangle.nodes, slave), bit for bit (it is this with the triangle prepared).
[[nodiscard]] FaceClosestPoint closest_point_on_prepared_triangle(const PreparedTriangle& triangle,
                                                                  const Vec3& slave);
/// The same into `out`, every field written where the caller keeps it (an answer returned and copied at
/// once is read back across its own stores: a store-forwarding stall per query).
void closest_point_on_prepared_triangle(const PreparedTriangle& triangle, const Vec3& slave,
                                        FaceClosestPoint& out);

}  // namespace contactnn::projection
