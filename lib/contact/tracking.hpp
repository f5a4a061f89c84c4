// Tracking: the surface search of a history, increment by increment, reusing what the previous increments
// found (SPEC 9's answers, exactly; only cheaper).
//
// The rule (a movement budget and a previous-point warm start, the bookkeeping contact codes use:
// OpenRadioss re-sorts its candidates only once a distance budget is spent; MOOSE and FrontISTR start from
// the previous point and face):
//  1. The broad phase (face_grid.hpp) lists each face by its box inflated by a margin m
//     (TrackingOptions::grid_margin_relative x the capture distance), and is kept from one increment to the
//     next while every face's box stays inside its inflated box at the build: a face within some reach of a
//     slave node is then still listed in the cells around it. Otherwise it is rebuilt (TrackingCounts::
//     grid_builds).
//  2. A node that had a face at the previous increment starts from it (SurfaceSearcher::nearest_fresh's
//     hint): that face's point, its distance bounding the faces the node gathers from the grid. A face with
//     a certificate that holds for the node (bilinear_certificate.hpp, curved_certificate.hpp) is projected
//     by one Newton run from the node's previous point on it (on a quadrilateral whose last two answers
//     were both on it, from twice the last point less the one before, clamped into the domain: a steady
//     motion's next point, one Newton step fewer; the certificate holds on the whole domain, so any start
//     gives its answer); every other face by the fresh search's
//     reference, and its nearest corner bounds the gathering. A warm start on a face without a certificate
//     could end on another stationary point than the face's nearest (a farther local minimum of a Gregory
//     patch around a slave node inside a closed body: issue 39), so none is made.
//  3. A node without one (the first increment, no point at the previous one, other slave ids or faces)
//     starts from a face listed in its grid cell, as a fresh search.
//  4. What a state computes of the master is kept for the next (SearchStorage, NodeFaces): the faces at each
//     node while the connectivity is the same; the faces' tables' memory (nothing is allocated per increment
//     once warm); and each face's entries (sphere, box, prepared face, certificate) where none of its nodes,
//     nor on a Gregory patch their normals, has moved: they are what would be computed again, bit for bit. A
//     state's work on the master is then in proportion to the part of it that moves.
//  5. Each node keeps the faces near it (NearFaces, surface_search.hpp): those whose box came within a
//     radius of the node, the node's reach then plus a budget of one grid cell, with each box's distance
//     then. The surface's drift is the largest
//     movement of a face's box from one state to the next (FaceIndex::box_drift), summed over the states.
//     While the node's movement since the list, plus the drift since, plus its reach stay within the radius,
//     the node's faces within reach are among the listed ones whose distance then, less that movement and
//     drift, is within reach: they are taken from the list (about one box tested per node), not gathered
//     from the grid's cells. Otherwise the list is made again from the grid, over the larger radius, at the
//     same query. Where more faces come within the radius than a list holds (five), the list keeps the
//     nearest and its radius shrinks to the nearest box it leaves out; where that is less than a tenth of a
//     cell beyond the reach, the node gathers its faces from the grid until its budget is spent. A state
//     whose boxes moved by more than 0.05 of a cell since the last uses no list (each would be made again at
//     every state): the grid gathers every node's faces.
// Then the scan as the fresh search's: the same faces, points and gaps (the tests and `replay` compare every
// increment with a fresh search and count the differences). A node costs its previous face, start and
// point, and its list (80 bytes).
//
// NarrowPhase::kReference keeps the tracker as it was before the grid (the search it is measured against):
// each node's list of the faces whose sphere came within capture + m at its build, valid while the node's
// movement plus the surface's drift (the largest movement of a face's sphere since) stays within m, and
// each list's faces pruned by their bounds less that movement.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "contact/face_grid.hpp"
#include "contact/surface_search.hpp"

