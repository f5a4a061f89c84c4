#include "contact/surface_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <nanoflann.hpp>
#include <utility>

#include "contact/bilinear_certificate.hpp"
#include "contact/curved_certificate.hpp"
#include "contact/face_grid.hpp"
#include "contact/face_surface.hpp"
#include "contact/narrow_phase.hpp"
#include "contact/point_cloud.hpp"
#include "core/error.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/quadratic_triangle.hpp"
#include "geometry/serendipity_quad.hpp"
#include "geometry/surface_of.hpp"
#include "projection/closest_point_on_face.hpp"

namespace contactnn::contact {

/// Everything the search needs of the faces, built per state (its buffers kept in a SearchStorage between
/// states): centres, bounding radii, sizes, adjacency, prepared faces.
struct FaceIndex {
  std::vector<Vec3> centres;
  std::vector<double> radii;         ///< bounding-sphere radius about the centre
  std::vector<Vec3> box_lo, box_hi;  ///< bounding box of the same points
  std::vector<double> sizes;         ///< longest corner distance
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
  /// The same for the curved faces: quad8, tri6 and Gregory patches (empty where the master has none or under
  /// kReference).
  CurvedCertificates curved;

  [[nodiscard]] std::span<const int> faces_at(int node) const { return topology->at(node); }
};

struct SearchStorage::Tables {
  FaceIndex index;  ///< the last state's, its buffers to be reused
};

SearchStorage::SearchStorage() : tables_(std::make_unique<Tables>()) {}
SearchStorage::~SearchStorage() = default;
SearchStorage::SearchStorage(const SearchStorage&) : SearchStorage() {}
SearchStorage& SearchStorage::operator=(const SearchStorage&) { return *this; }
SearchStorage::SearchStorage(SearchStorage&&) noexcept = default;
SearchStorage& SearchStorage::operator=(SearchStorage&&) noexcept = default;

namespace {

/// Distances within this fraction of the face size count as equal (SPEC 9's tie rule applies).
constexpr double kTieTolerance = 1e-12;

using CentreTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                       PointCloud, 3, std::uint32_t>;

using detail::closest_on_face;
using detail::face_configuration;
using detail::face_positions;
using detail::kind_of;
using detail::normal_on_edge;
using detail::weighted_corner_normal;

FaceIndex index_faces(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                      const SearchOptions& options, std::shared_ptr<const NodeFaces>* topology,
                      FaceIndex&& recycled, double unit, bool keep) {
  FaceIndex index = std::move(recycled);  // its buffers: every moved face's entries rewritten below
  const auto n = static_cast<std::size_t>(master.face_count());
  index.centres.resize(n);
  index.radii.resize(n);
  index.box_lo.resize(n);
  index.box_hi.resize(n);
  index.sizes.resize(n);
  index.checked.resize(n);
  // The faces at each node: the kept ones where the connectivity has not changed.
  const bool same_faces = topology != nullptr && *topology != nullptr && (*topology)->matches(master);
  if (same_faces) {
    index.topology = *topology;
  } else {
    index.topology = std::make_shared<const NodeFaces>(master);
    if (topology != nullptr) *topology = index.topology;
  }
  // The nodes that moved since the kept index was built (all of them without one): a face with none keeps
  // its entries, bit for bit what they would be computed again.
  const std::size_t node_count = master.positions.size();
  const bool gregory = options.surface == SurfaceKind::kGregory && normals.size() == node_count;
  const bool kept = same_faces && index.built_unit == unit && index.built_positions.size() == node_count &&
                    (!gregory || index.built_normals.size() == node_count) && index.centres.size() == n;
  std::vector<std::uint8_t> moved(node_count, 1);
  if (kept) {
#pragma omp parallel for schedule(static) if (node_count >= 16384)
    for (std::size_t i = 0; i < node_count; ++i) {
      moved[i] = !(master.positions[i] == index.built_positions[i]) ||
                 (gregory && !(normals[i] == index.built_normals[i]));
    }
  }
  index.bilinear.reset(options.narrow == NarrowPhase::kCertified ? n : 0);
  // Slots for prepared triangles and quadratic certificates where the surface has such faces.
  bool any_triangle = false, any_curved = false;
  for (std::size_t f = 0; f < n; ++f) {
    const mesh::FaceType type = master.face_type(static_cast<int>(f));
    any_triangle = any_triangle || type == mesh::FaceType::kTri3;
    any_curved = any_curved || type == mesh::FaceType::kQuad8 || type == mesh::FaceType::kTri6 ||
                 (type == mesh::FaceType::kQuad4 &&
                  kind_of(master, options, static_cast<int>(f)) == SurfaceKind::kGregory);
  }
  const bool certified = options.narrow == NarrowPhase::kCertified;
  index.triangles.reset(certified && any_triangle ? n : 0);
  if (kept) {
    index.curved.keep(certified && any_curved ? n : 0);
  } else {
    index.curved.reset(certified && any_curved ? n : 0);
  }
  // Each face on its own (threads for a large surface: the answers do not depend on them).
#pragma omp parallel for schedule(static) if (n >= 4096)
  for (std::size_t f = 0; f < n; ++f) {
    const auto face = static_cast<int>(f);
    const std::span<const int> corners = master.face_corners(face);
    const mesh::FaceNodes nodes = master.face_nodes(face);
    if (kept && std::none_of(nodes.begin(), nodes.end(),
                             [&](int c) { return moved[static_cast<std::size_t>(c)] != 0; }))
      continue;
    if (!index.curved.empty()) index.curved.forget(f);
    index.checked[f] = 0;
    if (nodes.type == mesh::FaceType::kTri3 && !index.triangles.empty())
      index.triangles.construct(f) = projection::prepare_triangle(detail::triangle_nodes(master, face));
    if (!index.bilinear.empty()) index.bilinear.construct(f);  // lambda_floor 0: no certificate
    if (nodes.type == mesh::FaceType::kQuad4 && kind_of(master, options, face) == SurfaceKind::kBilinear) {
      // closest_on_face's patch: the face's configuration relative to its first node.
      geometry::Configuration config = face_configuration(master, normals, SurfaceKind::kBilinear, face);
      const Vec3 origin = config.nodes[0];
      if (origin.allFinite()) {
        for (Vec3& x : config.nodes) x -= origin;
        const geometry::BilinearPatch patch(config.nodes);
        index.checked[f] =
            std::isfinite(patch.characteristic_length()) && !geometry::is_degenerate_segment(patch.nodes())
                ? 1
                : 0;
        if (index.checked[f] != 0 && !index.bilinear.empty()) {
          index.bilinear[f] = BilinearCertificate::prepare(
              face_configuration(master, normals, SurfaceKind::kBilinear, face).nodes);
        }
      }
    }
    Vec3 centre = Vec3::Zero();
    for (int c : corners) centre += master.positions[static_cast<std::size_t>(c)];
    centre /= static_cast<double>(corners.size());
    double radius = 0.0, size = 0.0;
    // The bounding sphere and box of the points whose convex hull holds the face (nodes, control points).
    Vec3 box_lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 box_hi = -box_lo;
    const auto include = [&](const Vec3& x) {
      radius = std::max(radius, (x - centre).norm());
      box_lo = box_lo.cwiseMin(x);
      box_hi = box_hi.cwiseMax(x);
    };
    for (int c : nodes) include(master.positions[static_cast<std::size_t>(c)]);
    for (int c : corners) {
      const Vec3& x = master.positions[static_cast<std::size_t>(c)];
      for (int d : corners) size = std::max(size, (x - master.positions[static_cast<std::size_t>(d)]).norm());
    }
    // A curved face lies in the convex hull of its control points, not of its nodes: the sphere holds those.
    if (nodes.type == mesh::FaceType::kQuad8) {
      const geometry::SerendipityQuad quad8(face_positions<8>(master, nodes));
      for (const Vec3& x : quad8.bezier_control_points()) include(x);
    } else if (nodes.type == mesh::FaceType::kTri6) {
      const geometry::QuadraticTriangle tri6(face_positions<6>(master, nodes));
      for (const Vec3& x : tri6.bezier_control_points()) include(x);
    } else if (corners.size() == 4 && kind_of(master, options, face) == SurfaceKind::kGregory) {
      const geometry::Configuration config = face_configuration(master, normals, SurfaceKind::kGregory, face);
      if (!geometry::surface_defect(config, SurfaceKind::kGregory)) {
        // The patch lies in the convex hull of its control points (each interior point mixes two of them).
        const geometry::GregoryPatch patch(config.nodes, config.normals, geometry::GregoryPatch::Diagnosed{});
        for (const Vec3& x : patch.control_points()) include(x);
      }
    }
    index.centres[f] = centre;
    index.radii[f] = radius;
    index.box_lo[f] = box_lo;
    index.box_hi[f] = box_hi;
    index.sizes[f] = size;
  }
  if (keep) {
    index.built_positions.assign(master.positions.begin(), master.positions.end());
    index.built_normals.assign(normals.begin(), gregory ? normals.end() : normals.begin());
    index.built_unit = unit;
  } else {
    index.built_unit = 0.0;
  }
  return index;
}

/// The pseudo-normal direction (not normalised) at the closest point `p` of face f (header, step 4).
Vec3 pseudo_normal(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                   const SearchOptions& options, const FaceIndex& index, int f,
                   const projection::FaceClosestPoint& p) {
  if (p.location == Location::kFace) return p.normal;
  const std::span<const int> corners = master.face_corners(f);
  const auto k = corners.size();
  Vec3 sum = Vec3::Zero();
  if (p.location == Location::kEdge) {
    const auto e = static_cast<std::size_t>(p.feature);
    const int a = corners[e], b = corners[(e + 1) % k];
    // The faces with the edge (a, b) either way round, in face order, each edge of a face once.
    int previous = -1;
    for (const int face : index.faces_at(a)) {
      if (face == previous) continue;  // a face with node a at two corners is listed twice
      previous = face;
      const std::span<const int> other = master.face_corners(face);
      const auto m = other.size();
      for (std::size_t g = 0; g < m; ++g) {
        const int x = other[g], y = other[(g + 1) % m];
        if ((x == a && y == b) || (x == b && y == a)) {
          sum += face == f ? p.normal
                           : normal_on_edge(master, normals, options, face, static_cast<int>(g), p.point);
        }
      }
    }
    return sum;
  }
  // A vertex: every face at the node, weighted by its corner angle there.
  const int node = corners[static_cast<std::size_t>(p.feature)];
  for (int face : index.faces_at(node)) {
    const std::span<const int> other = master.face_corners(face);
    const auto at = static_cast<int>(std::find(other.begin(), other.end(), node) - other.begin());
    sum += weighted_corner_normal(master, normals, options, face, at);
  }
  return sum;
}

/// (xi, eta) or (u, v) of a face's point after the face's corners are relabelled to start at corner k
/// (A' = old corner k, then on counter-clockwise): k cyclic steps of (s, t) -> (t, -s) about the centre.
std::array<double, 2> rotate_param(std::array<double, 2> p, int k, SurfaceKind kind) {
  const bool bilinear = kind == SurfaceKind::kBilinear;
  for (int i = 0; i < k; ++i)
    p = bilinear ? std::array<double, 2>{p[1], -p[0]} : std::array<double, 2>{p[1], 1.0 - p[0]};
  return p;
}

/// Face f's certificate, or null where it has none (NarrowPhase::kReference, or not a checked bilinear
/// quad4).
const BilinearCertificate* certificate_of(const FaceIndex& index, int face) {
  if (index.bilinear.empty()) return nullptr;
  const BilinearCertificate& c = index.bilinear[static_cast<std::size_t>(face)];
  return c.lambda_floor > 0.0 ? &c : nullptr;
}

/// Face f's curved certificate, or null where it has none (kReference, not a quad8, tri6 or Gregory patch, or
/// no bound).
/// Prepared on its first use in the state (CurvedCertificates).
const CurvedCertificate* curved_of(const FaceIndex& index, const mesh::SurfaceMesh& master,
                                   std::span<const Vec3> normals, const SearchOptions& options, int face) {
  if (index.curved.empty()) return nullptr;
  const mesh::FaceType type = master.face_type(face);
  const bool gregory =
      type == mesh::FaceType::kQuad4 && kind_of(master, options, face) == SurfaceKind::kGregory;
  if (type != mesh::FaceType::kQuad8 && type != mesh::FaceType::kTri6 && !gregory) return nullptr;
  const CurvedCertificate& c = index.curved.get(static_cast<std::size_t>(face), [&](CurvedCertificate& out) {
    const mesh::FaceNodes nodes = master.face_nodes(face);
    if (type == mesh::FaceType::kQuad8) {
      out = CurvedCertificate::prepare(geometry::SerendipityQuad(face_positions<8>(master, nodes)));
    } else if (type == mesh::FaceType::kTri6) {
      out = CurvedCertificate::prepare(geometry::QuadraticTriangle(face_positions<6>(master, nodes)));
    } else {
      const geometry::Configuration config = face_configuration(master, normals, SurfaceKind::kGregory, face);
      if (!geometry::surface_defect(config, SurfaceKind::kGregory))
        CurvedCertificate::prepare_gregory(out, config.nodes, config.normals);
    }
  });
  return c.lambda_floor > 0.0 ? &c : nullptr;
}

/// closest_on_face for face f of an indexed state: `checked` (the options with face_checked) where the index
/// checked the face, and its certificate where it has one. With options.interior, its method's point first
/// where it gives one within `capture` (narrow_phase.hpp; beyond, the face's exact point may still be
/// within).
projection::FaceClosestPoint closest_on_indexed_face(
    const mesh::SurfaceMesh& master, std::span<const Vec3> normals, const SearchOptions& options,
    const SearchOptions& checked, const FaceIndex& index, int f, const Vec3& slave,
    const std::array<double, 2>* start, int* reference_count, double capture) {
  if (options.interior != nullptr) {
    const auto p = options.interior->locate(master, normals, kind_of(master, options, f), f, slave);
    if (p && p->distance <= capture) return *p;
  }
  if (!index.triangles.empty() && master.face_type(f) == mesh::FaceType::kTri3)
    return projection::closest_point_on_prepared_triangle(index.triangles[static_cast<std::size_t>(f)],
                                                          slave);
  const SearchOptions& face_options = index.checked[static_cast<std::size_t>(f)] != 0 ? checked : options;
  return closest_on_face(master, normals, face_options, f, slave, certificate_of(index, f), start,
                         reference_count, curved_of(index, master, normals, options, f));
}

/// |S - c_f| - r_f and the distance to face f's box, the larger (SurfaceSearcher::lower_bound; the sphere's
/// is loose beside a flat face, the box's tight), where it is at most `reach`; otherwise some number above.
/// The box's squared distance is tested first, with a relative slack far above its rounding: most faces a
/// grid cell lists are then refused without a square root, and every face within reach gets
/// face_lower_bound's own bits.
double face_bound_within(const FaceIndex& index, const Vec3& slave, int face, double reach) {
  const auto f = static_cast<std::size_t>(face);
  const Vec3 outside = (index.box_lo[f] - slave).cwiseMax(slave - index.box_hi[f]).cwiseMax(Vec3::Zero());
  const double squared = outside.squaredNorm();
  if (squared > reach * reach * (1.0 + 1e-12)) return std::numeric_limits<double>::infinity();
  return std::max((slave - index.centres[f]).norm() - index.radii[f], std::sqrt(squared));
}

/// The bound itself.
double face_lower_bound(const FaceIndex& index, const Vec3& slave, int face) {
  return face_bound_within(index, slave, face, std::numeric_limits<double>::infinity());
}

/// A face's closest point computed before the scan (SurfaceSearcher::nearest_fresh's first face), and the
/// faces that needed the reference for it.
struct KnownPoint {
  int face = -1;
  projection::FaceClosestPoint point;
  int reference_faces = 0;
};

/// The reported pair of `contact` (to_pair), all in the unit of `master`'s positions: a quad4 in SPEC 7's
/// node order, A the corner nearest S (ties: the first in the face's order; distances compared after dividing
/// by `unit`, the searches' working unit, so that their squares stay in range), the label's parameters in
/// that order. Other faces keep their own order and parameters and have no SPEC 7 configuration; a quad8's
/// corners (its own order) fill `config` for the shape statistics.
void expand_pair(const mesh::SurfaceMesh& master, std::span<const Vec3> normals, const SearchOptions& options,
                 double unit, const Contact& contact, const Vec3& slave, NodeSegmentPair& best) {
  std::construct_at(&best);
  best.slave_id = contact.slave_id;
  best.reference_faces = contact.reference_faces;
  if (contact.status != PairStatus::kFound) return;
  best.status = PairStatus::kFound;
  best.segment = contact.face;
  best.candidates = contact.candidates;
  best.location = contact.location;
  best.point = contact.point;
  best.face_param = contact.param;
  best.by_method = contact.by_method;
  best.config.slave = slave;
  dataset::Label& label = best.label;
  label.status = Status::kOk;
  label.iterations = contact.iterations;
  label.param = contact.param;
  label.gap = contact.gap;
  const std::span<const int> corners = master.face_corners(best.segment);
  const mesh::FaceType type = master.face_type(best.segment);
  if (type == mesh::FaceType::kQuad8) {
    for (std::size_t i = 0; i < 4; ++i)
      best.config.nodes[i] = master.positions[static_cast<std::size_t>(corners[i])];
  }
  if (type != mesh::FaceType::kQuad4) return;
  int k = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const double d2 =
        ((master.positions[static_cast<std::size_t>(corners[static_cast<std::size_t>(i)])] - slave) / unit)
            .squaredNorm();
    if (d2 < nearest) {
      nearest = d2;
      k = i;
    }
  }
  for (int i = 0; i < 4; ++i)
    best.nodes[static_cast<std::size_t>(i)] = corners[static_cast<std::size_t>((k + i) % 4)];
  best.nearest_node = best.nodes[0];
  const SurfaceKind kind = kind_of(master, options, best.segment);
  const geometry::Configuration own = face_configuration(master, normals, kind, best.segment);
  for (std::size_t i = 0; i < 4; ++i) {
    best.config.nodes[i] = own.nodes[(static_cast<std::size_t>(k) + i) % 4];
    best.config.normals[i] = own.normals[(static_cast<std::size_t>(k) + i) % 4];
  }
  best.label.param = rotate_param(contact.param, k, kind);
}

/// A Contact's lengths in world units (its point and gap times the working unit).
void contact_to_world(Contact& contact, double unit) {
  contact.point *= unit;
  contact.gap *= unit;
}

/// Steps 2-4 of the header for one slave node, given its candidate faces (unordered; with `loose`, sorted by
/// bounds that are at most each face's own: SurfaceSearcher::nearest).
/// `checked`: `options` with projection.face_checked set, for the faces FaceIndex::checked marks.
/// `known`: a face's closest point already computed, taken where the scan reaches that face.
/// Into `best` (constructed there afresh: a node's answer written once, where the caller keeps it).
void search_one(const mesh::SurfaceMesh& master, std::span<const Vec3> normals, const SearchOptions& options,
                const SearchOptions& checked, const FaceIndex& index, double capture, long slave_id,
                const Vec3& slave, std::vector<std::pair<double, int>>& candidates, const FaceHint* hint,
                bool loose, const KnownPoint* known, Contact& best) {
  std::construct_at(&best);
  best.slave_id = slave_id;
  if (known != nullptr) best.reference_faces = known->reference_faces;
  // Nearest sphere first; equal bounds in face order, so the scan is the same whatever the tree returned. A
  // hint's face goes first (its point, warm-started, is usually the answer and prunes the others). Loose
  // bounds come sorted.
  if (!loose) std::sort(candidates.begin(), candidates.end());
  if (hint != nullptr) {
    const auto at = std::find_if(candidates.begin(), candidates.end(),
                                 [&](const std::pair<double, int>& c) { return c.second == hint->face; });
    if (at != candidates.end()) std::rotate(candidates.begin(), at, at + 1);
  }
  double best_distance = std::numeric_limits<double>::infinity();
  projection::FaceClosestPoint best_point;
  const auto consider = [&](int f, const projection::FaceClosestPoint& p) {
    const double tie = kTieTolerance * index.sizes[static_cast<std::size_t>(f)];
    bool better = best.face < 0 || p.distance < best_distance - tie;
    if (!better && p.distance <= best_distance + tie) {
      const auto key = [&](int g) { return std::pair(master.face_element_id(g), master.face_of(g).face); };
      better = key(f) < key(best.face);
    }
    if (better) {
      best.face = f;
      best_distance = p.distance;
      best_point = p;
    }
  };
  for (const auto& [bound, f] : candidates) {
    const bool hinted = hint != nullptr && f == hint->face;
    if (bound > capture) {
      if (hinted) continue;
      break;
    }
    // A face whose sphere is beyond the best point (and its tie band) cannot beat it.
    if (bound > best_distance + kTieTolerance * index.sizes[static_cast<std::size_t>(f)]) {
      if (hinted) continue;
      break;
    }
    if (loose) {
      // The face's own bound, now that it may matter (a loose bound is at most it: no face the exact
      // bounds would project is skipped, and none they skip is projected).
      const double exact = face_lower_bound(index, slave, f);
      if (exact > capture || exact > best_distance + kTieTolerance * index.sizes[static_cast<std::size_t>(f)])
        continue;
    }
    const projection::FaceClosestPoint p =
        known != nullptr && f == known->face
            ? known->point
            : closest_on_indexed_face(master, normals, options, checked, index, f, slave,
                                      hinted && hint->warm ? &hint->param : nullptr, &best.reference_faces,
                                      capture);
    if (p.status != Status::kOk) continue;
    ++best.candidates;
    consider(f, p);
  }
  if (best.face < 0 || best_distance > capture) {
    best.face = -1;
    best.candidates = 0;
    return;
  }
  best.status = PairStatus::kFound;
  best.location = best_point.location;
  best.point = best_point.point;
  best.iterations = best_point.iterations;
  best.param = best_point.param;
  best.by_method = best_point.by_method;
  const Vec3 n = pseudo_normal(master, normals, options, index, best.face, best_point);
  const Vec3 d = slave - best_point.point;
  const double side = d.dot(n);
  best.gap = side < 0.0 ? -best_point.distance : best_point.distance;
  // The contact normal (Contact::normal): the face's at an interior point or where S is on the surface.
  best.normal = best_point.normal;
  const double length = d.norm();
  if (best.location != Location::kFace && best.gap != 0.0 && length > 0.0 && std::isfinite(length))
    best.normal = (best.gap < 0.0 ? -d : d) / length;
}

Contact search_one(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                   const SearchOptions& options, const SearchOptions& checked, const FaceIndex& index,
                   double capture, long slave_id, const Vec3& slave,
                   std::vector<std::pair<double, int>>& candidates, const FaceHint* hint, bool loose) {
  Contact best;
  search_one(master, normals, options, checked, index, capture, slave_id, slave, candidates, hint, loose,
             nullptr, best);
  return best;
}

}  // namespace

