// A surface of a solid mesh as quadrilateral segments oriented outward, with node adjacency and the node
// normals of paper Eq 26 (SPEC 3, last bullet; SPEC 7 "Master segments").
#pragma once

#include <array>
#include <map>
#include <span>
#include <string>
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

/// Segments of a surface, indexed locally: node i of the surface is SolidMesh node mesh_nodes[i].
struct SurfaceMesh {
  std::vector<int> mesh_nodes;             ///< SolidMesh node index of each surface node, in increasing id
  std::vector<long> node_ids;              ///< deck id of each surface node (increasing)
  std::vector<Vec3> positions;             ///< position of each surface node
  std::vector<std::array<int, 4>> segments;  ///< surface node indices A, B, C, D; (B-A) x (D-A) outward
  std::vector<ElementFace> segment_faces;  ///< the element face of each segment
  std::vector<long> segment_element_ids;   ///< the deck id of each segment's element (SPEC 9's tie rule)
  /// The faces the paper's search does not pair with but SPEC 9's surface search counts: the triangles of
  /// C3D4 and C3D6 elements and the quadrilaterals of C3D6, outward ((B-A) x (C-A), resp. (B-A) x (D-A), points
  /// out of the element), surface node indices; a triangle's fourth entry is -1. They are still counted in
  /// skipped_faces (they are not segments). Quadratic elements' faces other than C3D20's are not read yet.
  std::vector<std::array<int, 4>> extra_faces;
  std::vector<ElementFace> extra_face_faces;  ///< the element face of each extra face
  std::vector<long> extra_face_element_ids;   ///< the deck id of its element
  std::vector<int> adjacency_offsets;      ///< segments of node i: adjacency[offsets[i] .. offsets[i+1])
  std::vector<int> adjacency;              ///< segment indices, increasing, for each node in turn
  /// Faces that gave no segment, by kind: "C3D6 triangle", "C3D6 quadrilateral", "C3D4 triangle",
  /// "<TYPE> face" (a type without a face table), "<TYPE> collapsed face" (two corners are one node).
  std::map<std::string, int> skipped_faces;
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
/// distinct corner nodes becomes one segment (outward_quad_corners), in the order of `faces`, repeats
/// dropped; every other face is counted in skipped_faces. The surface's nodes are the segments' corners.
/// InvalidArgument for an element index or face number out of range.
[[nodiscard]] SurfaceMesh build_surface_mesh(const SolidMesh& mesh, std::span<const ElementFace> faces);

/// Unit node normal at every surface node (paper Eq 26, SPEC 3): the normalised sum of the unit corner
/// normals (next - X) x (prev - X) of the segments sharing the node. A corner whose cross product is at
/// most 1e-12 |next - X| |prev - X| (collapsed) adds nothing; a node left without a direction (every corner
/// collapsed, or the corner normals cancel: |sum| <= 1e-12 per corner) gets the zero vector, which the
/// Gregory projection reports as degenerate.
[[nodiscard]] std::vector<Vec3> node_normals(const SurfaceMesh& surface);

}  // namespace contactnn::mesh
