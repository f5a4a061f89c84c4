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

/// Segments of a surface, indexed locally: node i of the surface is SolidMesh node mesh_nodes[i].
struct SurfaceMesh {
  std::vector<int> mesh_nodes;             ///< SolidMesh node index of each surface node, in increasing id
  std::vector<long> node_ids;              ///< deck id of each surface node (increasing)
  std::vector<Vec3> positions;             ///< position of each surface node
  std::vector<std::array<int, 4>> segments;  ///< surface node indices A, B, C, D; (B-A) x (D-A) outward
  std::vector<ElementFace> segment_faces;  ///< the element face of each segment
  std::vector<long> segment_element_ids;   ///< the deck id of each segment's element (SPEC 9's tie rule)
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
