// Global contact search (paper Section 2; SPEC 7): for each slave node, the master segment it is paired
// with, and that pair's label.
//
// For a slave node S:
//  1. M = the master node nearest S among the nodes of segments (nearest_node.hpp; ties: the lowest node id);
//  2. the candidates are the master segments containing M at which S passes the segment test of paper
//     Eqs 3-6 (c1 = next - M, c2 = prev - M, counter-clockwise about the outward normal);
//  3. each candidate, rotated so that A = M (then B, C, D counter-clockwise: SPEC 7's node order), is
//     labelled by the reference projection (dataset::label_configuration) on the chosen surface;
//  4. the pair is the candidate whose projection lies inside its segment (status ok), then the nearest:
//     smallest |S - P| with P the projection clamped to the segment; distances within
//     distance_tie_tolerance of each other count as equal and the lower segment index wins;
//  5. no candidate: no_segment.
//
// Tolerance of the segment test (SearchOptions::segment_test_tolerance, default 1e-6). Real meshes put
// slave nodes exactly on a master node or on the plane between two segments (matching meshes, symmetry
// planes), where the strict test of Eqs 3-4 passes or fails by the rounding of the deck's coordinates.
// Eqs 3-4 say that r (S - M in the corner's plane, Eqs 5-6) is r = alpha c1 + beta c2 with alpha, beta > 0.
// With a tolerance tol:
//  - S passes when |r| <= tol x the shorter of |c1|, |c2|: S is on the corner of every segment at M (a
//    slave node on a master node passes for all of them; step 4 then picks one);
//  - otherwise it passes when alpha |c1| > -tol |r| and beta |c2| > -tol |r|: S may lie outside the
//    corner's angle by about tol radians (geometry::passes_segment_test, which relaxes alpha and beta rather
//    than the products of Eqs 3-4, so r pointing backwards along an edge stays out).
// Both only admit more candidates; step 4 chooses among them by the projection, so a slave node on a
// shared edge gets the segment its projection lies in, whichever rounding the deck has. tol = 0 is the
// strict test of Eqs 3-4.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/conventions.hpp"
#include "dataset/labeller.hpp"
#include "geometry/configuration.hpp"
#include "geometry/segment_checks.hpp"
#include "mesh/surface_mesh.hpp"
#include "projection/newton_projection.hpp"

namespace contactnn::contact {

using geometry::Vec3;

enum class NearestNodeMethod { kTree, kBruteForce };

/// Which global search pairs a slave node with a master face: the surface search of SPEC 9 (every face
/// within the capture distance, the closest point on each, the nearest wins: surface_search.hpp), or the
/// paper's nearest-node search of SPEC 7 (this header).
enum class GlobalSearchKind { kSurface, kNearestNode };

/// The surface search's closest point on a face (surface_search.hpp): kCertified takes one Newton run where a
/// certificate proves its answer is the face's closest point (bilinear_certificate.hpp) and the reference
/// elsewhere; kReference the reference (lib/projection's grid of starts) on every face, as before the
/// certificate (kept to be timed and compared beside it).
enum class NarrowPhase { kCertified, kReference };

class FaceLocator;  // narrow_phase.hpp

struct SearchOptions {
  SurfaceKind surface = SurfaceKind::kBilinear;
  GlobalSearchKind search =
      GlobalSearchKind::kSurface;  ///< search_scene's choice; global_search is nearest-node
  /// Surface search: a face is a candidate when its closest point may lie within the capture distance of S.
  /// capture_distance > 0 sets it in world units; otherwise it is capture_relative x the master surface's
  /// largest face size (its longest node distance), so that every slave within about one element of the
  /// surface gets a point (surface_search.hpp explains the choice).
  double capture_distance = 0.0;
  double capture_relative = 1.0;
  /// Surface search: every face is a candidate (the oracle the tests compare the tree against).
  bool brute_force_faces = false;
  NarrowPhase narrow = NarrowPhase::kCertified;  ///< surface search: how each face's closest point is found
  /// Surface search: a method of the user's choice asked first for each face (narrow_phase.hpp); null: exact.
  const FaceLocator* interior = nullptr;
  double segment_test_tolerance = geometry::kSegmentTestTolerance;  ///< relative; see the header comment
  double distance_tie_tolerance = 1e-9;  ///< relative to the longest candidate edge
  NearestNodeMethod nearest = NearestNodeMethod::kTree;
  projection::ProjectionOptions projection;  ///< of the labels (the reference projection's defaults)
};

enum class PairStatus { kFound, kNoSegment };

/// One slave node and what the global search found for it.
struct NodeSegmentPair {
  long slave_id = 0;
  PairStatus status = PairStatus::kNoSegment;
  int nearest_node = -1;                     ///< master surface node nearest S (= nodes[0] when found)
  int segment = -1;                          ///< index into SurfaceMesh::segments
  std::array<int, 4> nodes{-1, -1, -1, -1};  ///< master surface nodes A, B, C, D (A = nearest_node)
  int candidates = 0;                        ///< segments at the nearest node that passed the segment test
  /// Surface search: faces whose closest point needed the reference (no certificate; NarrowPhase)
  int reference_faces = 0;
  geometry::Configuration config;  ///< world coordinates in the order A, B, C, D; unit node normals (Gregory)
  dataset::Label label;            ///< the reference projection of `config` (status ok..invalid)
  // The surface search's closest point (SPEC 9); the nearest-node search leaves these at their defaults.
  Location location = Location::kFace;         ///< where the point lies on its face
  Vec3 point = Vec3::Zero();                   ///< the closest point P, world coordinates
  std::array<double, 2> face_param{0.0, 0.0};  ///< P's local coordinates in the face's own node order
  bool by_method = false;  ///< SearchOptions::interior's method gave the point (else the exact closest point)
};

/// The pair of one slave node S, given the master node nearest it (steps 2-5 above).
/// @param master_normals  unit node normals of `master` (mesh::node_normals) for Gregory; ignored (may be
///                        empty) for bilinear
[[nodiscard]] NodeSegmentPair pair_at_nearest_node(const mesh::SurfaceMesh& master,
                                                   std::span<const Vec3> master_normals, long slave_id,
                                                   const Vec3& slave, int nearest_node,
                                                   const SearchOptions& options);

/// Steps 1-5 for every slave node, in parallel (OpenMP); result i belongs to slave i. Deterministic for
/// any thread count. InvalidArgument if the spans' sizes disagree or Gregory normals are missing.
[[nodiscard]] std::vector<NodeSegmentPair> global_search(const mesh::SurfaceMesh& master,
                                                         std::span<const Vec3> master_normals,
                                                         std::span<const long> slave_ids,
                                                         std::span<const Vec3> slave_positions,
                                                         const SearchOptions& options);

}  // namespace contactnn::contact
