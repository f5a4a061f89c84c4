// The contact search an FE code calls (issue 38): a handle created once from the master faces and the slave
// points, then called at every increment with the node coordinates; it answers SPEC 9's surface search for
// every slave point into arrays the caller owns. The C interface (contactnn/contactnn.h,
// contactnn_contact_*) and the Fortran module wrap it.
//
// What it is built from:
//  - Master faces, each of a type (mesh::FaceType: quad4, quad8, tri3, tri6) with its nodes in SPEC 9's
//    order: the corners counter-clockwise seen from outside (the side a positive gap lies on; (B-A)x(D-A),
//    resp. (B-A)x(C-A), points out of the body), then for a quadratic face the mid-side nodes of the edges
//    1-2, 2-3, ... The caller's node order is kept: the local coordinates are in it.
//  - Node numbering: the coordinate array holds `count` nodes; a node id names node `id - base` (base 0 for
//    C, 1 for Fortran), or, where `ids` is given, the node whose id it is (an FE code's global ids).
//  - Slave points: slave nodes by id (their coordinates come from the node coordinates) or `free_points`
//    free points (integration points of a surface-to-surface code) whose coordinates the caller passes at
//    every update.
//
// The search is surface_search's (surface_search.hpp, SPEC 9) on the surface these faces make, by
// SurfaceTracker (tracking.hpp): the first update is a fresh search, later ones reuse the previous lists and
// points and give a fresh search's answers. Built once at creation: the mesh::SurfaceMesh (quad4 and quad8
// faces as its segments, tri3 and tri6 as its extra faces, each in the caller's order), the face index maps;
// an update only copies the positions in (and, Gregory, computes the node normals of Eq 26,
// mesh::node_normals, over the quad4 and quad8 faces, as a deck's C3D8 and C3D20 segments).
//
// Differences from a deck's search, by design:
//  - Face i is the caller's face i; SPEC 9's tie rule (the lower element id, then the lower face number)
//  reads
//    the lower face index: a deck's faces given in increasing (element id, face number) answer as the deck.
//  - Every quad4 face is a segment: with Gregory quad4 it becomes a Gregory patch. A deck's C3D6
//    quadrilaterals stay bilinear facets under --surface gregory (surface_search.hpp); the handle has no such
//    faces.
//
// The face-interior method (ContactSearchOptions::method): empty, the exact search (lib/projection's
// reference on every candidate face). Otherwise a search::Method name ("closed_form+newton:2", "newton:4", a
// network method with ContactSearchOptions::network): the handle builds a FaceLocator (narrow_phase.hpp) of
// it once and sets SearchOptions::interior to it for every update, fresh and tracked, so that its answers are
// surface_search's with that locator: the method's point where it puts one inside a face and within the
// capture distance, the exact point otherwise (edges, vertices, tri3, pairs it refuses). A scene plan
// (scene-study's plan.toml) is read above this module: lib/contact links no file reader (docs/library.md's
// modules), so a C++ caller reads it with io::read_plan (io/plan_file.hpp) and io::read_network_model and
// passes its method and network here, as the C interface's options.plan_file does.
//
// What an update writes, per slave point i (arrays of the caller, m points; an empty span is not written):
//  status[i]    Status::kOk (0) found, Status::kNoSegment (6) no face point within the capture distance
//  face[i]      the caller's face index (from 0), -1 when none
//  location[i]  Location: 0 face interior, 1 edge, 2 vertex; -1 when none
//  param[2i..]  local coordinates of the point in the face's own node order: (xi, eta) in [-1, 1]^2 for a
//               quad4 bilinear facet and a quad8, (u, v) in [0, 1]^2 for a Gregory quad4, (r, s) for a
//               triangle (SPEC 9)
//  point[3i..]  the closest point P
//  gap[i]       the signed distance |S - P| (SPEC 9: negative where S penetrates)
//  normal[3i..] unit normal: at a face interior the face's outward unit normal at P; at an edge or a vertex
//               (S - P) / gap (so that S = P + gap n); where S lies on the surface (gap 0) the face's normal
//               at P. A slave point without a face gets 0 in param, point, gap and normal.
// Bad input throws (InvalidArgument, NumericalError for a non-finite coordinate) before anything is written.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "contact/surface_search.hpp"
#include "contact/tracking.hpp"
#include "core/error.hpp"
#include "mesh/surface_mesh.hpp"

namespace contactnn::search {
class NetworkModel;
}  // namespace contactnn::search

