#include "mesh/surface_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>

#include "core/error.hpp"

namespace contactnn::mesh {

namespace {

// A corner whose cross product is this small relative to its edges has no direction (as in
// geometry::corner_normal); unit corner normals summing to less than this per corner cancel.
constexpr double kMinCornerSine = 1e-12;
constexpr double kMinSumPerCorner = 1e-12;
// Two nodes of a face coincide within this fraction of their element's size, or this many units in the last
// place of its largest coordinate (the header's "Collapsed faces").
constexpr double kCoincidentRelative = 1e-9;
constexpr double kCoincidentUlps = 16.0;

}  // namespace

namespace {

/// A face's corners in outward order as 0-based indices into its element's node list (then -1 for a
/// triangle), and whether the element is numbered inside out (the manual's own order is then the outward
/// one).
struct OutwardCorners {
  std::array<int, 4> local{-1, -1, -1, -1};
  std::size_t count = 0;
  bool inside_out = false;
};

OutwardCorners outward_local_corners(const SolidMesh& mesh, ElementFace face) {
  const ElementType& type = mesh.element_type(face.element);
  const std::span<const int> corners = face_corner_indices(type.shape, face.face);
  const std::span<const int> nodes = mesh.element_nodes(face.element);
  const auto at = [&](int local) -> const Vec3& {
    return mesh.position(nodes[static_cast<std::size_t>(local)]);
  };
  Vec3 element_centroid = Vec3::Zero();
  const int n_corners = corner_node_count(type.shape);
  for (int i = 0; i < n_corners; ++i) element_centroid += at(i);
  element_centroid /= n_corners;
  OutwardCorners out;
  out.count = corners.size();
  if (corners.size() == 4) {
    // The manuals list each face clockwise seen from outside (its right-hand normal points into the
    // element), so the outward order is the reverse. The centroid test catches elements numbered the
    // other way round; the diagonals' cross product is the face's mean normal even on a warped face.
    const std::array<int, 4> manual = {corners[0], corners[1], corners[2], corners[3]};
    const std::array<int, 4> reversed = {manual[0], manual[3], manual[2], manual[1]};
    const Vec3 face_centroid = 0.25 * (at(manual[0]) + at(manual[1]) + at(manual[2]) + at(manual[3]));
    const Vec3 normal = (at(reversed[2]) - at(reversed[0])).cross(at(reversed[3]) - at(reversed[1]));
    out.inside_out = normal.dot(face_centroid - element_centroid) < 0.0;
    out.local = out.inside_out ? manual : reversed;
  } else if (corners.size() == 3) {
    const std::array<int, 3> manual = {corners[0], corners[1], corners[2]};
    const Vec3 face_centroid = (at(manual[0]) + at(manual[1]) + at(manual[2])) / 3.0;
    const Vec3 normal =
        (at(manual[2]) - at(manual[0])).cross(at(manual[1]) - at(manual[0]));  // reversed order's
    out.inside_out = normal.dot(face_centroid - element_centroid) < 0.0;
    out.local = out.inside_out ? std::array<int, 4>{manual[0], manual[1], manual[2], -1}
                               : std::array<int, 4>{manual[0], manual[2], manual[1], -1};
  }
  return out;
}

std::array<int, 4> node_indices(const SolidMesh& mesh, int element, const std::array<int, 4>& local) {
  const std::span<const int> nodes = mesh.element_nodes(element);
  std::array<int, 4> out{-1, -1, -1, -1};
  for (std::size_t k = 0; k < 4; ++k) out[k] = local[k] < 0 ? -1 : nodes[static_cast<std::size_t>(local[k])];
  return out;
}

}  // namespace

std::array<int, 4> outward_quad_corners(const SolidMesh& mesh, ElementFace face) {
  CONTACTNN_REQUIRE(face.element >= 0 && face.element < mesh.element_count(),
                    "element index " << face.element << " outside [0, " << mesh.element_count() << ")");
  const ElementType& type = mesh.element_type(face.element);
  CONTACTNN_REQUIRE(face_corner_indices(type.shape, face.face).size() == 4,
                    "element " << mesh.element_id(face.element) << " (" << type.name
                               << ") has no quadrilateral face S" << face.face);
  return node_indices(mesh, face.element, outward_local_corners(mesh, face).local);
}

/// The 3 corners of a triangular face, outward ((B - A) x (C - A) points out of the element: the manual's
/// order reversed, unless the element's centroid says the element is numbered inside out), then -1.
std::array<int, 4> outward_triangle_corners(const SolidMesh& mesh, ElementFace face) {
  return node_indices(mesh, face.element, outward_local_corners(mesh, face).local);
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

/// The mid-side nodes of the edges of a face whose corners, in outward order, are `local` (0-based indices
/// into the element's node list, `count` of them), as indices into that list, for a quadratic element; four
/// -1 otherwise. By position in the element, not by node: a collapsed face repeats a corner's node.
std::array<int, 4> local_midsides(const SolidMesh& mesh, int element, const std::array<int, 4>& local,
                                  std::size_t count) {
  std::array<int, 4> mids{-1, -1, -1, -1};
  const ElementType& type = mesh.element_type(element);
  if (type.node_count != quadratic_node_count(type.shape)) return mids;
  for (std::size_t k = 0; k < count; ++k) {
    const int m = midside_node_index(type.shape, local[k], local[(k + 1) % count]);
    CONTACTNN_REQUIRE(m >= 0, "element " << mesh.element_id(element) << " (" << type.name
                                         << "): no mid-side node between face corners");
    mids[k] = m;
  }
  return mids;
}

/// A face of a known element type before coincident nodes are merged: SolidMesh node indices.
struct FaceDraft {
  ElementFace face;
  std::array<int, 4> corners{-1, -1, -1, -1};  ///< outward order
  std::array<int, 4> mids{-1, -1, -1, -1};     ///< of the edges corner 1-2, 2-3, ...; -1 for a linear face
  std::size_t count = 0;                       ///< corners: 3 or 4
  bool inside_out = false;
  bool collapsed = false;  ///< two of its corners coincide
  double tolerance = 0.0;  ///< the coincidence tolerance of its element (coincidence_tolerance)
  [[nodiscard]] std::size_t node_count() const { return mids[0] >= 0 ? 2 * count : count; }
  [[nodiscard]] int node(std::size_t i) const { return i < count ? corners[i] : mids[i - count]; }
};

/// Sets of coincident nodes (union-find over SolidMesh indices); each set stands for its lowest deck id.
class CoincidentNodes {
 public:
  explicit CoincidentNodes(const SolidMesh& mesh) : mesh_(mesh) {}
  int representative(int n) {
    if (parent_.empty()) return n;  // nothing joined (no collapsed face): no look-up
    for (auto it = parent_.find(n); it != parent_.end(); it = parent_.find(n)) n = it->second;
    return n;
  }
  /// The root of each set is its lowest deck id, so representative() is that node.
  void join(int a, int b) {
    a = representative(a);
    b = representative(b);
    if (a == b) return;
    if (mesh_.node_id(b) < mesh_.node_id(a)) std::swap(a, b);
    parent_[b] = a;
  }

 private:
  const SolidMesh& mesh_;
  std::unordered_map<int, int> parent_;  ///< the joined nodes only (a large mesh has few collapsed faces)
};

/// What a face collapsed by coincident nodes is (SurfaceMesh::skipped_faces's kinds).
enum class Collapse { kNone, kTriangle, kFlatTriangle, kLine, kPoint, kNoTriangle };

std::string_view collapse_kind(Collapse c) {
  switch (c) {
    case Collapse::kTriangle: return " face collapsed to a triangle";
    case Collapse::kFlatTriangle: return " face collapsed to a flat triangle";
    case Collapse::kLine: return " face collapsed to a line";
    case Collapse::kPoint: return " face collapsed to a point";
    case Collapse::kNoTriangle: return " face collapsed, not a triangle";
    case Collapse::kNone: break;
  }
  return "";
}

/// How far apart two points are for the coincidence test: their largest coordinate difference (no square: no
/// overflow or underflow at any scale the searches take).
double apart(const Vec3& a, const Vec3& b) { return (a - b).cwiseAbs().maxCoeff(); }

/// The coincidence tolerance of an element's faces (build_surface_mesh's "Collapsed faces"):
/// kCoincidentRelative of the largest coordinate difference between its corner nodes, or kCoincidentUlps
/// units in the last place of its largest coordinate, in the deck's coordinates.
double coincidence_tolerance(const SolidMesh& mesh, int element) {
  const std::span<const int> nodes = mesh.element_nodes(element);
  const auto corners =
      std::min(nodes.size(), static_cast<std::size_t>(corner_node_count(mesh.element_type(element).shape)));
  // The largest coordinate difference between two corners is the bounding box's largest side.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t i = 0; i < corners; ++i) {
    lo = lo.cwiseMin(mesh.deck_position(nodes[i]));
    hi = hi.cwiseMax(mesh.deck_position(nodes[i]));
  }
  if (corners == 0) return 0.0;
  const double size = (hi - lo).maxCoeff();
  const double largest = std::max(hi.cwiseAbs().maxCoeff(), lo.cwiseAbs().maxCoeff());
  return std::max(kCoincidentRelative * size,
                  kCoincidentUlps * std::numeric_limits<double>::epsilon() * largest);
}

/// Face `d` with its nodes replaced by their sets' representatives: what it is (kNone: a face of its own
/// type), and for a triangle its corners and mid-side nodes (SolidMesh indices) written into `corners` and
/// `mids`.
Collapse classify(const SolidMesh& mesh, CoincidentNodes& coincident, const FaceDraft& d,
                  std::array<int, 4>& corners, std::array<int, 4>& mids) {
  std::array<int, 4> c{-1, -1, -1, -1}, m{-1, -1, -1, -1};
  for (std::size_t k = 0; k < d.count; ++k) {
    c[k] = coincident.representative(d.corners[k]);
    m[k] = d.mids[k] < 0 ? -1 : coincident.representative(d.mids[k]);
  }
  corners = c;
  mids = m;
  std::array<int, 4> sorted = c;
  std::sort(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(d.count));
  const auto distinct = static_cast<std::size_t>(
      std::unique(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(d.count)) - sorted.begin());
  if (distinct == d.count && !d.collapsed) return Collapse::kNone;

  // No area: every node (mid-side nodes too: a quadratic face lies in their affine hull) within the tolerance
  // of a point or of the line through the two farthest.
  const std::size_t n = d.node_count();
  double farthest = -1.0;
  std::size_t p = 0, q = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const double distance = apart(mesh.deck_position(d.node(i)), mesh.deck_position(d.node(j)));
      if (distance > farthest) {
        farthest = distance;
        p = i;
        q = j;
      }
    }
  }
  if (!(farthest > d.tolerance)) return Collapse::kPoint;
  const Vec3 a = mesh.deck_position(d.node(p));
  Vec3 direction = (mesh.deck_position(d.node(q)) - a) / farthest;  // largest coordinate 1: its norm is safe
  direction /= direction.norm();
  bool on_line = true;
  for (std::size_t i = 0; i < n && on_line; ++i) {
    on_line = !((mesh.deck_position(d.node(i)) - a).cross(direction).cwiseAbs().maxCoeff() > d.tolerance);
  }
  if (on_line) return Collapse::kLine;
  if (distinct == d.count) return Collapse::kNone;
  if (d.count != 4 || distinct != 3) return Collapse::kNoTriangle;
  // One edge collapsed to a point (A = B, B = C, ...), not a diagonal (A = C: the face folds onto itself).
  std::size_t edge = 4;
  for (std::size_t k = 0; k < 4; ++k) {
    if (c[k] == c[(k + 1) % 4]) edge = k;
  }
  if (edge == 4) return Collapse::kNoTriangle;
  const auto at = [&](std::size_t k) { return k % 4; };
  corners = {c[edge], c[at(edge + 2)], c[at(edge + 3)], -1};
  if (m[0] < 0) return Collapse::kTriangle;
  // The 6-node triangle of the other three edges, when the collapsed edge's mid-side node is on its corners
  // and the six nodes are distinct; else the flat triangle of the corners.
  mids = {m[at(edge + 1)], m[at(edge + 2)], m[at(edge + 3)], -1};
  std::array<int, 6> six = {corners[0], corners[1], corners[2], mids[0], mids[1], mids[2]};
  std::sort(six.begin(), six.end());
  if (m[edge] == c[edge] && std::adjacent_find(six.begin(), six.end()) == six.end())
    return Collapse::kTriangle;
  mids = {-1, -1, -1, -1};
  return Collapse::kFlatTriangle;
}

