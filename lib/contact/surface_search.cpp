#include "contact/surface_search.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <nanoflann.hpp>
#include <optional>
#include <utility>

#include "contact/bilinear_certificate.hpp"
#include "contact/curved_certificate.hpp"
#include "contact/face_grid.hpp"
#include "contact/face_index.hpp"
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

namespace {

/// Distances within this fraction of the face size count as equal (SPEC 9's tie rule applies).
constexpr double kTieTolerance = 1e-12;
/// A list of a node's faces near it (NearFaces) reaches this fraction of a grid cell beyond its query; a list
/// cut short to the faces it holds, at least the second.
constexpr double kNearBudget = 1.0;
constexpr double kNearBudgetLeast = 0.1;

using CentreTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                       PointCloud, 3, std::uint32_t>;

using detail::closest_on_face;
using detail::face_configuration;
using detail::face_positions;
using detail::kind_of;
using detail::normal_on_edge;
using detail::weighted_corner_normal;

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

/// closest_on_face for face f of an indexed state: `checked` (the options with face_checked) where the index
/// checked the face, and its certificate where it has one. With options.interior, its method's point first
/// where it gives one within `capture` (narrow_phase.hpp; beyond, the face's exact point may still be
/// within).
projection::FaceClosestPoint closest_on_indexed_face(
    const mesh::SurfaceMesh& master, std::span<const Vec3> normals, const SearchOptions& options,
    const SearchOptions& checked, const FaceIndex& index, int f, const Vec3& slave,
    const std::array<double, 2>* start, int* reference_count, double capture, bool curved_convex = false) {
  if (options.interior != nullptr) {
    const auto p = options.interior->locate(master, normals, kind_of(master, options, f), f, slave);
    if (p && p->distance <= capture) return *p;
  }
  if (!index.triangles.empty() && master.face_type(f) == mesh::FaceType::kTri3)
    return projection::closest_point_on_prepared_triangle(index.triangles[static_cast<std::size_t>(f)],
                                                          slave);
  const SearchOptions& face_options = index.checked[static_cast<std::size_t>(f)] != 0 ? checked : options;
  return closest_on_face(master, normals, face_options, f, slave, certificate_of(index, f), start,
                         reference_count, curved_of(index, master, normals, options, f), curved_convex);
}

/// The largest float at most x (x >= 0: a positive float rounded up steps down by one in its last bit, as
/// std::nextafter towards 0, without its library call; NaN for NaN).
float float_below(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::bit_cast<float>(std::bit_cast<std::uint32_t>(f) - 1U) : f;
}

/// The squared distance from S to face f's box.
double box_squared(const FaceIndex& index, const Vec3& slave, std::size_t f) {
  const Vec3 outside = (index.box_lo[f] - slave).cwiseMax(slave - index.box_hi[f]).cwiseMax(Vec3::Zero());
  return outside.squaredNorm();
}

/// |S - c_f| - r_f, the distance to face f's box and (a triangle's) the distance beyond its edges' planes
/// (EdgePlanes), the largest (SurfaceSearcher::lower_bound; the sphere's is loose beside a flat face, the
/// box's tight beside an axis-aligned one, the planes' beside a triangle's edge), where it is at most
/// `reach`; otherwise some number above. `squared`: box_squared's. The box's squared distance is tested
/// first, with a relative slack far above its rounding: most faces a grid cell lists are then refused without
/// a square root, and every face within reach gets face_lower_bound's own bits. `distance`: sqrt(squared),
/// where the caller has it (negative: computed here).
double bound_within(const FaceIndex& index, const Vec3& slave, std::size_t f, double squared, double reach,
                    double distance = -1.0) {
  if (squared > reach * reach * (1.0 + 1e-12)) return std::numeric_limits<double>::infinity();
  double bound = std::max((slave - index.centres[f]).norm() - index.radii[f],
                          distance >= 0.0 ? distance : std::sqrt(squared));
  if (!index.planes.empty()) {
    // m_e.S rounded down by far more than its rounding (3 eps |S|_1, m_e a unit vector).
    const EdgePlanes& p = index.planes[f];
    const double slack = 1e-15 * slave.cwiseAbs().sum();
    for (std::size_t e = 0; e < 3; ++e) bound = std::max(bound, p.m[e].dot(slave) - p.h[e] - slack);
  }
  return bound;
}

/// bound_within with face f's box distance.
inline __attribute__((always_inline)) double face_bound_within(const FaceIndex& index, const Vec3& slave,
                                                               int face, double reach) {
  const auto f = static_cast<std::size_t>(face);
  return bound_within(index, slave, f, box_squared(index, slave, f), reach);
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

/// The answer's fields from the winning face's closest point `p` and the pseudo-normal direction `n` there
/// (step 4).
void report_best(Contact& best, const projection::FaceClosestPoint& p, const Vec3& n, const Vec3& slave) {
  best.status = PairStatus::kFound;
  best.location = p.location;
  best.point = p.point;
  best.iterations = p.iterations;
  best.param = p.param;
  best.by_method = p.by_method;
  const Vec3 d = slave - p.point;
  const double side = d.dot(n);
  best.gap = side < 0.0 ? -p.distance : p.distance;
  // The contact normal (Contact::normal): the face's at an interior point or where S is on the surface.
  best.normal = p.normal;
  if (best.location != Location::kFace && best.gap != 0.0) {
    const double length = d.norm();
    if (length > 0.0 && std::isfinite(length)) best.normal = (best.gap < 0.0 ? -d : d) / length;
  }
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
  report_best(best, best_point, pseudo_normal(master, normals, options, index, best.face, best_point), slave);
}

/// search_one's answer where its candidates are the known face alone and the known point lies inside that
/// face, within the capture distance: that point, reported without the scan (true); false otherwise (the
/// scan decides). A general test (every other candidate's bound beyond the point and its tie band) cost what
/// it saved on the large history.
bool known_alone(const KnownPoint* known, const std::vector<std::pair<double, int>>& candidates,
                 double capture, long slave_id, const Vec3& slave, Contact& best) {
  if (known == nullptr || candidates.size() != 1 || candidates[0].second != known->face) return false;
  const projection::FaceClosestPoint& p = known->point;
  if (p.status != Status::kOk || p.location != Location::kFace || !(p.distance <= capture) ||
      candidates[0].first > capture)
    return false;
  // Every field written (no construct_at first: its zero fill of the node's answer cost 2% of a tracked
  // search).
  best.slave_id = slave_id;
  best.reference_faces = known->reference_faces;
  best.face = known->face;
  best.candidates = 1;
  report_best(best, p, p.normal, slave);  // inside the face: its normal is the pseudo-normal
  return true;
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
  SearchOptions checked_options;   ///< options with projection.face_checked (FaceIndex::checked)
  std::optional<PointBox> region;  ///< the box of the points it is asked about (working units), if given
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

  /// Step 1 for a node with a list of its faces near it (NearFaces): the faces within `reach` of `slave`
  /// from the list where it covers the reach at the surface's drift `drift`; otherwise gathered from the grid
  /// over a larger radius, and the list made again from them.
  void collect_near(const Vec3& slave, double reach, double drift, NearFaces& near,
                    std::vector<std::pair<double, int>>& out) const {
    constexpr double kSlack = 1.0 + 1e-9;
    const auto within = [&](int face) {
      const double bound = face_bound_within(index, slave, face, reach);
      if (bound <= reach) out.emplace_back(bound, face);
    };
    // What the node's movement and the surface's drift have spent of the list's radius since it was made.
    const double spent = ((slave - near.anchor).norm() + (drift - near.drift)) * kSlack;
    if (near.radius >= 0.0F && spent + reach * kSlack <= static_cast<double>(near.radius)) {
      if (near.count > static_cast<int>(NearFaces::kCapacity)) {
        grid->for_faces_near(slave, reach, within);  // more faces near S than a list holds
        return;
      }
      // Each face's box is now at least its distance at the list, less what has been spent: the faces from
      // the first beyond the reach on are not near.
      for (int k = 0; k < near.count; ++k) {
        const auto u = static_cast<std::size_t>(k);
        if (static_cast<double>(near.bounds[u]) - spent > reach * kSlack) break;
        within(near.faces[u]);
      }
      return;
    }
    // A budget for the node's movement and the surface's drift before the list is made again: a grid cell
    // (half a face's box side, face_grid.hpp). The query over the larger radius reads a few cells more, once
    // for the states the list lasts: on the large history's tracked search, a tenth of a cell (twice what was
    // spent since, up to half a cell) made 22% of the lists again at each state, and took 1.2 times as long.
    const double radius = reach * kSlack + kNearBudget * grid->cell();
    const double squared = radius * radius * kSlack;
    std::size_t count = 0;
    // The nearest box (rounded down) of a face the list does not keep.
    float beyond = std::numeric_limits<float>::infinity();
    grid->for_faces_near(slave, radius, [&](int face) {
      const auto f = static_cast<std::size_t>(face);
      const double box = box_squared(index, slave, f);
      if (!(box <= squared)) return;
      // In increasing order of the box's distance (rounded down), by insertion: the kCapacity nearest.
      const double distance = std::sqrt(box);
      const float bound = float_below(distance * (1.0 - 1e-9));
      constexpr std::size_t kLast = NearFaces::kCapacity - 1;
      if (count < NearFaces::kCapacity || bound < near.bounds[kLast]) {
        std::size_t at = std::min(count, kLast);
        if (count > kLast) beyond = std::min(beyond, near.bounds[kLast]);
        for (; at > 0 && near.bounds[at - 1] > bound; --at) {
          near.bounds[at] = near.bounds[at - 1];
          near.faces[at] = near.faces[at - 1];
        }
        near.bounds[at] = bound;
        near.faces[at] = face;
      } else {
        beyond = std::min(beyond, bound);
      }
      ++count;
      const double within_bound = bound_within(index, slave, f, box, reach, distance);  // within(face)
      if (within_bound <= reach) out.emplace_back(within_bound, face);
    });
    float rounded = float_below(radius);
    if (!std::isfinite(rounded) || !std::isfinite(drift)) {
      near.radius = -1.0F;
      return;
    }
    // More faces than a list holds: it lists every face nearer than the nearest it leaves out (a shorter
    // radius), where that leaves at least kNearBudgetLeast of a cell beyond the reach; otherwise the grid
    // gathers the node's faces while the list's radius lasts.
    if (count > NearFaces::kCapacity &&
        static_cast<double>(beyond) >= reach * kSlack + kNearBudgetLeast * grid->cell()) {
      rounded = std::min(rounded, beyond);
      count = NearFaces::kCapacity;
    }
    near.count = static_cast<std::int32_t>(std::min(count, NearFaces::kCapacity + 1));
    near.anchor = slave;
    near.drift = drift;
    near.radius = rounded;
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
       double grid_margin_relative, std::shared_ptr<const NodeFaces>* topology, SearchStorage* kept_storage,
       const PointBox* queries)
      : unit(working_unit(m)),
        scaled(unit == 1.0 ? nullptr : std::make_unique<mesh::SurfaceMesh>(in_unit(m, unit))),
        master(scaled ? *scaled : m),
        normals(n),
        options(in_unit(o, unit)),
        checked_options(with_face_checked(options)),
        region(kept == nullptr && options.narrow != NarrowPhase::kReference && !options.brute_force_faces &&
                       queries != nullptr
                   ? std::optional<PointBox>(PointBox{queries->lo / unit, queries->hi / unit})
                   : std::nullopt),
        index(index_faces(master, n, options, topology,
                          kept_storage != nullptr ? std::move(kept_storage->tables().index) : FaceIndex{},
                          unit, kept_storage != nullptr && queries == nullptr, region ? &*region : nullptr)),

        largest_radius(index.radii.empty() ? 0.0 : *std::max_element(index.radii.begin(), index.radii.end())),
        largest_size(index.sizes.empty() ? 0.0 : *std::max_element(index.sizes.begin(), index.sizes.end())),
        cloud{&index.centres},
        storage(kept_storage) {
    // capture_distance's, from the sizes the index has computed (the same products, the same largest).
    capture =
        options.capture_distance > 0.0 ? options.capture_distance : options.capture_relative * largest_size;
    if (options.narrow != NarrowPhase::kReference && !options.brute_force_faces) {
      // A fresh search's own grid in the storage's memory (built again below).
      if (kept == nullptr && storage != nullptr) own_grid = std::move(storage->tables().grid);
      FaceGrid& g = kept != nullptr ? *kept : own_grid;
      // A kept grid holds the boxes it held at the last state where no box has changed since (the same
      // stamp).
      if (kept == nullptr || kept->unit() != unit ||
          !(kept->held() == index.generation || kept->holds(index.box_lo, index.box_hi))) {
        g.build(index.box_lo, index.box_hi, kept != nullptr ? grid_margin_relative * capture : 0.0, unit);
        grid_rebuilt = true;
      }
      g.held(index.generation);
      grid = &g;
    }
    if (unit == 1.0) return;
    for (const Vec3& c : index.centres) world_centres.push_back(c * unit);
    for (double r : index.radii) world_radii.push_back(r * unit);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (storage == nullptr) return;
    storage->tables().index = std::move(index);
    if (grid == &own_grid) storage->tables().grid = std::move(own_grid);
  }
};

SurfaceSearcher::SurfaceSearcher(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                                 const SearchOptions& options, FaceGrid* grid, double grid_margin_relative,
                                 std::shared_ptr<const NodeFaces>* topology, SearchStorage* storage,
                                 const PointBox* queries) {
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
  impl_ = std::make_unique<Impl>(master, master_normals, options, grid, grid_margin_relative, topology,
                                 storage, queries);
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

double SurfaceSearcher::box_drift() const { return impl_->index.box_drift; }

std::size_t SurfaceSearcher::faces_left_out() const { return impl_->index.left_out; }

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
                                    const FaceHint* hint, NearFaces* near, double drift) const {
  const Impl& m = *impl_;
  const Vec3 slave = m.unit == 1.0 ? world_slave : Vec3(world_slave / m.unit);  // exact either way
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
  // A hint that is not warm (a neighbouring node's face) is taken where S lies in its box (a search in the
  // slaves' order: the grid cell's faces cost 9% of a fresh search on the large history) or where S's own
  // cell lists no face.
  int nearest =
      hinted && (hint->warm || box_squared(m.index, slave, static_cast<std::size_t>(hint->face)) == 0.0)
          ? hint->face
          : m.grid->face_near(slave, m.index.centres, !hinted);
  if (nearest < 0 && hinted) nearest = hint->face;
  // Its distance d bounds the answer's: where the face has a certificate (or is a flat triangle), its closest
  // point, computed once and taken again by the scan; otherwise (a curved face's certificate included, where
  // it does not hold for S) its nearest corner (a point of the face), so that no reference projection is
  // spent on a face the scan may never reach.
  KnownPoint known;
  const KnownPoint* first = nullptr;
  double reach = m.capture;
  // A curved face's certificate holds for S (tested once: the projection is told).
  const CurvedCertificate* curved =
      nearest < 0 ? nullptr : curved_of(m.index, m.master, m.normals, m.options, nearest);
  const bool curved_convex = curved != nullptr && curved->convex_for(slave - curved->origin);
  const BilinearCertificate* certificate = nearest < 0 ? nullptr : certificate_of(m.index, nearest);
  const std::array<double, 2>* start = hinted && hint->warm ? &hint->param : nullptr;
  if (nearest < 0) {
    // No face in the cells around S: the scan gathers over the capture distance.
  } else if (m.options.interior == nullptr &&
             ((certificate != nullptr &&
               certificate->closest_point(slave, m.options.projection, start, known.point)) ||
              (curved_convex &&
               curved->closest_point(slave, m.options.projection, start, true, known.point)))) {
    // closest_on_indexed_face's first answer (a certificate's), written where it is kept. This repeats its
    // dispatch on purpose: the same answer through closest_on_indexed_face and closest_on_face with an
    // out-parameter measured 7% slower on the large history's tracked search (140 -> 151-156 ns, paired).
    known.face = nearest;
    first = &known;
    reach = std::min(reach, known.point.distance);
  } else if (m.options.interior == nullptr && !m.index.triangles.empty() &&
             m.master.face_type(nearest) == mesh::FaceType::kTri3) {
    // closest_on_indexed_face's answer of a prepared triangle, the same way.
    projection::closest_point_on_prepared_triangle(m.index.triangles[static_cast<std::size_t>(nearest)],
                                                   slave, known.point);
    known.face = nearest;
    first = &known;
    if (known.point.status == Status::kOk) reach = std::min(reach, known.point.distance);
  } else if (certificate != nullptr || curved_convex ||
             m.master.face_type(nearest) == mesh::FaceType::kTri3) {
    known.face = nearest;
    known.point = closest_on_indexed_face(m.master, m.normals, m.options, m.checked_options, m.index, nearest,
                                          slave, start, &known.reference_faces, m.capture, curved_convex);
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
  if (near != nullptr)
    m.collect_near(slave, reach, drift, *near, candidates);
  else
    m.collect(slave, reach, candidates, scratch, false);
  if (!known_alone(first, candidates, m.capture, slave_id, slave, contact)) {
    search_one(m.master, m.normals, m.options, m.checked_options, m.index, m.capture, slave_id, slave,
               candidates, nullptr, false, first, contact);
  }
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
                    const SearchOptions& options, std::vector<NodeSegmentPair>& pairs,
                    SearchStorage* storage) {
  std::vector<Contact> contacts;
  surface_search(master, master_normals, slave_ids, slave_positions, options, contacts, storage);
  to_pairs(master, master_normals, options, contacts, slave_positions, pairs);
}

void surface_search(const mesh::SurfaceMesh& master, std::span<const Vec3> master_normals,
                    std::span<const long> slave_ids, std::span<const Vec3> slave_positions,
                    const SearchOptions& options, std::vector<Contact>& contacts, SearchStorage* storage) {
  CONTACTNN_REQUIRE(slave_ids.size() == slave_positions.size(),
                    slave_ids.size() << " slave ids for " << slave_positions.size() << " positions");
  const auto n = static_cast<long>(slave_ids.size());
  // The slave nodes in Morton order (the search before the certificate, NarrowPhase::kReference, in theirs),
  // and their box: every query is a slave node's, so the faces beyond the capture distance of it are left
  // out.
  thread_local std::vector<std::uint32_t> order;
  thread_local std::vector<std::uint64_t> codes;
  PointBox box;
  const bool reference = options.narrow == NarrowPhase::kReference;
  if (reference) {
    CONTACTNN_REQUIRE(slave_ids.size() < (std::size_t{1} << 32), n << " slave nodes: at most 2^32 - 1");
    order.resize(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
  } else {
    spatial_order(slave_positions, order, codes, &box);
  }
  const SurfaceSearcher searcher(master, master_normals, options, nullptr, 0.0, nullptr,
                                 reference ? nullptr : storage, reference ? nullptr : &box);
  contacts.resize(static_cast<std::size_t>(n));
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