namespace contactnn::contact {

/// How node ids name the nodes of the coordinate array.
struct NodeNumbering {
  long count = 0;             ///< nodes in the coordinate array (3 coordinates each)
  long base = 0;              ///< the id of node 0 when `ids` is empty: 0 (C) or 1 (Fortran)
  std::span<const long> ids;  ///< empty, or `count` distinct ids: node i's id
};

/// The slave points: node ids, or a number of free points (exactly one of them).
struct SlavePoints {
  std::span<const long> nodes;  ///< slave node ids
  long free_points = 0;         ///< or: this many points, their coordinates passed to every update
};

struct ContactSearchOptions {
  /// World units; <= 0: one largest face size of the state searched (SearchOptions::capture_relative 1).
  double capture_distance = 0.0;
  SurfaceKind quad4 = SurfaceKind::kBilinear;  ///< a quad4 face's surface: bilinear facet or Gregory patch
  int threads = 0;  ///< OpenMP threads of an update, at most 1024; <= 0 OpenMP's default (capped at 1024)
  bool tracking = true;  ///< false: every update a fresh search (the same answers)
  /// The face-interior method: a search::Method name (search/method.hpp; not start+newton:K, which needs a
  /// start the search does not have), or empty for the exact search (see the header).
  std::string method;
  /// The network of a network method (null otherwise); its surface must be `quad4` (a network answers only
  /// quad4 faces of its own surface). Shared: the handle keeps it as long as it lives.
  std::shared_ptr<const search::NetworkModel> network;
};

/// The caller's output arrays for m slave points (sizes m, 2m, 3m); an empty optional span is not written.
struct ContactResults {
  std::span<int> status;  ///< required
  std::span<int> face;    ///< required
  std::span<int> location;
  std::span<double> param;  ///< 2m
  std::span<double> point;  ///< 3m
  std::span<double> gap;
  std::span<double> normal;  ///< 3m
};

/// InvalidArgument ("<who>: output face holds 3 values, expected 2") unless every output array of `out`
/// (ContactResults, or mpi::DistributedResults with its owner) holds its values for n slave points: status
/// and face required, the others as many or none.
template <class Results>
void check_output_sizes(const char* who, const Results& out, std::size_t n) {
  const auto check = [&](const char* name, std::size_t given, std::size_t per, bool required) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, given == per * n || (!required && given == 0),
                         who << ": output " << name << " holds " << given << " values, expected " << per * n
                             << (required ? "" : " (or none)"));
  };
  check("status", out.status.size(), 1, true);
  check("face", out.face.size(), 1, true);
  if constexpr (requires { out.owner; }) check("owner", out.owner.size(), 1, false);
  check("location", out.location.size(), 1, false);
  check("param", out.param.size(), 2, false);
  check("point", out.point.size(), 3, false);
  check("gap", out.gap.size(), 1, false);
  check("normal", out.normal.size(), 3, false);
}

/// Arrays that own the answers for m slave points, and the ContactResults over them: status filled with
/// `status_fill`, face and location with `face_fill`, the reals with `fill`, until an update writes them.
struct ContactAnswers {
  std::vector<int> status, face, location;
  std::vector<double> param, point, gap, normal;
  explicit ContactAnswers(std::size_t m, int status_fill = 0, int face_fill = 0, double fill = 0.0)
      : status(m, status_fill),
        face(m, face_fill),
        location(m, face_fill),
        param(2 * m, fill),
        point(3 * m, fill),
        gap(m, fill),
        normal(3 * m, fill) {}
  ContactResults results() { return {status, face, location, param, point, gap, normal}; }
  friend bool operator==(const ContactAnswers&, const ContactAnswers&) = default;
};

class ContactSearch {
 public:
  /// `face_types[i]` and its nodes, concatenated in `connectivity` (4, 8, 3 or 6 ids per face by its type).
  /// InvalidArgument for a face naming a node that does not exist, a face with a node twice, a connectivity
  /// of the wrong length, repeated node ids, a slave node that does not exist, no faces, or both or neither
  /// kind of slave point; for a method that does not parse, start+newton:K, a network method without a
  /// network, a network without a method or one of the other surface than `quad4` (the message names the
  /// option). Nothing is created then.
  ContactSearch(std::span<const mesh::FaceType> face_types, std::span<const long> connectivity,
                const NodeNumbering& nodes, const SlavePoints& slaves,
                const ContactSearchOptions& options = {});
  ~ContactSearch();
  ContactSearch(const ContactSearch&) = delete;
  ContactSearch& operator=(const ContactSearch&) = delete;

  /// One increment. `coordinates`: 3 x NodeNumbering::count values (x, y, z of each node); `free_points`:
  /// 3 x SlavePoints::free_points values for free points (empty for slave nodes). Writes `out` (see the
  /// header). InvalidArgument for arrays of the wrong size, NumericalError for a non-finite coordinate of a
  /// node the search uses or of a free point: then nothing is written and the tracking state is unchanged.
  void update(std::span<const double> coordinates, std::span<const double> free_points,
              const ContactResults& out);

  [[nodiscard]] long face_count() const;
  [[nodiscard]] long slave_count() const;
  [[nodiscard]] long node_count() const;
  [[nodiscard]] bool free_points() const;
  /// What the last update cost the tracker (zero before the first or without tracking).
  [[nodiscard]] const TrackingCounts& counts() const;
  /// The surface the search runs on (its positions those of the last update).
  [[nodiscard]] const mesh::SurfaceMesh& surface() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Nodes per face of a type: 4, 8, 3, 6.
[[nodiscard]] int face_node_count(mesh::FaceType type);

}  // namespace contactnn::contact