/// A face of a known type by its nodes, or nullopt for a face build_surface_mesh counts and skips (a repeated
/// face, an element type it does not know).
std::optional<FaceDraft> draft_face(const SolidMesh& mesh, const ElementFace& face, SurfaceMesh& surface,
                                    std::set<std::pair<int, int>>& seen) {
  CONTACTNN_REQUIRE(face.element >= 0 && face.element < mesh.element_count(),
                    "element index " << face.element << " outside [0, " << mesh.element_count() << ")");
  const ElementType& type = mesh.element_type(face.element);
  CONTACTNN_REQUIRE(
      type.face_count == 0 || (face.face >= 1 && face.face <= type.face_count),
      "element " << mesh.element_id(face.element) << " (" << type.name << ") has no face S" << face.face);
  if (!seen.emplace(face.element, face.face).second) {
    ++surface.repeated_faces;
    return std::nullopt;
  }
  const std::size_t corners = face_corner_indices(type.shape, face.face).size();
  // Linear and quadratic hexahedra, wedges and tetrahedra; faces of other types are skipped.
  const bool known =
      type.node_count == corner_node_count(type.shape) || type.node_count == quadratic_node_count(type.shape);
  if (!known || (corners != 3 && corners != 4)) {
    const char* kind = corners == 3 ? " triangle" : corners == 4 ? " quadrilateral" : " face";
    ++surface.skipped_faces[type.name + kind];
    return std::nullopt;
  }
  FaceDraft d;
  d.face = face;
  const OutwardCorners outward = outward_local_corners(mesh, face);
  d.count = outward.count;
  d.inside_out = outward.inside_out;
  d.corners = node_indices(mesh, face.element, outward.local);
  d.mids = node_indices(mesh, face.element, local_midsides(mesh, face.element, outward.local, d.count));
  d.tolerance = coincidence_tolerance(mesh, face.element);
  return d;
}

