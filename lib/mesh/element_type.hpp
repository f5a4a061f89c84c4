// Solid element types of an Abaqus / CalculiX deck and their faces (SPEC 7).
//
// Face numbering is CalculiX's (= Abaqus's), node numbers 1-based as in the manuals:
//   hexahedron (C3D8*, C3D20*): S1 1-2-3-4, S2 5-8-7-6, S3 1-5-6-2, S4 2-6-7-3, S5 3-7-8-4, S6 4-8-5-1
//   wedge      (C3D6, C3D15):   S1 1-2-3, S2 4-6-5, S3 1-4-5-2, S4 2-5-6-3, S5 3-6-4-1
//   tetrahedron (C3D4, C3D10):  S1 1-2-3, S2 1-4-2, S3 2-4-3, S4 3-4-1
// Quadratic elements list their corner nodes first (C3D20: 1-8, C3D15: 1-6, C3D10: 1-4), so a face's
// corners are the same indices for the linear and the quadratic element; then one mid-side node per edge:
//   C3D20: 9 1-2, 10 2-3, 11 3-4, 12 4-1, 13 5-6, 14 6-7, 15 7-8, 16 8-5, 17 1-5, 18 2-6, 19 3-7, 20 4-8
//   C3D15: 7 1-2, 8 2-3, 9 3-1, 10 4-5, 11 5-6, 12 6-4, 13 1-4, 14 2-5, 15 3-6
//   C3D10: 5 1-2, 6 2-3, 7 3-1, 8 1-4, 9 2-4, 10 3-4
// (the manuals' figures; CalculiX's own face tables, e.g. ifaceq in gencontelem_n2f.f, list the same nodes).
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace contactnn::mesh {

enum class ElementShape { kHexahedron, kWedge, kTetrahedron, kOther };

/// What the reader and the surface builder need to know of an element type.
struct ElementType {
  std::string name;  ///< as in the deck, upper case ("C3D20R")
  ElementShape shape = ElementShape::kOther;
  int node_count = 0;  ///< nodes per element; 0 when the type is not known here
  int face_count = 0;  ///< faces S1..S<face_count>; 0 when not known
  /// True for the types whose quadrilateral faces become master segments: exactly C3D8, C3D8R, C3D8I,
  /// C3D20 and C3D20R (SPEC 7). Faces of every other type are skipped and counted.
  bool has_segment_faces = false;
};

/// The type called `name` (any case). Known node counts: C3D8* 8, C3D20* 20, C3D6 6, C3D15 15, C3D4 4,
/// C3D10* 10; any other name gives shape kOther and node_count 0 (the reader then relies on the
/// trailing-comma continuation rule). Never throws.
[[nodiscard]] ElementType element_type(std::string_view name);

/// 0-based indices into the element's node list of the corners of face `face` (1-based, S1 = 1), in the
/// manual's order above: 3 for a triangle, 4 for a quadrilateral. Empty when the shape is kOther or
/// `face` is not in 1..face_count.
[[nodiscard]] std::span<const int> face_corner_indices(ElementShape shape, int face);

/// Nodes of the quadratic element of `shape` (C3D20 20, C3D15 15, C3D10 10); 0 for kOther.
[[nodiscard]] int quadratic_node_count(ElementShape shape);

/// Corner nodes of an element of `shape` (8, 6, 4); 0 for kOther.
[[nodiscard]] int corner_node_count(ElementShape shape);

/// 0-based index into the quadratic element's node list of the mid-side node of the edge between corners
/// `a` and `b` (0-based, either order), as the header's table; -1 when a-b is not an edge of the shape.
[[nodiscard]] int midside_node_index(ElementShape shape, int a, int b);

}  // namespace contactnn::mesh
