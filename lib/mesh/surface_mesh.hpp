// A surface of a solid mesh as quadrilateral segments oriented outward, with node adjacency and the node
// normals of paper Eq 26 (SPEC 3, last bullet; SPEC 7 "Master segments"), and the other faces of SPEC 9
// (triangles, quadratic faces with their mid-side nodes).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/surface_point.hpp"
#include "mesh/solid_mesh.hpp"

namespace contactnn::mesh {

/// Face `face` (1-based: S1 = 1) of the element with index `element` in a SolidMesh.
struct ElementFace {
  int element = -1;
  int face = 0;
  friend bool operator==(const ElementFace&, const ElementFace&) = default;
};

/// The 4 corners (SolidMesh node indices) of a quadrilateral face, ordered so that (B - A) x (D - A)
/// points out of the element: A is the manual's first corner of the face (element_type.hpp), then the
/// manual's order reversed (A, D, C, B). That is outward for every element numbered as the manuals
/// require (positive volume); the element's centroid decides: if it lies on the side the normal
/// (C - A) x (D - B) points to, the element is inside out and the manual's own order is returned instead.
/// Precondition: the element's type has 4-corner face `face` (InvalidArgument otherwise).
[[nodiscard]] std::array<int, 4> outward_quad_corners(const SolidMesh& mesh, ElementFace face);

/// The corners of a triangular face (C3D4, C3D6, SPEC 9) ordered so that (B - A) x (C - A) points out of the
/// element (the manual's order reversed unless the element is inside out), then -1.
[[nodiscard]] std::array<int, 4> outward_triangle_corners(const SolidMesh& mesh, ElementFace face);

/// The face types of SPEC 9, by their nodes: 4-node quadrilateral (bilinear), 8-node serendipity
/// quadrilateral, 3-node (flat) triangle, 6-node quadratic triangle.
enum class FaceType : std::uint8_t { kQuad4, kQuad8, kTri3, kTri6 };
/// "quad4", "quad8", "tri3" or "tri6" (the `face_type` column of SPEC 9).
[[nodiscard]] std::string_view to_string(FaceType type);

/// A face's nodes in its own outward order (SPEC 9): the corners, then for a quadratic face the mid-side
/// nodes of the edges corner 1-2, 2-3, ... (quad8: A-B, B-C, C-D, D-A; tri6: A-B, B-C, C-A). Surface node
/// indices.
struct FaceNodes {
  FaceType type = FaceType::kQuad4;
  std::array<int, 8> nodes{-1, -1, -1, -1, -1, -1, -1, -1};
  int count = 0;  ///< 4, 8, 3 or 6
  [[nodiscard]] const int* begin() const { return nodes.data(); }
  [[nodiscard]] const int* end() const { return nodes.data() + count; }
  [[nodiscard]] int operator[](int i) const { return nodes[static_cast<std::size_t>(i)]; }
  [[nodiscard]] int corner_count() const {
    return type == FaceType::kQuad4 || type == FaceType::kQuad8 ? 4 : 3;
  }
  [[nodiscard]] bool quadratic() const { return type == FaceType::kQuad8 || type == FaceType::kTri6; }
};

/// Segments of a surface, indexed locally: node i of the surface is SolidMesh node mesh_nodes[i].
///
/// Faces (SPEC 9). The paper's nearest-node search pairs with `segments`, the quadrilaterals of C3D8* and
/// C3D20/C3D20R elements by their 4 corners (SPEC 7); the surface search counts every face: the segments,
/// then `extra_faces`. A quadratic face (C3D20/C3D20R and C3D15 quadrilaterals: quad8; C3D10 and C3D15
/// triangles: tri6) keeps its corners in `segments` / `extra_faces` and its mid-side nodes beside them, in
/// `segment_midsides` / `extra_face_midsides`: face_corners stays corners-only (what the paper's search, the
/// node normals of Eq 26, the adjacency and the edge keys of the surface search use), face_nodes gives all of
/// a face's nodes in SPEC 9's order. The surface's nodes are every node of its faces, mid-side nodes included
/// (in increasing id like the rest); a mid-side node belongs to no segment (segments_of is empty), so the
/// nearest-node search, which takes its nearest node among the nodes of segments, never sees one.
struct SurfaceMesh {
  std::vector<int> mesh_nodes;               ///< SolidMesh node index of each surface node, in increasing id
  std::vector<long> node_ids;                ///< deck id of each surface node (increasing)
  std::vector<Vec3> positions;               ///< position of each surface node
  std::vector<std::array<int, 4>> segments;  ///< surface node indices A, B, C, D; (B-A) x (D-A) outward
  std::vector<ElementFace> segment_faces;    ///< the element face of each segment
  std::vector<long> segment_element_ids;     ///< the deck id of each segment's element (SPEC 9's tie rule)
  /// Mid-side nodes of the segments: empty when no segment is quadratic, else one entry per segment: the
  /// surface node indices of the mid-side nodes of its edges A-B, B-C, C-D, D-A (C3D20/C3D20R faces), or four
  /// -1 (a linear segment). Code that copies segments must copy these alongside (or leave both lists
  /// consistent).
  std::vector<std::array<int, 4>> segment_midsides;
  /// The faces the paper's search does not pair with but SPEC 9's surface search counts: the triangles of
  /// C3D4, C3D10, C3D6 and C3D15 elements and the quadrilaterals of C3D6 and C3D15 (and of hexahedra of types
  /// that are not SPEC 7's: C3D8H, C3D20RH, ...), by their corners, outward ((B-A) x (C-A), resp. (B-A) x
  /// (D-A), points out of the element), surface node indices; a triangle's fourth entry is -1. They are still
  /// counted in skipped_faces (they are not segments).
  std::vector<std::array<int, 4>> extra_faces;
  std::vector<ElementFace> extra_face_faces;  ///< the element face of each extra face
  std::vector<long> extra_face_element_ids;   ///< the deck id of its element
  /// Mid-side nodes of the extra faces, as segment_midsides: empty when none is quadratic, else one entry per
  /// extra face (edges corner 1-2, 2-3, 3-4 or 3-1, 4-1; -1 where there is none).
  std::vector<std::array<int, 4>> extra_face_midsides;
  std::vector<int> adjacency_offsets;  ///< segments of node i: adjacency[offsets[i] .. offsets[i+1])
  std::vector<int> adjacency;          ///< segment indices, increasing, for each node in turn
  /// Faces that gave no segment, by kind: "C3D6 triangle", "C3D6 quadrilateral", "C3D4 triangle",
  /// "<TYPE> face" (a type without a face table), and the collapsed faces of build_surface_mesh: "<TYPE> face
  /// collapsed to a triangle" and "... to a flat triangle" (extra faces), "... to a line", "... to a point"
  /// and "<TYPE> face collapsed, not a triangle" (no face of either search).
  std::map<std::string, int> skipped_faces;
  /// The nodes of the faces that stand for another node of a collapsed face (build_surface_mesh): {SolidMesh
  /// index of the node, SolidMesh index of the node that stands for it, a surface node}, in increasing id of
  /// the first. They are not surface nodes; the faces use the second.
  std::vector<std::array<int, 2>> merged_nodes;
  int repeated_faces = 0;    ///< faces listed more than once (kept once)
  int inside_out_faces = 0;  ///< faces whose element is numbered inside out (see outward_quad_corners)