/// Joins the nodes that coincide within a collapsed face (two corners within the tolerance, deck
/// coordinates), and appends each joined pair's nodes to `joined`.
void join_coincident_nodes(const SolidMesh& mesh, FaceDraft& d, CoincidentNodes& coincident,
                           std::vector<int>& joined) {
  const auto close = [&](std::size_t i, std::size_t j) {
    return !(apart(mesh.deck_position(d.node(i)), mesh.deck_position(d.node(j))) > d.tolerance);
  };
  for (std::size_t i = 0; i < d.count; ++i) {
    for (std::size_t j = i + 1; j < d.count; ++j) d.collapsed = d.collapsed || close(i, j);
  }
  if (!d.collapsed) return;
  for (std::size_t i = 0; i < d.node_count(); ++i) {
    for (std::size_t j = i + 1; j < d.node_count(); ++j) {
      if (!close(i, j) || d.node(i) == d.node(j)) continue;
      coincident.join(d.node(i), d.node(j));
      joined.push_back(d.node(i));
      joined.push_back(d.node(j));
    }
  }
}

/// The surface's faces in SolidMesh node indices (-1: none), before the surface numbers its nodes.
struct FaceLists {
  std::vector<std::array<int, 4>> segments, segment_mids, extra, extra_mids;
};

