// The surface search (SPEC 9): for each slave node, the closest point of the whole master surface, on a
// face's interior, an edge or a vertex, with its signed gap.
//
// The faces are SurfaceMesh::face_count(), each by its type (SurfaceMesh::face_nodes):
//  - quad4: C3D8* segments, bilinear facets or, with --surface gregory, Gregory patches; C3D6 quadrilaterals,
//    bilinear facets under either surface (their nodes need not carry Eq 26 normals);
//  - quad8: C3D20/C3D20R segments and C3D15 quadrilaterals, the 8-node serendipity surface through all 8
//  nodes
//    (geometry::SerendipityQuad; projection::closest_point_on_serendipity_quad), not the facet of the
//    corners;
//  - tri3: C3D4 and C3D6 triangles, exact flat triangles (projection::closest_point_on_triangle);
//  - tri6: C3D10 and C3D15 triangles, the 6-node quadratic surface (geometry::QuadraticTriangle;
//    projection::closest_point_on_quadratic_triangle).
// --surface gregory smooths quad4 segments only: a quadratic face already has its curved shape from its
// mid-side nodes, and stays its own quadratic surface under either --surface.
//
// For a slave node S:
//  1. Candidates: the faces whose bounding sphere (centre: the mean of the corner nodes; radius: the largest
//     distance from it to a node, to a Gregory control point, or to a Bezier control point of a quadratic
//     face, which bound the patch: a quadratic face may bulge beyond its nodes) comes within the capture
//     distance of S, and whose bounding box does (each face's bound is the larger of the two distances). A
//     grid of the boxes (face_grid.hpp) finds them; NarrowPhase::kReference keeps the search as it was, a
//     k-d tree over the centres (nanoflann); brute_force_faces tries every face (the oracle). A fresh search
//     (surface_search) leaves out every face beyond the capture distance of its slave nodes' box before
//     bounding it: such a face is no node's candidate (a Gregory patch is first bounded from its nodes and
//     normals alone, the control points computed only for the faces kept).
//  2. Candidates in increasing order of their sphere's distance; the closest point on each (by its type, as
//     above: the references of lib/projection; a bilinear quad4, a quad8, a tri6 or a Gregory patch by one
//     Newton run where a convexity certificate proves its answer is the face's nearest,
//     bilinear_certificate.hpp, curved_certificate.hpp, NarrowPhase); a face
//     whose sphere is farther than the best point so far cannot hold a nearer one and ends the scan. A query
//     projects a first face (a tracked node's previous face, else one listed in the grid cell of S) and
//     gathers only the faces within its distance.
//     With SearchOptions::interior (narrow_phase.hpp), a method of the user's choice answers each face first
//     where it puts the point inside the face and within the capture distance (the exact point otherwise).
//  3. The nearest point wins; ties (equal distances to 1e-12 of the face size) go to the lower element id,
//     then the lower face number (SPEC 9). No point within the capture distance: no_segment.
//  4. The gap is the signed distance |S - P|: the sign of (S - P).n, n the face's unit normal at P for a
//     point inside the face, and the angle-weighted pseudo-normal otherwise (Baerentzen & Aanaes 2005): at an
//     edge, the sum of the unit normals at P of the faces sharing it (edges are matched by their two corner
//     nodes, whatever the faces' types; each face's normal at its own point of the edge nearest P); at a
//     vertex, the sum over the faces at the node of the face's corner angle (between its edges' tangents
//     there) times its normal at the corner. So a node just outside a convex edge is separated and one just
//     inside a concave corner penetrates, whichever face it reports.
//     S on the surface (|S - P| = 0) has gap 0.
//
// The answer (Contact): the winning face, where its point lies, its local coordinates in the face's own node
// order, the point, the gap of step 4 and a unit normal. The reported pair (NodeSegmentPair, to_pair: what
// gen-configs writes for training): `segment` the winning face (an index of SurfaceMesh::face_corners);
// for a quad4, `nodes` and `config` its corners rotated so that A is the corner nearest S (ties: the first in
// the face's own order), then counter-clockwise about the outward normal (SPEC 7's node order), and the
// label's parameters in that order; for every other face the label's parameters in the face's own order
// ((xi, eta) of the quad8, (r, s) of a triangle; SurfaceMesh::face_nodes gives that order), `nodes` -1 and
// no SPEC 7 configuration (a quad8 puts its 4 corners, in its own order, in config.nodes for the shape
// statistics: they are not its surface); status ok, gap as above; `location` and `point`.
//
// Capture distance. A contact search must never miss a contact, and a node far from the master surface has
// none to report: by default a face is searched within one largest face size (SearchOptions), far beyond any
// penetration or closing gap an increment of an FE run produces (the CalculiX comparisons' largest |COPEN| is
// a small fraction of an element), yet small enough that a slave node is tested against a handful of faces.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "contact/global_search.hpp"
#include "contact/node_faces.hpp"
#include "mesh/surface_mesh.hpp"