SearchOptions with_face_checked(SearchOptions o) {
  o.projection.face_checked = true;
  return o;
}

struct SurfaceSearcher::Impl {
  double unit;                                ///< world length = unit x working length
  std::unique_ptr<mesh::SurfaceMesh> scaled;  ///< the master in working units, where unit != 1
  const mesh::SurfaceMesh& master;            ///< the master in working units
  std::span<const Vec3> normals;              ///< unit vectors: the same in any unit
  SearchOptions options;
  SearchOptions checked_options;  ///< options with projection.face_checked (FaceIndex::checked)
  FaceIndex index;
  double capture = 0.0;
  double largest_radius = 0.0;
  double largest_size = 0.0;  ///< the largest face size (the tie band's widest)
  PointCloud cloud;           ///< the face centres
  /// The broad phase of the certified search (face_grid.hpp): the searcher's own, or a caller's kept between
  /// states (`grid`); null for the reference search and brute_force_faces (the k-d tree, every face).
  FaceGrid own_grid;
  const FaceGrid* grid = nullptr;
  bool grid_rebuilt = false;
  /// Built on the first query that needs it (faces_within): a tracker's increment whose nodes all answer from
  /// their lists needs none.
  mutable std::unique_ptr<CentreTree> tree;
  mutable std::once_flag tree_built;
  const CentreTree& centre_tree() const {
    std::call_once(tree_built, [this] {
      tree = std::make_unique<CentreTree>(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    });
    return *tree;
  }
  std::vector<Vec3> world_centres;  ///< index's, in world units (where unit != 1)
  std::vector<double> world_radii;

  /// The reported pair of an answer in world units (expand_pair in the working unit, then to world).
  NodeSegmentPair pair_of(Contact contact, const Vec3& world_slave) const {
    NodeSegmentPair pair;
    if (unit == 1.0) {
      expand_pair(master, normals, options, 1.0, contact, world_slave, pair);
      return pair;
    }
    contact.point /= unit;
    contact.gap /= unit;
    expand_pair(master, normals, options, 1.0, contact, world_slave / unit, pair);
    to_world(pair, unit, world_slave);
    return pair;
  }

  /// Step 1 in working units (faces_within): every face whose bound comes within `reach` of `slave`.
  void collect(const Vec3& slave, double reach, std::vector<std::pair<double, int>>& out,
               std::vector<std::pair<std::uint32_t, double>>& scratch, bool spheres_only) const {
    const auto bound_of = [&](int face) {
      const auto f = static_cast<std::size_t>(face);
      return spheres_only ? (slave - index.centres[f]).norm() - index.radii[f]
                          : face_bound_within(index, slave, face, reach);
    };
    if (options.brute_force_faces) {
      for (std::size_t s = 0; s < index.centres.size(); ++s) {
        const double bound = bound_of(static_cast<int>(s));
        if (bound <= reach) out.emplace_back(bound, static_cast<int>(s));
      }
      return;
    }
    if (grid != nullptr) {
      // Every face whose box comes within reach (a sphere within reach: its box within reach + its radius).
      grid->for_faces_near(slave, spheres_only ? reach + largest_radius : reach, [&](int face) {
        const double bound = bound_of(face);
        if (bound <= reach) out.emplace_back(bound, face);
      });
      return;
    }
    // Every centre within reach + the largest radius, then each face by its own sphere.
    const double radius = reach + largest_radius;
    const double q[3] = {slave.x(), slave.y(), slave.z()};
    scratch.clear();
    centre_tree().radiusSearch(q, radius * radius * (1.0 + 1e-12), scratch,
                               nanoflann::SearchParams(32, 0.0F, false));
    for (const auto& item : scratch) {
      const double bound = bound_of(static_cast<int>(item.first));
      if (bound <= reach) out.emplace_back(bound, static_cast<int>(item.first));
    }
  }

  SearchStorage* storage = nullptr;  ///< where the tables go back when the searcher ends

  Impl(const mesh::SurfaceMesh& m, std::span<const Vec3> n, const SearchOptions& o, FaceGrid* kept,
       double grid_margin_relative, std::shared_ptr<const NodeFaces>* topology, SearchStorage* kept_storage)
      : unit(working_unit(m)),
        scaled(unit == 1.0 ? nullptr : std::make_unique<mesh::SurfaceMesh>(in_unit(m, unit))),
        master(scaled ? *scaled : m),
        normals(n),
        options(in_unit(o, unit)),
        checked_options(with_face_checked(options)),
        index(index_faces(master, n, options, topology,
                          kept_storage != nullptr ? std::move(kept_storage->tables().index) : FaceIndex{},
                          unit, kept_storage != nullptr)),

        largest_radius(index.radii.empty() ? 0.0 : *std::max_element(index.radii.begin(), index.radii.end())),
        largest_size(index.sizes.empty() ? 0.0 : *std::max_element(index.sizes.begin(), index.sizes.end())),
        cloud{&index.centres},
        storage(kept_storage) {
    // capture_distance's, from the sizes the index has computed (the same products, the same largest).
    capture =
        options.capture_distance > 0.0 ? options.capture_distance : options.capture_relative * largest_size;
    if (options.narrow != NarrowPhase::kReference && !options.brute_force_faces) {
      FaceGrid& g = kept != nullptr ? *kept : own_grid;
      if (kept == nullptr || kept->unit() != unit || !kept->holds(index.box_lo, index.box_hi)) {
        g.build(index.box_lo, index.box_hi, kept != nullptr ? grid_margin_relative * capture : 0.0, unit);
        grid_rebuilt = true;
      }
      grid = &g;
    }
    if (unit == 1.0) return;
    for (const Vec3& c : index.centres) world_centres.push_back(c * unit);
    for (double r : index.radii) world_radii.push_back(r * unit);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (storage != nullptr) storage->tables().index = std::move(index);
  }
};

SurfaceSearcher::SurfaceSearcher(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                                 const SearchOptions& options, FaceGrid* grid, double grid_margin_relative,
                                 std::shared_ptr<const NodeFaces>* topology, SearchStorage* storage) {
  const bool gregory = options.surface == SurfaceKind::kGregory;
  CONTACTNN_REQUIRE(!gregory || master_normals.size() == master.positions.size(),
                    "Gregory search needs one node normal per master node: "
                        << master_normals.size() << " for " << master.positions.size());
  CONTACTNN_REQUIRE(master.segment_element_ids.size() == master.segments.size() &&
                        master.extra_face_element_ids.size() == master.extra_faces.size(),
                    master.segment_element_ids.size()
                        << " element ids for " << master.segments.size() << " faces");
  CONTACTNN_REQUIRE(master.midsides_consistent(),
                    "mid-side nodes for "
                        << master.segment_midsides.size() << " of " << master.segments.size()
                        << " segments and " << master.extra_face_midsides.size() << " of "
                        << master.extra_faces.size() << " extra faces (each list: none or all)");
  impl_ =
      std::make_unique<Impl>(master, master_normals, options, grid, grid_margin_relative, topology, storage);
}

SurfaceSearcher::~SurfaceSearcher() = default;

// The public members take and give world units; inside, lengths are in the working unit (Impl::unit, a power
// of two: every conversion is exact).
double SurfaceSearcher::capture() const { return impl_->capture * impl_->unit; }

double SurfaceSearcher::unit() const { return impl_->unit; }

bool SurfaceSearcher::grid_rebuilt() const { return impl_->grid_rebuilt; }

double SurfaceSearcher::lower_bound(const Vec3& slave, int face) const {
  return face_lower_bound(impl_->index, slave / impl_->unit, face) * impl_->unit;
}

double SurfaceSearcher::sphere_bound(const Vec3& slave, int face) const {
  const auto f = static_cast<std::size_t>(face);
  return ((slave / impl_->unit - impl_->index.centres[f]).norm() - impl_->index.radii[f]) * impl_->unit;
}

const std::vector<Vec3>& SurfaceSearcher::centres() const {
  return impl_->unit == 1.0 ? impl_->index.centres : impl_->world_centres;
}
const std::vector<double>& SurfaceSearcher::radii() const {
  return impl_->unit == 1.0 ? impl_->index.radii : impl_->world_radii;
}

void SurfaceSearcher::faces_within(const Vec3& world_slave, double world_reach,
                                   std::vector<std::pair<double, int>>& out,
                                   std::vector<std::pair<std::uint32_t, double>>& scratch,
                                   bool spheres_only) const {
  const double unit = impl_->unit;
  const Vec3 slave = world_slave / unit;
  if (!slave.allFinite() || impl_->index.centres.empty()) return;
  const std::size_t first = out.size();
  impl_->collect(slave, world_reach / unit, out, scratch, spheres_only);
  if (unit != 1.0) {
    for (std::size_t i = first; i < out.size(); ++i) out[i].first *= unit;
  }
}

NodeSegmentPair SurfaceSearcher::nearest_fresh(long slave_id, const Vec3& slave,
                                               std::vector<std::pair<double, int>>& candidates,
                                               std::vector<std::pair<std::uint32_t, double>>& scratch,
                                               const FaceHint* hint) const {
  Contact contact;
  nearest_fresh(slave_id, slave, candidates, scratch, contact, hint);
  return impl_->pair_of(contact, slave);
}

void SurfaceSearcher::nearest_fresh(long slave_id, const Vec3& world_slave,
                                    std::vector<std::pair<double, int>>& candidates,
                                    std::vector<std::pair<std::uint32_t, double>>& scratch, Contact& contact,
                                    const FaceHint* hint) const {
  const Impl& m = *impl_;
  const Vec3 slave = world_slave / m.unit;
  candidates.clear();
  // NarrowPhase::kReference is the search as it was before the certificate, its broad phase included.
  if (!slave.allFinite() || m.index.centres.empty() || m.options.brute_force_faces ||
      m.options.narrow == NarrowPhase::kReference) {
    faces_within(world_slave, capture(), candidates, scratch);
    contact = nearest_contact(slave_id, world_slave, candidates);
    return;
  }
  // The first face: the hint's, else one listed in the grid cell of S (or around it). Any face would do (the
  // answer does not depend on it; a nearer one gathers fewer candidates).
  const bool hinted =
      hint != nullptr && hint->face >= 0 && hint->face < static_cast<int>(m.index.centres.size());
  // A hint that is not warm (a neighbouring node's face) is taken where S's own cell lists no face.
  int nearest = hinted && hint->warm ? hint->face : m.grid->face_near(slave, m.index.centres, !hinted);
  if (nearest < 0 && hinted) nearest = hint->face;
  // Its distance d bounds the answer's: where the face has a certificate (or is a flat triangle), its closest
  // point, computed once and taken again by the scan; otherwise (a curved face's certificate included, where
  // it does not hold for S) its nearest corner (a point of the face), so that no reference projection is
  // spent on a face the scan may never reach.
  KnownPoint known;
  const KnownPoint* first = nullptr;
  double reach = m.capture;
  if (nearest < 0) {
    // No face in the cells around S: the scan gathers over the capture distance.
  } else if (const CurvedCertificate* curved = curved_of(m.index, m.master, m.normals, m.options, nearest);
             certificate_of(m.index, nearest) != nullptr ||
             (curved != nullptr && curved->convex_for(slave - curved->origin)) ||
             m.master.face_type(nearest) == mesh::FaceType::kTri3) {
    known.face = nearest;
    known.point = closest_on_indexed_face(m.master, m.normals, m.options, m.checked_options, m.index, nearest,
                                          slave, hinted && hint->warm ? &hint->param : nullptr,
                                          &known.reference_faces, m.capture);
    first = &known;
    if (known.point.status == Status::kOk) reach = std::min(reach, known.point.distance);
  } else {
    for (const int c : m.master.face_corners(nearest)) {
      const double d = (slave - m.master.positions[static_cast<std::size_t>(c)]).norm();
      if (std::isfinite(d)) reach = std::min(reach, d);
    }
  }
  // The scan over the faces within `reach` makes the same choices as over every face within the capture
  // distance as long as it reaches none of the faces left out: its final best B (and B's tie band) must stay
  // within `reach`. Then every face left out has a bound beyond B and its band, where the full scan stops.
  // Where that does not hold (no point, or a best beyond), the scan runs again over the capture distance.
  const double band = kTieTolerance * m.largest_size;
  reach = std::min(m.capture, reach + 4.0 * band);
  m.collect(slave, reach, candidates, scratch, false);
  search_one(m.master, m.normals, m.options, m.checked_options, m.index, m.capture, slave_id, slave,
             candidates, nullptr, false, first, contact);
  // |gap| is the scan's own distance of the best, bit for bit (a distance recomputed from the point may
  // differ by the rounding of the face's origin, as much as the band itself far from the origin).
  const bool complete =
      reach >= m.capture || (contact.status == PairStatus::kFound && std::abs(contact.gap) + band <= reach);
  if (!complete) {
    const int spent = contact.reference_faces - (first != nullptr ? first->reference_faces : 0);
    candidates.clear();
    m.collect(slave, m.capture, candidates, scratch, false);
    search_one(m.master, m.normals, m.options, m.checked_options, m.index, m.capture, slave_id, slave,
               candidates, nullptr, false, first, contact);
    contact.reference_faces += spent;
  }
  if (m.unit != 1.0) contact_to_world(contact, m.unit);
}

Contact SurfaceSearcher::nearest_contact(long slave_id, const Vec3& slave,
                                         std::vector<std::pair<double, int>>& candidates,
                                         const FaceHint* hint, Bounds bounds) const {
  const double unit = impl_->unit;
  if (unit == 1.0) {
    return search_one(impl_->master, impl_->normals, impl_->options, impl_->checked_options, impl_->index,
                      impl_->capture, slave_id, slave, candidates, hint, bounds == Bounds::kLooseSorted);
  }
  for (auto& c : candidates) c.first /= unit;
  Contact contact =
      search_one(impl_->master, impl_->normals, impl_->options, impl_->checked_options, impl_->index,
                 impl_->capture, slave_id, slave / unit, candidates, hint, bounds == Bounds::kLooseSorted);
  for (auto& c : candidates) c.first *= unit;
  contact_to_world(contact, unit);
  return contact;
}

NodeSegmentPair SurfaceSearcher::nearest(long slave_id, const Vec3& slave,
                                         std::vector<std::pair<double, int>>& candidates,
                                         const FaceHint* hint, Bounds bounds) const {
  return impl_->pair_of(nearest_contact(slave_id, slave, candidates, hint, bounds), slave);
}

NodeSegmentPair to_pair(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                        const SearchOptions& options, const Contact& contact, const Vec3& slave) {
  NodeSegmentPair pair;
  expand_pair(master, master_normals, options, working_unit(master), contact, slave, pair);
  return pair;
}

Contact contact_of(const NodeSegmentPair& pair) {
  Contact c;
  c.slave_id = pair.slave_id;
  c.reference_faces = pair.reference_faces;
  if (pair.status != PairStatus::kFound) return c;
  c.face = pair.segment;
  c.status = pair.status;
  c.location = pair.location;
  c.by_method = pair.by_method;
  c.iterations = pair.label.iterations;
  c.candidates = pair.candidates;
  c.param = pair.face_param;
  c.point = pair.point;
  c.gap = pair.label.gap;
  return c;
}

void to_pairs(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
              const SearchOptions& options, std::span<const Contact> contacts,
              std::span<const Vec3> slave_positions, std::vector<NodeSegmentPair>& pairs) {
  CONTACTNN_REQUIRE(contacts.size() == slave_positions.size(),
                    contacts.size() << " answers for " << slave_positions.size() << " positions");
  const double unit = working_unit(master);
  const auto n = static_cast<long>(contacts.size());
  pairs.resize(contacts.size());
#pragma omp parallel for schedule(static) if (n >= 4096)
  for (long i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    expand_pair(master, master_normals, options, unit, contacts[u], slave_positions[u], pairs[u]);
  }
}

std::vector<NodeSegmentPair> surface_search(const mesh::SurfaceMesh& master,
                                            std::span<const Vec3> master_normals,
                                            std::span<const long> slave_ids,
                                            std::span<const Vec3> slave_positions,
                                            const SearchOptions& options) {
  std::vector<NodeSegmentPair> pairs;
  surface_search(master, master_normals, slave_ids, slave_positions, options, pairs);
  return pairs;
}

void surface_search(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                    std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                    const SearchOptions& options, std::vector<NodeSegmentPair>& pairs) {
  std::vector<Contact> contacts;
  surface_search(master, master_normals, slave_ids, slave_positions, options, contacts);
  to_pairs(master, master_normals, options, contacts, slave_positions, pairs);
}

void surface_search(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                    std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                    const SearchOptions& options, std::vector<Contact>& contacts) {
  CONTACTNN_REQUIRE(slave_ids.size() == slave_positions.size(),
                    slave_ids.size() << " slave ids for " << slave_positions.size() << " positions");
  const SurfaceSearcher searcher(master, master_normals, options);
  const auto n = static_cast<long>(slave_ids.size());
  contacts.resize(static_cast<std::size_t>(n));
  // The slave nodes in Morton order (the search before the certificate, NarrowPhase::kReference, in theirs).
  thread_local std::vector<std::uint32_t> order;
  thread_local std::vector<std::uint64_t> codes;
  if (options.narrow == NarrowPhase::kReference) {
    CONTACTNN_REQUIRE(slave_ids.size() < (std::size_t{1} << 32), n << " slave nodes: at most 2^32 - 1");
    order.resize(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
  } else {
    spatial_order(slave_positions, order, codes);
  }
  const std::uint32_t* at = order.data();
#pragma omp parallel if (n >= 512)
  {
    std::vector<std::pair<double, int>> candidates;
    std::vector<std::pair<std::uint32_t, double>> scratch;
    // Each node's first face: the previous node's answer (its neighbour in Morton order; any face gives the
    // same answer, bit for bit, when its run is not warm-started: a near one gathers fewer candidates),
    // else one of its grid cell's.
    FaceHint previous;
    previous.warm = false;
#pragma omp for schedule(dynamic, 64)
    for (long i = 0; i < n; ++i) {
      const std::size_t u = at[i];
      searcher.nearest_fresh(slave_ids[u], slave_positions[u], candidates, scratch, contacts[u],
                             previous.face >= 0 ? &previous : nullptr);
      previous.face = contacts[u].status == PairStatus::kFound ? contacts[u].face : -1;
    }
  }
}

}  // namespace contactnn::contact