/// Each face by its representatives: a segment, an extra face of its own type or a triangle, or skipped.
FaceLists sort_faces(const SolidMesh& mesh, CoincidentNodes& coincident, std::span<const FaceDraft> drafts,
                     SurfaceMesh& surface) {
  FaceLists lists;
  for (const FaceDraft& d : drafts) {
    const ElementType& type = mesh.element_type(d.face.element);
    std::array<int, 4> corners{}, mids{};
    const Collapse collapse = classify(mesh, coincident, d, corners, mids);
    if (collapse != Collapse::kNone) {
      ++surface.skipped_faces[type.name + std::string(collapse_kind(collapse))];
      if (collapse != Collapse::kTriangle && collapse != Collapse::kFlatTriangle) continue;
    } else if (type.has_segment_faces) {
      if (d.inside_out) ++surface.inside_out_faces;
      lists.segments.push_back(corners);
      lists.segment_mids.push_back(mids);
      surface.segment_faces.push_back(d.face);
      surface.segment_element_ids.push_back(mesh.element_id(d.face.element));
      continue;
    } else {
      // Wedges, tetrahedra (and hexahedra of other types): faces of the surface search (SPEC 9), not
      // segments.
      ++surface.skipped_faces[type.name + (d.count == 3 ? " triangle" : " quadrilateral")];
    }
    lists.extra.push_back(corners);
    lists.extra_mids.push_back(mids);
    surface.extra_face_faces.push_back(d.face);
    surface.extra_face_element_ids.push_back(mesh.element_id(d.face.element));
  }
  return lists;
}