namespace contactnn::contact {

/// The unit of length the searches work in: 1, or where the master's largest coordinate lies beyond 2^+-40,
/// the power of two at most it (every conversion exact). The closest points, the segment test's products and
/// the trees' squared radii need lengths whose fourth powers stay in the double range: a deck scaled by
/// 1e-100 found no point for any slave node, one scaled by 1e100 put every point on an edge. Both searches
/// answer in world units.
[[nodiscard]] double working_unit(const mesh::SurfaceMesh& master);
/// The working unit's conversions, exact for a power of two: the master's positions and the options' absolute
/// lengths divided by `unit`, and an answer found in that unit back in world units (its point, gap and
/// configuration; `slave` the world slave node).
[[nodiscard]] mesh::SurfaceMesh in_unit(const mesh::SurfaceMesh& master, double unit);
[[nodiscard]] SearchOptions in_unit(SearchOptions options, double unit);
void to_world(NodeSegmentPair& pair, double unit, const Vec3& slave);

/// The capture distance of `options` for `master` (world units): options.capture_distance when positive,
/// else options.capture_relative x the largest face size (0 for a surface without faces).
[[nodiscard]] double capture_distance(const mesh::SurfaceMesh& master, const SearchOptions& options);

/// One slave point's answer (steps 1-4): what an FE code reads of it, 112 bytes (the training set's
/// NodeSegmentPair, 504 bytes with its SPEC 7 configuration and label, is made from it where a tool needs
/// one: to_pair).
struct Contact {
  long slave_id = 0;
  int face = -1;  ///< index of SurfaceMesh::face_corners; -1 none (no point within the capture distance)
  PairStatus status = PairStatus::kNoSegment;
  Location location = Location::kFace;  ///< where the point lies on its face
  bool by_method = false;  ///< SearchOptions::interior's method gave the point (else the exact closest point)
  int iterations = 0;      ///< Newton iterations of the point's interior projection
  int candidates = 0;      ///< faces projected with a point (status ok)
  int reference_faces = 0;                ///< faces whose closest point needed the reference (NarrowPhase)
  std::array<double, 2> param{0.0, 0.0};  ///< the point's local coordinates in the face's own node order
  Vec3 point = Vec3::Zero();              ///< the closest point P
  double gap = 0.0;                       ///< the signed distance (step 4)
  /// Unit normal: inside the face, the face's unit normal at P; on an edge or a vertex, (S - P) / gap (so
  /// that S = P + gap n); where S lies on the surface (gap 0), the face's normal at P. Zero without a face.
  Vec3 normal = Vec3::Zero();
};

/// The training set's pair of an answer (the header's "reported pair": a quad4 in SPEC 7's node order, the
/// label's parameters in that order; every other face in its own), from the master the answer was found on
/// (world units) and the slave's position.
[[nodiscard]] NodeSegmentPair to_pair(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                                      const SearchOptions& options, const Contact& contact,
                                      const Vec3& slave);
/// The answer a pair holds (to_pair's inverse, but for the normal, which a pair does not keep: zero).
[[nodiscard]] Contact contact_of(const NodeSegmentPair& pair);
/// The same for every answer, in parallel (OpenMP): pairs[i] of contacts[i] and slave_positions[i]; `pairs`
/// resized.
void to_pairs(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
              const SearchOptions& options, std::span<const Contact> contacts,
              std::span<const Vec3> slave_positions, std::vector<NodeSegmentPair>& pairs);

/// A face to try first and the start of its projection (an FE code's previous point: tracking.hpp).
class FaceGrid;

struct FaceHint {
  int face = -1;                          ///< index of SurfaceMesh::face_corners
  std::array<double, 2> param{0.0, 0.0};  ///< local coordinates in the face's own node order
  /// Whether the face's certified run starts from `param` (a tracked node's previous point); false: from the
  /// face's centre, as a fresh search (the face is then only the first one, e.g. a neighbouring node's).
  bool warm = true;
};

/// A tracked node's faces near it (tracking.hpp, rule 5), kept from one state to the next: every face whose
/// box came within `radius` of `anchor` at the state where the list was made, when the surface's drift (the
/// sum over the states since of the largest movement of a face's box, SurfaceTracker's) was `drift`; each
/// with its box's distance from `anchor` then, in increasing order (all in the searcher's working unit,
/// rounded down). At a later state, with S moved by m from `anchor` and the drift grown by D, a face within
/// reach r of S is listed where m + D + r <= radius, and it is not among the faces whose distance then was
/// beyond m + D + r. Where more faces came within the radius than the list holds, it holds the nearest and
/// `radius` is at most the nearest box it left out (or, with count kCapacity + 1, it holds no face that
/// counts). The node's faces are then taken from here, not gathered from the grid's cells;
/// otherwise the list is made again around S (SurfaceSearcher::nearest_fresh). The answers never depend on
/// it.
struct NearFaces {
  static constexpr std::size_t kCapacity = 5;
  Vec3 anchor = Vec3::Zero();
  double drift = 0.0;
  float radius = -1.0F;    ///< negative: no list
  std::int32_t count = 0;  ///< kCapacity + 1: more faces than a list holds (the grid gathers them)
  std::array<std::int32_t, kCapacity> faces{};
  std::array<float, kCapacity> bounds{};
};
static_assert(sizeof(NearFaces) == 80);

/// A box of points: the smallest holding every finite one (lo > hi on each axis where none is finite).
struct PointBox {
  Vec3 lo, hi;
};

/// Buffers a caller keeps between states (a tracker's increments, or a fresh search's: surface_search), so
/// that a state's SurfaceSearcher writes its faces' tables (spheres, boxes, prepared faces and certificates)
/// and the faces at each node into the last state's memory instead of allocating it afresh: nothing is
/// allocated per increment once warm, and no page is faulted in again. A copy starts empty (buffers, not
/// state: the answers never depend on them).
class SearchStorage {
 public:
  SearchStorage();
  ~SearchStorage();
  SearchStorage(const SearchStorage&);
  SearchStorage& operator=(const SearchStorage&);
  SearchStorage(SearchStorage&&) noexcept;
  SearchStorage& operator=(SearchStorage&&) noexcept;

