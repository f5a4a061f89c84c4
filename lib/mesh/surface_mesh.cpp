#include "mesh/surface_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.hpp"

namespace contactnn::mesh {

namespace {

// A corner whose cross product is this small relative to its edges has no direction (as in
// geometry::corner_normal); unit corner normals summing to less than this per corner cancel.
constexpr double kMinCornerSine = 1e-12;
constexpr double kMinSumPerCorner = 1e-12;

}  // namespace

std::array<int, 4> outward_quad_corners(const SolidMesh& mesh, ElementFace face) {
  CONTACTNN_REQUIRE(face.element >= 0 && face.element < mesh.element_count(),
                    "element index " << face.element << " outside [0, " << mesh.element_count() << ")");
  const ElementType& type = mesh.element_type(face.element);
  const std::span<const int> corners = face_corner_indices(type.shape, face.face);
  CONTACTNN_REQUIRE(corners.size() == 4, "element " << mesh.element_id(face.element) << " (" << type.name
                                                    << ") has no quadrilateral face S" << face.face);
  const std::span<const int> nodes = mesh.element_nodes(face.element);
  const std::array<int, 4> manual = {nodes[static_cast<std::size_t>(corners[0])],
                                     nodes[static_cast<std::size_t>(corners[1])],
                                     nodes[static_cast<std::size_t>(corners[2])],
                                     nodes[static_cast<std::size_t>(corners[3])]};
  // The manuals list each face clockwise seen from outside (its right-hand normal points into the
  // element), so the outward order is the reverse. The centroid test catches elements numbered the
  // other way round; the diagonals' cross product is the face's mean normal even on a warped face.
  const std::array<int, 4> reversed = {manual[0], manual[3], manual[2], manual[1]};
  const auto at = [&](int n) -> const Vec3& { return mesh.position(n); };
  Vec3 element_centroid = Vec3::Zero();
  const int n_corners = corner_node_count(type.shape);
  for (int i = 0; i < n_corners; ++i) element_centroid += at(nodes[static_cast<std::size_t>(i)]);
  element_centroid /= n_corners;
  const Vec3 face_centroid = 0.25 * (at(manual[0]) + at(manual[1]) + at(manual[2]) + at(manual[3]));
  const Vec3 normal = (at(reversed[2]) - at(reversed[0])).cross(at(reversed[3]) - at(reversed[1]));
  return normal.dot(face_centroid - element_centroid) < 0.0 ? manual : reversed;
}

/// The 3 corners of a triangular face, outward ((B - A) x (C - A) points out of the element: the manual's
/// order reversed, unless the element's centroid says the element is numbered inside out), then -1.
std::array<int, 4> outward_triangle_corners(const SolidMesh& mesh, ElementFace face) {
  const ElementType& type = mesh.element_type(face.element);
  const std::span<const int> corners = face_corner_indices(type.shape, face.face);
  const std::span<const int> nodes = mesh.element_nodes(face.element);
  const std::array<int, 3> manual = {nodes[static_cast<std::size_t>(corners[0])],
                                     nodes[static_cast<std::size_t>(corners[1])],
                                     nodes[static_cast<std::size_t>(corners[2])]};
  const auto at = [&](int n) -> const Vec3& { return mesh.position(n); };
  Vec3 element_centroid = Vec3::Zero();
  const int n_corners = corner_node_count(type.shape);
  for (int i = 0; i < n_corners; ++i) element_centroid += at(nodes[static_cast<std::size_t>(i)]);
  element_centroid /= n_corners;
  const Vec3 face_centroid = (at(manual[0]) + at(manual[1]) + at(manual[2])) / 3.0;
  const Vec3 normal = (at(manual[2]) - at(manual[0])).cross(at(manual[1]) - at(manual[0]));  // reversed order's
  return normal.dot(face_centroid - element_centroid) < 0.0 ? std::array<int, 4>{manual[0], manual[1], manual[2], -1}
                                                            : std::array<int, 4>{manual[0], manual[2], manual[1], -1};
}

std::string_view to_string(FaceType type) {
  switch (type) {
    case FaceType::kQuad4: return "quad4";
    case FaceType::kQuad8: return "quad8";
    case FaceType::kTri3: return "tri3";
    case FaceType::kTri6: return "tri6";
  }
  return "quad4";
}

FaceNodes SurfaceMesh::face_nodes(int f) const {
  FaceNodes out;
  const std::span<const int> corners = face_corners(f);
  out.count = static_cast<int>(corners.size());
  std::copy(corners.begin(), corners.end(), out.nodes.begin());
  const auto u = static_cast<std::size_t>(f);
  const std::array<int, 4>* mids = nullptr;
  if (u < segments.size()) {
    if (!segment_midsides.empty()) mids = &segment_midsides[u];
  } else if (!extra_face_midsides.empty()) {
    mids = &extra_face_midsides[u - segments.size()];
  }
  const bool quad = corners.size() == 4;
  if (mids != nullptr && (*mids)[0] >= 0) {
    for (std::size_t k = 0; k < corners.size(); ++k) out.nodes[corners.size() + k] = (*mids)[k];
    out.count = 2 * out.count;
    out.type = quad ? FaceType::kQuad8 : FaceType::kTri6;
  } else {
    out.type = quad ? FaceType::kQuad4 : FaceType::kTri3;
  }
  return out;
}

namespace {

/// The mid-side nodes (SolidMesh indices) of the edges of a face whose corners, in outward order, are
/// `corners` (SolidMesh indices, `count` of them), for a quadratic element; four -1 otherwise.
std::array<int, 4> face_midsides(const SolidMesh& mesh, int element, const std::array<int, 4>& corners,
                                 std::size_t count) {
  std::array<int, 4> mids{-1, -1, -1, -1};
  const ElementType& type = mesh.element_type(element);
  if (type.node_count != quadratic_node_count(type.shape)) return mids;
  const std::span<const int> nodes = mesh.element_nodes(element);
  const int n_corners = corner_node_count(type.shape);
  const auto local = [&](int node) {
    for (int i = 0; i < n_corners; ++i) {
      if (nodes[static_cast<std::size_t>(i)] == node) return i;
    }
    return -1;
  };
  for (std::size_t k = 0; k < count; ++k) {
    const int m = midside_node_index(type.shape, local(corners[k]), local(corners[(k + 1) % count]));
    CONTACTNN_REQUIRE(m >= 0, "element " << mesh.element_id(element) << " (" << type.name
                                          << "): no mid-side node between face corners");
    mids[k] = nodes[static_cast<std::size_t>(m)];
  }
  return mids;
}

}  // namespace

SurfaceMesh build_surface_mesh(const SolidMesh& mesh, std::span<const ElementFace> faces) {
  SurfaceMesh surface;
  std::vector<std::array<int, 4>> segments, segment_mids;  // SolidMesh node indices for now
  std::vector<std::array<int, 4>> extra, extra_mids;       // likewise
  std::set<std::pair<int, int>> seen;
  for (const ElementFace& face : faces) {
    CONTACTNN_REQUIRE(face.element >= 0 && face.element < mesh.element_count(),
                      "element index " << face.element << " outside [0, " << mesh.element_count() << ")");
    const ElementType& type = mesh.element_type(face.element);
    CONTACTNN_REQUIRE(type.face_count == 0 || (face.face >= 1 && face.face <= type.face_count),
                      "element " << mesh.element_id(face.element) << " (" << type.name << ") has no face S"
                                 << face.face);
    if (!seen.emplace(face.element, face.face).second) {
      ++surface.repeated_faces;
      continue;
    }
    const std::size_t corners = face_corner_indices(type.shape, face.face).size();
    if (!type.has_segment_faces) {
      const char* kind = corners == 3 ? " triangle" : corners == 4 ? " quadrilateral" : " face";
      ++surface.skipped_faces[type.name + kind];
      // Linear and quadratic wedges, tetrahedra (and hexahedra of other types): faces of the surface search
      // (SPEC 9), not segments.
      const bool known = type.node_count == corner_node_count(type.shape) || type.node_count == quadratic_node_count(type.shape);
      if (known && (corners == 3 || corners == 4)) {
        std::array<int, 4> outward = corners == 4 ? outward_quad_corners(mesh, face) : outward_triangle_corners(mesh, face);
        std::array<int, 4> sorted = outward;
        std::sort(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(corners));
        if (std::adjacent_find(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(corners)) ==
            sorted.begin() + static_cast<std::ptrdiff_t>(corners)) {
          extra.push_back(outward);
          extra_mids.push_back(face_midsides(mesh, face.element, outward, corners));
          surface.extra_face_faces.push_back(face);
          surface.extra_face_element_ids.push_back(mesh.element_id(face.element));
        }
      }
      continue;
    }
    const std::array<int, 4> quad = outward_quad_corners(mesh, face);
    const std::array<int, 4> manual_order = [&] {
      const auto idx = face_corner_indices(type.shape, face.face);
      const auto nodes = mesh.element_nodes(face.element);
      return std::array<int, 4>{nodes[static_cast<std::size_t>(idx[0])], nodes[static_cast<std::size_t>(idx[1])],
                                nodes[static_cast<std::size_t>(idx[2])], nodes[static_cast<std::size_t>(idx[3])]};
    }();
    std::array<int, 4> sorted = quad;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      ++surface.skipped_faces[type.name + " collapsed face"];
      continue;
    }
    if (quad == manual_order) ++surface.inside_out_faces;
    segments.push_back(quad);
    segment_mids.push_back(face_midsides(mesh, face.element, quad, 4));
    surface.segment_faces.push_back(face);
    surface.segment_element_ids.push_back(mesh.element_id(face.element));
  }

