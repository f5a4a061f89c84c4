// Tracking: the surface search of a history, increment by increment, reusing what the previous increments
// found (SPEC 9's answers, exactly; only cheaper).
//
// The rule (a Verlet list with a previous-point warm start, the bookkeeping explicit codes use: OpenRadioss
// re-sorts a node's candidates once it has used up a distance budget, MOOSE and FrontISTR start from the
// previous point and face):
//  1. A node's candidate list is built by a fresh query: every face whose bounding sphere comes within
//     capture + m of the node (m = TrackingOptions::margin_relative x the capture distance), with the
//     sphere's bound b_f = |S0 - c_f| - r_f, sorted by it, the node's position S0 and the surface's drift D0
//     at that moment.
//  2. The surface's drift D adds, at every increment, the largest movement of a face's sphere (|c_f - c_f'| +
//     |r_f - r_f'| over the faces). The list is valid while |S - S0| + (D - D0) <= m: a face outside it was
//     beyond capture + m at the build, and its sphere can have come nearer by at most that much, so it is
//     still beyond the capture distance. Otherwise the node gets a fresh list (step 1).
//  3. The node's answer is the nearest point over its list's faces (SurfaceSearcher::nearest), the face it
//     had at the previous increment first; the other faces are pruned as in the fresh search, by
//     b_f - |S - S0| - (D - D0), which no face's sphere (and so no point of it) can be nearer than: a face's
//     own bound is computed only once that one no longer rules it out (after the first face's point, for most
//     nodes, none is). A bilinear face with a certificate (bilinear_certificate.hpp) is projected by one
//     Newton run from the node's previous point on it; every other face by the fresh search's reference. A
//     warm start on a face without a certificate could end on another stationary point than the face's
//     nearest (a farther local minimum of a Gregory patch around a slave node inside a closed body: issue
//     39), so none is made.
// The faces, points and gaps equal a fresh search's (the tests and `replay` compare every increment with a
// fresh search and count the differences).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "contact/surface_search.hpp"

namespace contactnn::contact {

struct TrackingOptions {
  /// The list margin m in units of the capture distance: larger lists that stay valid for longer.
  double margin_relative = 0.5;
};

/// What one increment cost the tracker, node by node.
struct TrackingCounts {
  long fresh = 0;    ///< nodes whose list was built by a fresh query (first increment, moved past the margin)
  long tracked = 0;  ///< nodes answered from their list
  long warm = 0;     ///< nodes whose previous face was tried first (warm where it has a certificate)
  long list_faces = 0;  ///< faces in the lists used (sum over the nodes)
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
  /// The same into `pairs` (resized; its storage reused).
  void step(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
            std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
            std::vector<NodeSegmentPair>& pairs, TrackingCounts* counts = nullptr);
  /// Forgets everything: the next step is searched fresh.
  void reset();

 private:
  SearchOptions options_;
  TrackingOptions tracking_;
  std::vector<long> ids_;
  std::vector<Vec3> anchors_;                               ///< S0 of each node's list
  std::vector<double> drift_at_build_;                      ///< D0 of each node's list
  std::vector<std::vector<std::pair<double, int>>> lists_;  ///< each node's candidate faces (b_f, f), sorted
  std::vector<FaceHint> hints_;  ///< each node's previous face and point (face -1: none)
  std::vector<Vec3> centres_;    ///< the previous state's face spheres
  std::vector<double> radii_;
  double drift_ = 0.0;
  std::vector<std::uint32_t> order_;  ///< the slave nodes in Morton order (spatial_order), and its work space
  std::vector<std::uint64_t> order_scratch_;
};

}  // namespace contactnn::contact