  struct Tables;  ///< face_index.hpp's
  [[nodiscard]] Tables& tables() { return *tables_; }

 private:
  std::unique_ptr<Tables> tables_;
};

/// The surface search's pieces for one state of a master surface: the faces' bounding spheres and boxes,
/// their grid (or k-d tree) and adjacency, built once; queries are const and may run concurrently. `master`
/// and `master_normals` must outlive it.
class SurfaceSearcher {
 public:
  /// InvalidArgument if Gregory normals are missing or the surface's element ids do not match its faces.
  /// `grid`: a broad phase the caller keeps between states (tracking.hpp), used as it is where it still
  /// holds this state's faces (FaceGrid::holds, in the same unit), else rebuilt with their boxes inflated by
  /// `grid_margin_relative` x the capture distance; null: the searcher builds its own. The certified search's
  /// only. `topology`: the faces at each node, a caller's kept between states, used where it matches the
  /// master's connectivity (NodeFaces::matches), else built afresh and put there (null: the storage's where
  /// it matches, else built for this searcher alone). `storage`: buffers kept between states
  /// (SearchStorage), taken by the searcher and given back when it ends; it must outlive the searcher and
  /// serve one searcher at a time. Each face's entries are kept from the storage's last state where none of
  /// its nodes has moved, except with `queries`, where only the memory is reused. `queries`: the box (world
  /// units) of the points the searcher will be asked about, where the caller knows them (spatial_order gives
  /// it): the certified search without a caller's grid then leaves out every face beyond the capture
  /// distance of it (neither bounded nor prepared: faces_left_out), and a query from elsewhere may miss a
  /// face. Null: none left out.
  SurfaceSearcher(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                  const SearchOptions& options, FaceGrid* grid = nullptr, double grid_margin_relative = 0.0,
                  std::shared_ptr<const NodeFaces>* topology = nullptr, SearchStorage* storage = nullptr,
                  const PointBox* queries = nullptr);
  ~SurfaceSearcher();
  SurfaceSearcher(const SurfaceSearcher&) = delete;
  SurfaceSearcher& operator=(const SurfaceSearcher&) = delete;