  // Surface nodes (corners and mid-side nodes) in increasing deck id, so every later loop over them is in a
  // reproducible order.
  for (const auto* list : {&segments, &segment_mids, &extra, &extra_mids}) {
    for (const auto& f : *list) {
      for (int n : f) {
        if (n >= 0) surface.mesh_nodes.push_back(n);
      }
    }
  }
  std::sort(surface.mesh_nodes.begin(), surface.mesh_nodes.end(),
            [&](int a, int b) { return mesh.node_id(a) < mesh.node_id(b); });
  surface.mesh_nodes.erase(std::unique(surface.mesh_nodes.begin(), surface.mesh_nodes.end()),
                           surface.mesh_nodes.end());
  std::vector<int> local(static_cast<std::size_t>(mesh.node_count()), -1);
  for (std::size_t i = 0; i < surface.mesh_nodes.size(); ++i) {
    const int n = surface.mesh_nodes[i];
    local[static_cast<std::size_t>(n)] = static_cast<int>(i);
    surface.node_ids.push_back(mesh.node_id(n));
    surface.positions.push_back(mesh.position(n));
  }
  const auto to_local = [&](const std::array<int, 4>& f) {
    std::array<int, 4> out{-1, -1, -1, -1};
    for (std::size_t k = 0; k < 4; ++k) out[k] = f[k] < 0 ? -1 : local[static_cast<std::size_t>(f[k])];
    return out;
  };
  const auto quadratic = [](const std::vector<std::array<int, 4>>& mids) {
    return std::any_of(mids.begin(), mids.end(), [](const std::array<int, 4>& m) { return m[0] >= 0; });
  };
  surface.segments.reserve(segments.size());
  for (const auto& quad : segments) surface.segments.push_back(to_local(quad));
  for (const auto& f : extra) surface.extra_faces.push_back(to_local(f));
  // Empty unless some face is quadratic: a linear surface looks as it always did.
  if (quadratic(segment_mids)) {
    for (const auto& m : segment_mids) surface.segment_midsides.push_back(to_local(m));
  }
  if (quadratic(extra_mids)) {
    for (const auto& m : extra_mids) surface.extra_face_midsides.push_back(to_local(m));
  }

