// The surface search's per-state table of the master's faces (surface_search.cpp's FaceIndex): spheres,
// boxes, sizes, the faces at each node, prepared faces and certificates; built in parallel, kept between a
// tracker's states (SearchStorage), each face's entries kept where none of its nodes has moved.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "contact/bilinear_certificate.hpp"
#include "contact/curved_certificate.hpp"
#include "contact/face_grid.hpp"
#include "contact/face_slots.hpp"
#include "contact/node_faces.hpp"
#include "contact/surface_search.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::contact {

/// A triangle's (tri3, tri6) three edge planes: the unit normal m_e of edge e in the face's plane, pointing
/// out, and the largest m_e.P over the points whose convex hull holds the face. m_e.S - h_e is then a lower
/// bound on S's distance to the face (tight beside the edge, where a triangle's box, which is its cell's
/// box, is not: a slave node over one triangle of a cell is no longer a candidate of the other). A face
/// without planes (not a triangle, or a degenerate one) has h = +inf.
struct EdgePlanes {
  std::array<Vec3, 3> m;
  std::array<double, 3> h;
};

/// Everything the search needs of the faces, built per state (its buffers kept in a SearchStorage between
/// states): centres, bounding radii, sizes, adjacency, prepared faces.
struct FaceIndex {
  std::vector<Vec3> centres;
  std::vector<double> radii;         ///< bounding-sphere radius about the centre
  std::vector<Vec3> box_lo, box_hi;  ///< bounding box of the same points
  std::vector<double> sizes;         ///< longest corner distance
  /// The largest movement of a face's box (box_movement) since the kept index's state, rounded up; infinite
  /// where no index was kept (the first state, another unit or other faces).
  double box_drift = 0.0;
  /// Changes (a fresh stamp, never 0) wherever a face's box may have changed since the index it was kept
  /// from: an index of the same stamp holds the same boxes, bit for bit (FaceGrid::held).
  std::uint64_t generation = 0;
  /// The faces at each surface node (node_faces.hpp): a kept one where the connectivity is the same.
  std::shared_ptr<const NodeFaces> topology;
  /// The positions and normals (working units) the faces' entries were computed from, where the index is kept
  /// between states (SearchStorage): a face none of whose nodes has moved since keeps its entries.
  std::vector<Vec3> built_positions, built_normals;
  double built_unit = 0.0;
  /// 1 for a quad4 face on a bilinear facet that passes projection::closest_point_on_face's checks (finite,
  /// not degenerate, on its nodes relative to the first): its projections skip them
  /// (ProjectionOptions::face_checked; the same answers, computed once per face instead of once per slave).
  std::vector<std::uint8_t> checked;
  /// The certificates of the checked quad4 bilinear faces (lambda_floor 0 for every other face): their
  /// closest points in one Newton run where the certificate holds (NarrowPhase::kCertified).
  FaceSlots<BilinearCertificate> bilinear;  ///< every slot constructed by index_faces
  /// The tri3 faces prepared (projection::PreparedTriangle; every face's slot, where the surface has a tri3
  /// face and the search is certified): their closest points without rebuilding their edges per slave.
  FaceSlots<projection::PreparedTriangle> triangles;  ///< the tri3 faces' slots constructed
  /// Every face's EdgePlanes where the surface has a triangle and the search is certified (empty otherwise):
  /// a triangle's bound is also the distance beyond its edges' planes.
  std::vector<EdgePlanes> planes;
  /// The same for the curved faces: quad8, tri6 and Gregory patches (empty where the master has none or under
  /// kReference).
  CurvedCertificates curved;

  /// The faces left out for lying beyond the capture distance of the region the searcher is asked about
  /// (index_faces' `region`): neither bounded nor prepared, their boxes empty (listed in no grid cell).
  std::size_t left_out = 0;
  [[nodiscard]] std::span<const int> faces_at(int node) const { return topology->at(node); }
};

struct SearchStorage::Tables {
  FaceIndex index;  ///< the last state's, its buffers to be reused
  FaceGrid grid;    ///< a fresh search's grid (SurfaceSearcher's own, built again), its buffers to be reused
};

/// The index of `master`'s state (working units) with `normals` (Gregory) and `options`. `topology`: the
/// faces at each node, kept by the caller (SurfaceSearcher's); null: the recycled index's where it has the
/// master's connectivity, else built. `recycled`: a kept index whose buffers are reused and, with `keep` and
/// the same `unit`, whose entries are kept for every face none of whose nodes (nor, on Gregory patches,
/// normals) has moved since it was built (without `keep`, every entry is computed afresh: its memory alone
/// is reused); `keep`: record this state's positions for the next. `region` (not with `keep`): the box of
/// the points the searcher will be asked about (working units); every face whose bound lies beyond the
/// capture distance of it is left out (FaceIndex::left_out), its box empty; a Gregory patch's bound first
/// from its nodes alone (its control points computed only for the faces kept).
[[nodiscard]] FaceIndex index_faces(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                                    const SearchOptions& options, std::shared_ptr<const NodeFaces>* topology,
                                    FaceIndex&& recycled, double unit, bool keep,
                                    const PointBox* region = nullptr);

/// Face f's certificate, or null where it has none (NarrowPhase::kReference, or not a checked bilinear
/// quad4).
[[nodiscard]] inline const BilinearCertificate* certificate_of(const FaceIndex& index, int face) {
  if (index.bilinear.empty()) return nullptr;
  const BilinearCertificate& c = index.bilinear[static_cast<std::size_t>(face)];
  return c.lambda_floor > 0.0 ? &c : nullptr;
}

/// Face f's curved certificate, or null where it has none (kReference, not a quad8, tri6 or Gregory patch, or
/// no bound).
/// Prepared on its first use in the state (CurvedCertificates).
[[nodiscard]] const CurvedCertificate* curved_of(const FaceIndex& index, const mesh::SurfaceMesh& master,
                                                 std::span<const Vec3> normals, const SearchOptions& options,
                                                 int face);

}  // namespace contactnn::contact