  [[nodiscard]] double capture() const;
  /// The searcher's unit of length (working_unit of its master): lengths divided by it before a norm keep
  /// their squares in the double range.
  [[nodiscard]] double unit() const;
  /// Whether this searcher built its grid (always, without a caller's grid; for the reference search, never).
  [[nodiscard]] bool grid_rebuilt() const;
  /// |S - c_f| - r_f: no point of face f is nearer S than this.
  [[nodiscard]] double lower_bound(const Vec3& slave, int face) const;
  /// |S - c_f| - r_f alone: at most lower_bound, and it moves by at most the movement of S, c_f and r_f.
  [[nodiscard]] double sphere_bound(const Vec3& slave, int face) const;
  /// Step 1 with any reach: appends (lower_bound, face) for every face whose bound comes within `reach` of
  /// S (every face when options.brute_force_faces); with `spheres_only`, (sphere_bound, face) for every face
  /// whose sphere does (a tracker's lists: only the spheres' movement is tracked). `scratch` is the tree's
  /// work space (reused by a caller's loop). Nothing for a non-finite S.
  void faces_within(const Vec3& slave, double reach, std::vector<std::pair<double, int>>& out,
                    std::vector<std::pair<std::uint32_t, double>>& scratch, bool spheres_only = false) const;
  /// What the candidates' bounds are: lower_bound itself, in any order; or bounds at most lower_bound, sorted
  /// by (bound, face) (a tracker's bounds from an earlier state less the movement since: each face's own
  /// bound is then computed only where the loose one does not already rule the face out).
  enum class Bounds { kExact, kLooseSorted };
  /// Steps 2-4 over `candidates` (reordered). With a hint (a tracked node), its face is projected first, from
  /// the hint's point where the face has a certificate (bilinear_certificate.hpp; otherwise by the reference,
  /// as fresh). The answer is the same for either kind of bounds, and with or without a hint.
  [[nodiscard]] NodeSegmentPair nearest(long slave_id, const Vec3& slave,
                                        std::vector<std::pair<double, int>>& candidates,
                                        const FaceHint* hint = nullptr, Bounds bounds = Bounds::kExact) const;
  /// Steps 1-4 for one slave node: faces_within(capture) and nearest, gathering fewer candidates: only the
  /// faces whose bound is within the distance of a first face (its certified closest point, or its nearest
  /// corner): the hint's (a tracked node's previous face, its certified run started from the previous point),
  /// else one listed in the grid cell of S; where the scan's answer is not within that reach (and its tie
  /// band), the scan runs again over the capture distance. The same answer with or without a hint.
  [[nodiscard]] NodeSegmentPair nearest_fresh(long slave_id, const Vec3& slave,
                                              std::vector<std::pair<double, int>>& candidates,
                                              std::vector<std::pair<std::uint32_t, double>>& scratch,
                                              const FaceHint* hint = nullptr) const;
  /// The same into `contact` (written once, in place: an FE code's buffer).
  /// `near`: the node's faces near it (NearFaces), taken where they cover the reach and made again where
  /// they do not, and `drift` the surface's drift at this state (a tracker's, kept per node between states;
  /// the certified search's only).
  void nearest_fresh(long slave_id, const Vec3& slave, std::vector<std::pair<double, int>>& candidates,
                     std::vector<std::pair<std::uint32_t, double>>& scratch, Contact& contact,
                     const FaceHint* hint = nullptr, NearFaces* near = nullptr, double drift = 0.0) const;
  /// nearest's answer as a Contact.
  [[nodiscard]] Contact nearest_contact(long slave_id, const Vec3& slave,
                                        std::vector<std::pair<double, int>>& candidates,
                                        const FaceHint* hint = nullptr, Bounds bounds = Bounds::kExact) const;
  /// The largest movement of a face's bounding box since the state of the storage it was given (working
  /// unit): infinite without one, or where that state's faces, unit or positions could not be kept.
  [[nodiscard]] double box_drift() const;
  /// The faces left out for lying beyond the capture distance of the queries' box (the constructor's
  /// `queries`): their bounds are infinite and no query finds them.
  [[nodiscard]] std::size_t faces_left_out() const;
  [[nodiscard]] const std::vector<Vec3>& centres() const;  ///< face centres (mean of the corners)
  [[nodiscard]] const std::vector<double>& radii() const;  ///< bounding-sphere radii

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The indices of `points` in Morton order (the Z curve through their bounding box in cubic cells, 2^10 along
/// its longest side; a two-pass radix sort; non-finite points in the first cell), so that consecutive queries
/// meet the same faces and tree nodes: the searches take their slave nodes in this order (the answers do not
/// depend on it), and a random node order costs about what a mesh's own does. An order whose consecutive
/// points lie a few spacings apart on average (a mesh's own, at most 8 extent / sqrt(n) a step) is kept as it
/// is: measured on the large history's grid order, the Z curve was slower. `order` and `scratch` are resized
/// and reused. `box`, where given: the points' PointBox (the same pass).
void spatial_order(std::span<const Vec3> points, std::vector<std::uint32_t>& order,
                   std::vector<std::uint64_t>& scratch, PointBox* box = nullptr);

/// Steps 1-4 above for every slave node, in parallel (OpenMP); result i belongs to slave i; deterministic
/// for any thread count. `master_normals`: unit node normals (mesh::node_normals) for Gregory, ignored for
/// bilinear. InvalidArgument if the spans' sizes disagree, Gregory normals are missing, or master's mid-side
/// lists are inconsistent with its faces (SurfaceMesh::midsides_consistent).
[[nodiscard]] std::vector<NodeSegmentPair> surface_search(const mesh::SurfaceMesh& master,
                                                          std::span<const Vec3> master_normals,
                                                          std::span<const long> slave_ids,
                                                          std::span<const Vec3> slave_positions,
                                                          const SearchOptions& options);
/// The same into `pairs` (resized to the slave nodes); `storage` as below.
void surface_search(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                    std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                    const SearchOptions& options, std::vector<NodeSegmentPair>& pairs,
                    SearchStorage* storage = nullptr);
/// The same as Contacts (resized to the slave nodes; its storage reused: an FE code's search at every
/// increment allocates nothing for the answers once the buffer has its size). `storage`: the faces' tables'
/// memory kept between calls (an FE code's increments; every entry computed afresh, so the answers never
/// depend on it: a fresh search's 9 MB of tables for 1e5 Gregory faces, zero-filled and faulted in at every
/// call, cost 10 ms a call); null: allocated for this call. Ignored under NarrowPhase::kReference (the search
/// as it was).
void surface_search(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                    std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                    const SearchOptions& options, std::vector<Contact>& contacts,
                    SearchStorage* storage = nullptr);

}  // namespace contactnn::contact
