// Solid element types of an Abaqus / CalculiX deck and their faces (SPEC 7).
//
// Face numbering is CalculiX's (= Abaqus's), node numbers 1-based as in the manuals:
//   hexahedron (C3D8*, C3D20*): S1 1-2-3-4, S2 5-8-7-6, S3 1-5-6-2, S4 2-6-7-3, S5 3-7-8-4, S6 4-8-5-1
//   wedge      (C3D6, C3D15):   S1 1-2-3, S2 4-6-5, S3 1-4-5-2, S4 2-5-6-3, S5 3-6-4-1
//   tetrahedron (C3D4, C3D10):  S1 1-2-3, S2 1-4-2, S3 2-4-3, S4 3-4-1
// Quadratic elements list their corner nodes first (C3D20: 1-8, C3D15: 1-6, C3D10: 1-4), so a face's
// corners are the same indices for the linear and the quadratic element.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace contactnn::mesh {

enum class ElementShape { kHexahedron, kWedge, kTetrahedron, kOther };

/// What the reader and the surface builder need to know of an element type.
struct ElementType {
  std::string name;                         ///< as in the deck, upper case ("C3D20R")
  ElementShape shape = ElementShape::kOther;
  int node_count = 0;                       ///< nodes per element; 0 when the type is not known here
  int face_count = 0;                       ///< faces S1..S<face_count>; 0 when not known
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

}  // namespace contactnn::mesh