  // Adjacency (compressed rows): count, prefix sum, fill in segment order so each row is increasing.
  const std::size_t n_nodes = surface.mesh_nodes.size();
  surface.adjacency_offsets.assign(n_nodes + 1, 0);
  for (const auto& quad : surface.segments) {
    for (int n : quad) ++surface.adjacency_offsets[static_cast<std::size_t>(n) + 1];
  }
  for (std::size_t i = 0; i < n_nodes; ++i) surface.adjacency_offsets[i + 1] += surface.adjacency_offsets[i];
  surface.adjacency.resize(static_cast<std::size_t>(surface.adjacency_offsets[n_nodes]));
  std::vector<int> fill(surface.adjacency_offsets.begin(), surface.adjacency_offsets.end() - 1);
  for (std::size_t s = 0; s < surface.segments.size(); ++s) {
    for (int n : surface.segments[s]) {
      surface.adjacency[static_cast<std::size_t>(fill[static_cast<std::size_t>(n)]++)] = static_cast<int>(s);
    }
  }
  return surface;
}

std::vector<Vec3> node_normals(const SurfaceMesh& surface) {
  std::vector<Vec3> normals(surface.positions.size(), Vec3::Zero());
  for (int node = 0; node < surface.node_count(); ++node) {
    Vec3 sum = Vec3::Zero();
    int corners = 0;
    for (int s : surface.segments_of(node)) {
      const auto& quad = surface.segments[static_cast<std::size_t>(s)];
      for (int k = 0; k < 4; ++k) {
        if (quad[static_cast<std::size_t>(k)] != node) continue;
        const Vec3& x = surface.positions[static_cast<std::size_t>(node)];
        Vec3 to_next = surface.positions[static_cast<std::size_t>(quad[static_cast<std::size_t>((k + 1) % 4)])] - x;
        Vec3 to_prev = surface.positions[static_cast<std::size_t>(quad[static_cast<std::size_t>((k + 3) % 4)])] - x;
        // In units of the corner's size, a power of two (exact: the same bits wherever nothing under- or
        // overflowed): the cross product is a square of the size and vanished below 1e-154 (a deck scaled by
        // 1e-200 had no normals, and its Gregory patches none either).
        int exponent = 0;
        (void)std::frexp(std::max(to_next.cwiseAbs().maxCoeff(), to_prev.cwiseAbs().maxCoeff()), &exponent);
        const double unit = std::ldexp(1.0, exponent);
        if (std::isfinite(unit) && unit > 0.0) {
          to_next /= unit;
          to_prev /= unit;
        }
        const Vec3 cross = to_next.cross(to_prev);
        const double length = cross.norm();
        if (!(length > kMinCornerSine * to_next.norm() * to_prev.norm())) continue;
        sum += cross / length;
        ++corners;
      }
    }
    const double length = sum.norm();
    if (corners > 0 && length > kMinSumPerCorner * corners) normals[static_cast<std::size_t>(node)] = sum / length;
  }
  return normals;
}

}  // namespace contactnn::mesh