  [[nodiscard]] std::span<const int> segments_of(int node) const {
    const auto n = static_cast<std::size_t>(node);
    return {adjacency.data() + adjacency_offsets[n],
            static_cast<std::size_t>(adjacency_offsets[n + 1] - adjacency_offsets[n])};
  }
  [[nodiscard]] int node_count() const { return static_cast<int>(node_ids.size()); }
  /// Every face of the surface search: the segments, then the extra faces (index segments.size() + i).
  [[nodiscard]] int face_count() const { return static_cast<int>(segments.size() + extra_faces.size()); }
  /// Face f's corners (4 for a quadrilateral, 3 for a triangle) in surface node indices, outward order.
  [[nodiscard]] std::span<const int> face_corners(int f) const {
    const auto u = static_cast<std::size_t>(f);
    if (u < segments.size()) return {segments[u].data(), 4};
    const auto& e = extra_faces[u - segments.size()];
    return {e.data(), e[3] < 0 ? 3u : 4u};
  }
  /// Face f's type and all its nodes, corners then mid-side nodes (SPEC 9's order).
  [[nodiscard]] FaceNodes face_nodes(int f) const;
  /// face_nodes(f).type, without copying the nodes (the searches ask it per slave point and face).
  [[nodiscard]] FaceType face_type(int f) const {
    const auto u = static_cast<std::size_t>(f);
    const bool segment = u < segments.size();
    const bool quad = segment || extra_faces[u - segments.size()][3] >= 0;
    const std::vector<std::array<int, 4>>& mids = segment ? segment_midsides : extra_face_midsides;
    const bool curved = !mids.empty() && mids[segment ? u : u - segments.size()][0] >= 0;
    return curved ? (quad ? FaceType::kQuad8 : FaceType::kTri6) : (quad ? FaceType::kQuad4 : FaceType::kTri3);
  }
  /// True when the mid-side lists are consistent with the faces (each empty or one entry per face).
  [[nodiscard]] bool midsides_consistent() const {
    return (segment_midsides.empty() || segment_midsides.size() == segments.size()) &&
           (extra_face_midsides.empty() || extra_face_midsides.size() == extra_faces.size());
  }
  [[nodiscard]] long face_element_id(int f) const {
    const auto u = static_cast<std::size_t>(f);
    return u < segments.size() ? segment_element_ids[u] : extra_face_element_ids[u - segments.size()];
  }
  [[nodiscard]] const ElementFace& face_of(int f) const {
    const auto u = static_cast<std::size_t>(f);
    return u < segments.size() ? segment_faces[u] : extra_face_faces[u - segments.size()];
  }
};

/// The surface made of `faces`: each face of an element type with segment faces (ElementType) and four
/// distinct corners becomes one segment (outward_quad_corners), in the order of `faces`, repeats dropped;
/// every other face is counted in skipped_faces, and, when its element is a linear or a quadratic C3D8/C3D20,
/// C3D6/C3D15 or C3D4/C3D10, becomes an extra face if it has an area (below). A face of a quadratic element
/// (20, 15 or 10 nodes) has its mid-side nodes (element_type.hpp's tables) in segment_midsides /
/// extra_face_midsides. The surface's nodes are every node of its faces. InvalidArgument for an element index
/// or face number out of range.
///
/// Collapsed faces. Two nodes of a face coincide when they are one node (a repeated id: `1,2,3,3,5,6,7,7`) or
/// no coordinate of theirs differs by more than the coincidence tolerance: 1e-9 of their element's size (the
/// largest coordinate difference between its corner nodes), or 16 units in the last place of the element's
/// largest coordinate, whichever is larger (coordinate differences, not distances: nothing is squared, so a
/// deck at any scale the searches take collapses the same faces). The element's size, not the face's: a face
/// collapsed to a point has no size of its own; not the model's: a graded mesh has real edges far below its
/// size. 1e-9 lies above the 1e-10 of the longest node distance below which the projections call a face
/// degenerate (geometry::is_degenerate_segment), so no face is left that the search would refuse for a short
/// edge, and moves no point by more than 2e-9 element sizes. Judged on the deck's coordinates
/// (SolidMesh::deck_position), not on a history's: every increment has the same faces. Where two corners of a
/// face coincide, its coincident nodes are one node of the surface, the lowest id standing for the others
/// (merged_nodes) on every face of the surface, so that the faces around the collapsed one keep their shared
/// edges. Then, by its nodes (skipped_faces's kinds):
///  - every node (mid-side nodes too) within the tolerance of a point or of a line: no area, no face of
///    either search ("to a point", "to a line");
///  - a quadrilateral with one edge collapsed (A = B, ...): a triangle of its three corners, in the face's
///    outward order ("to a triangle"): tri3, or for a quad8 the tri6 of the other three edges when the
///    collapsed edge's mid-side node is on its corners and the six nodes are distinct (the same three edges
///    as the collapsed quad8; its interior is the quadratic triangle's); any other quad8 the flat tri3 of its
///    corners ("to a flat triangle");
///  - anything else (a diagonal collapsed: the face folds onto itself; a triangle with two corners one but
///    curved edges): skipped ("collapsed, not a triangle").
/// A triangle made so is an extra face, never a segment: the paper's search (SPEC 7) pairs quadrilaterals.
[[nodiscard]] SurfaceMesh build_surface_mesh(const SolidMesh& mesh, std::span<const ElementFace> faces);

/// Sets surface.adjacency_offsets and adjacency (compressed rows: the segments at each node, increasing) from
/// surface.segments, over its node_ids.size() nodes; build_surface_mesh calls it, and so does any code that
/// makes a SurfaceMesh of its own.
void set_adjacency(SurfaceMesh& surface);

/// Unit node normal at every surface node (paper Eq 26, SPEC 3): the normalised sum of the unit corner
/// normals (next - X) x (prev - X) of the segments sharing the node. A corner whose cross product is at
/// most 1e-12 |next - X| |prev - X| (collapsed) adds nothing; a node left without a direction (every corner
/// collapsed, or the corner normals cancel: |sum| <= 1e-12 per corner) gets the zero vector, which the
/// Gregory projection reports as degenerate. A node of no segment (a mid-side node, a node of extra faces
/// only) gets the zero vector too: no Gregory patch uses it.
[[nodiscard]] std::vector<Vec3> node_normals(const SurfaceMesh& surface);
/// The same for the first normals.size() nodes, written into `normals` (no allocation: a surface moved to a
/// new state, history::RunStates). InvalidArgument if `normals` is longer than the surface has nodes.
void node_normals(const SurfaceMesh& surface, std::span<Vec3> normals);

}  // namespace contactnn::mesh