/// The surface's nodes (corners and mid-side nodes) in increasing deck id, so every later loop over them is
/// in a reproducible order: mesh_nodes, node_ids, positions. Returns each SolidMesh node's surface index (-1:
/// none).
std::vector<int> number_surface_nodes(const SolidMesh& mesh, const FaceLists& lists, SurfaceMesh& surface) {
  for (const auto* list : {&lists.segments, &lists.segment_mids, &lists.extra, &lists.extra_mids}) {
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
  return local;
}

/// The faces in surface node indices; the mid-side lists stay empty unless some face is quadratic, so a
/// linear surface looks as it always did.
void set_local_faces(const FaceLists& lists, const std::vector<int>& local, SurfaceMesh& surface) {
  const auto to_local = [&](const std::array<int, 4>& f) {
    std::array<int, 4> out{-1, -1, -1, -1};
    for (std::size_t k = 0; k < 4; ++k) out[k] = f[k] < 0 ? -1 : local[static_cast<std::size_t>(f[k])];
    return out;
  };
  const auto quadratic = [](const std::vector<std::array<int, 4>>& mids) {
    return std::any_of(mids.begin(), mids.end(), [](const std::array<int, 4>& m) { return m[0] >= 0; });
  };
  surface.segments.reserve(lists.segments.size());
  for (const auto& quad : lists.segments) surface.segments.push_back(to_local(quad));
  for (const auto& f : lists.extra) surface.extra_faces.push_back(to_local(f));
  if (quadratic(lists.segment_mids)) {
    for (const auto& m : lists.segment_mids) surface.segment_midsides.push_back(to_local(m));
  }
  if (quadratic(lists.extra_mids)) {
    for (const auto& m : lists.extra_mids) surface.extra_face_midsides.push_back(to_local(m));
  }
}

}  // namespace

// Count, prefix sum, fill in segment order so each row is increasing.
void set_adjacency(SurfaceMesh& surface) {
  const std::size_t n_nodes = surface.node_ids.size();
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
}

SurfaceMesh build_surface_mesh(const SolidMesh& mesh, std::span<const ElementFace> faces) {
  SurfaceMesh surface;
  // 1. The faces of known types, by their nodes; the nodes that coincide within a collapsed face joined.
  std::vector<FaceDraft> drafts;
  drafts.reserve(faces.size());
  std::set<std::pair<int, int>> seen;
  CoincidentNodes coincident(mesh);
  std::vector<int> joined;  // nodes of the joined pairs
  for (const ElementFace& face : faces) {
    std::optional<FaceDraft> d = draft_face(mesh, face, surface, seen);
    if (!d) continue;
    join_coincident_nodes(mesh, *d, coincident, joined);
    drafts.push_back(*d);
  }
  // 2. Each face by its representatives: a face of its own type, a triangle, or skipped.
  const FaceLists lists = sort_faces(mesh, coincident, drafts, surface);
  // 3. The surface's nodes, and the nodes that another stands for, where that one is a node of the surface.
  const std::vector<int> local = number_surface_nodes(mesh, lists, surface);
  std::sort(joined.begin(), joined.end(), [&](int a, int b) { return mesh.node_id(a) < mesh.node_id(b); });
  joined.erase(std::unique(joined.begin(), joined.end()), joined.end());
  for (int n : joined) {
    const int r = coincident.representative(n);
    if (r != n && local[static_cast<std::size_t>(r)] >= 0) surface.merged_nodes.push_back({n, r});
  }
  // 4. The faces in the surface's node indices, and the segments around each node.
  set_local_faces(lists, local, surface);
  set_adjacency(surface);
  return surface;
}

std::vector<Vec3> node_normals(const SurfaceMesh& surface) {
  std::vector<Vec3> normals(surface.positions.size(), Vec3::Zero());
  node_normals(surface, normals);
  return normals;
}

void node_normals(const SurfaceMesh& surface, std::span<Vec3> normals) {
  CONTACTNN_REQUIRE(normals.size() <= surface.positions.size(), normals.size()
                                                                    << " normals asked of a surface of "
                                                                    << surface.positions.size() << " nodes");
  for (int node = 0; node < static_cast<int>(normals.size()); ++node) {
    Vec3 sum = Vec3::Zero();
    int corners = 0;
    for (int s : surface.segments_of(node)) {
      const auto& quad = surface.segments[static_cast<std::size_t>(s)];
      for (int k = 0; k < 4; ++k) {
        if (quad[static_cast<std::size_t>(k)] != node) continue;
        const Vec3& x = surface.positions[static_cast<std::size_t>(node)];
        Vec3 to_next =
            surface.positions[static_cast<std::size_t>(quad[static_cast<std::size_t>((k + 1) % 4)])] - x;
        Vec3 to_prev =
            surface.positions[static_cast<std::size_t>(quad[static_cast<std::size_t>((k + 3) % 4)])] - x;
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
    normals[static_cast<std::size_t>(node)] =
        corners > 0 && length > kMinSumPerCorner * corners ? Vec3(sum / length) : Vec3::Zero();
  }
}

}  // namespace contactnn::mesh