namespace contactnn::contact {

struct TrackingOptions {
  /// The reference tracker's list margin m in units of the capture distance: larger lists that stay valid
  /// for longer.
  double margin_relative = 0.5;
  /// The grid's margin (rule 1) in units of the capture distance: a grid kept for longer, its cells holding
  /// more faces (at 0.5, twice the cost of a query on the large history).
  double grid_margin_relative = 0.1;
};

/// What one increment cost the tracker, node by node.
struct TrackingCounts {
  long fresh = 0;    ///< nodes searched without a previous face (the reference's: whose list was rebuilt)
  long tracked = 0;  ///< nodes that started from their previous face (the reference's: answered from a list)
  long warm = 0;     ///< nodes whose previous face was tried first (warm where it has a certificate)
  long list_faces = 0;   ///< faces gathered from the grid (the reference's: in the lists), over the nodes
  long grid_builds = 0;  ///< 1 where the broad phase was rebuilt at this increment (rule 1)
};

/// The surface search over a history. step() takes the states in increment order; the surface's faces and the
/// slave ids must stay the same from one step to the next (otherwise every node is searched fresh).
class SurfaceTracker {
 public:
  explicit SurfaceTracker(const SearchOptions& options, TrackingOptions tracking = {});

  /// The surface search of this state (surface_search's contract), by the rule above. Deterministic for any
  /// thread count. InvalidArgument as surface_search.
  [[nodiscard]] std::vector<NodeSegmentPair> step(const mesh::SurfaceMesh& master,
                                                  std::span<const Vec3> master_normals,
                                                  std::span<const long> slave_ids,
                                                  std::span<const Vec3> slave_positions,
                                                  TrackingCounts* counts = nullptr);
  /// The same into `pairs` (resized).
  void step(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
            std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
            std::vector<NodeSegmentPair>& pairs, TrackingCounts* counts = nullptr);
  /// The same as Contacts (resized; its storage reused: what an FE code's handle keeps).
  void step(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
            std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
            std::vector<Contact>& contacts, TrackingCounts* counts = nullptr);
  /// Forgets everything: the next step is searched fresh.
  void reset();

 private:
  void step_hints(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                  std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                  std::vector<Contact>& contacts, TrackingCounts* counts);
  /// near_ and answers_ from previous_order_'s order to order_'s.
  void reorder();
  /// The start on `face` after the answers `before` and `last` on it (rule 2).
  [[nodiscard]] std::array<double, 2> extrapolated(const mesh::SurfaceMesh& master, int face,
                                                   const std::array<double, 2>& before,
                                                   const std::array<double, 2>& last) const;
  void step_lists(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                  std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                  std::vector<Contact>& contacts, TrackingCounts* counts);

  SearchOptions options_;
  TrackingOptions tracking_;
  std::vector<long> ids_;
  std::vector<Vec3> anchors_;                               ///< S0 of each node's list
  std::vector<double> drift_at_build_;                      ///< D0 of each node's list
  std::vector<std::vector<std::pair<double, int>>> lists_;  ///< each node's candidate faces (b_f, f), sorted
  std::vector<FaceHint> hints_;  ///< each node's previous face and its start there (face -1: none)
  /// In the order of order_ (reorder()): each node's previous point on its previous face, and its faces
  /// near it (rule 5).
  std::vector<std::array<double, 2>> answers_;
  std::vector<NearFaces> near_;
  std::vector<std::uint32_t> previous_order_, place_;  ///< reorder()'s work space
  std::vector<std::array<double, 2>> answers_scratch_;
  std::vector<NearFaces> near_scratch_;
  double box_drift_ = 0.0;                     ///< rule 5's drift (working unit)
  int faces_ = -1;                             ///< the previous state's face count (the grid's tracker)
  FaceGrid grid_;                              ///< rule 1's broad phase
  std::shared_ptr<const NodeFaces> topology_;  ///< the faces at each node, kept while the faces are
  SearchStorage storage_;                      ///< the faces' tables' buffers, reused from state to state
  std::vector<Vec3> centres_;                  ///< the previous state's face spheres
  std::vector<double> radii_;
  double drift_ = 0.0;
  std::vector<std::uint32_t> order_;  ///< the slave nodes in Morton order (spatial_order), and its work space
  std::vector<std::uint64_t> order_scratch_;
  std::vector<Contact> contacts_;  ///< the answers of a step into NodeSegmentPairs, before they are made
};

}  // namespace contactnn::contact
