// The closest point of a quadratic master face to a slave node (SPEC 9 "Closest point on a face"): the 8-node
// serendipity quadrilateral (quad8) and the 6-node triangle (tri6), their interiors, curved edges and
// vertices.
#pragma once

#include <array>

#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::projection {

/// Edges of a triangular face in its own node order: 0 = A->B, 1 = B->C, 2 = C->A; vertices 0..2 = A, B, C.
/// In (r, s): edge 0 is s = 0, edge 1 r + s = 1, edge 2 r = 0.
inline constexpr int kTriangleEdges = 3;

/// The closest point of the quad8 `face` ((xi, eta) in [-1, 1]^2, edges and vertices numbered as kQuadEdges)
/// to `slave`, with the result conventions of closest_point_on_face:
///  1. Interior: damped Newton on Eqs 7-8 with the exact Jacobian (the P_xi_eta.(S - P) term included; the
///     Gauss-Newton step where it is not positive definite; Armijo halving; iterates kept on the closed face,
///     a run pinned to its boundary stops) from every local minimum of |S - P|^2 sampled on a grid of
///     3 x options.starts_per_axis points per parameter over the closed face (options.warm_start: the one
///     start options.start instead); a converged local minimum of |S - P|^2 within options.domain_margin of
///     the domain is a candidate, its parameters clamped to the closed domain. options.max_iterations,
///     tol_param and tol_residual as for project_point. The face is moved to its first node first, so that
///     tolerances meet the rounding of the face's size, not of its distance from the origin.
///  2. Each edge, a quadratic curve: the nearest of 33 samples refined by safeguarded 1-D Newton on every
///     sampled local minimum (closest_point_on_quadratic_edge), its ends (the vertices) included.
///  3. The nearest candidate wins (ties: the interior, then the lower edge); location from the parameters
///     (kOnBoundaryTolerance x the domain width from a bound).
/// Status: invalid for a non-finite slave or node; degenerate when the corners' bilinear facet is
/// (geometry::is_degenerate_segment); ok otherwise. `normal` is the unit P_xi x P_eta at the point.
/// Limits: the interior search is a local method from sampled starts. On strongly curved faces (mid-side
/// nodes 0.3 of their edge off its chord) an interior minimum within a sample spacing of an edge was missed
/// for about 1 slave node in 10^4 of the tests' random ones (Newton from the nearest sample pinned at the
/// edge); with mid-side nodes up to 0.1 off their chords, none in 24000.
[[nodiscard]] FaceClosestPoint closest_point_on_serendipity_quad(const geometry::SerendipityQuad& face,
                                                                 const Vec3& slave,
                                                                 const ProjectionOptions& options = {});

/// The same for the tri6 `face`: (r, s) on the triangle r, s >= 0, r + s <= 1, edges and vertices as
/// kTriangleEdges. The interior starts are the sampled minima on the lattice of 3 x options.starts_per_axis
/// points per side (options.warm_start: options.start alone); iterates are kept on the closed triangle.
/// Location as for closest_point_on_triangle (kOnBoundaryTolerance on r, s and 1 - r - s). Status: invalid
/// for a non-finite input; degenerate when the corners are (|(B - A) x (C - A)| at most 1e-12 of the longest
/// corner distance squared); ok otherwise. `normal` is the unit P_r x P_s.
[[nodiscard]] FaceClosestPoint closest_point_on_quadratic_triangle(const geometry::QuadraticTriangle& face,
                                                                   const Vec3& slave,
                                                                   const ProjectionOptions& options = {});

/// Steps 2-3 of closest_point_on_serendipity_quad (closest_point_on_quadratic_triangle) given step 1's
/// answer, on `face` as given (those functions pass it moved to its first node): `interior` the converged
/// interior point (moved onto the closed face here; null: none) and `iterations` its Newton iterations. The
/// nearest of it and the edge points, located and reported as those functions do; status invalid where a
/// value is not finite. For faster interior solvers that must answer as the reference does (lib/contact's
/// CurvedCertificate). `from_interior` (optional): whether the interior point won. `edges_farther`: the
/// caller has proved every edge point farther than the interior one by more than the rounding of either
/// distance; the edges are then not computed.
/// Face parameters of the point t of edge `edge` (t = 0 at the edge's first corner, t = 1 at its second,
/// exactly): a quad8's (xi, eta) or a tri6's (r, s).
[[nodiscard]] std::array<double, 2> quad_edge_param(int edge, double t);
[[nodiscard]] std::array<double, 2> triangle_edge_param(int edge, double t);

/// Face: geometry::SerendipityQuad or geometry::QuadraticTriangle (instantiated for both).
template <class Face>
[[nodiscard]] FaceClosestPoint nearest_of_interior_and_quadratic_edges(const Face& face, const Vec3& slave,
                                                                       const std::array<double, 2>* interior,
                                                                       int iterations,
                                                                       bool* from_interior = nullptr,
                                                                       bool edges_farther = false);

/// The report of those functions for the point `param` of `face` (on the closed face): param, location,
/// point, unit normal, distance and status as they set them, `iterations` as given.
template <class Face>
[[nodiscard]] FaceClosestPoint quadratic_face_point(const Face& face, const Vec3& slave,
                                                    const std::array<double, 2>& param, int iterations);

/// The nearest point of edge `edge` of a quadratic face to `slave` (step 2 above): its parameters on the face
/// and |S - P|. The curve through the edge's corners X, Y and mid-side node M is
/// C(t) = X (1 - t)(1 - 2t) + 4 M t (1 - t) + Y t (2t - 1), t in [0, 1]; the ends are exact corner
/// parameters.
[[nodiscard]] EdgePoint closest_point_on_quadratic_edge(const geometry::SerendipityQuad& face, int edge,
                                                        const Vec3& slave);
[[nodiscard]] EdgePoint closest_point_on_quadratic_edge(const geometry::QuadraticTriangle& face, int edge,
                                                        const Vec3& slave);

}  // namespace contactnn::projection
