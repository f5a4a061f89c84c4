#include "contact/face_index.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "contact/face_surface.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "geometry/quadratic_triangle.hpp"
#include "geometry/segment_checks.hpp"
#include "geometry/serendipity_quad.hpp"
#include "geometry/surface_of.hpp"

namespace contactnn::contact {

using detail::face_configuration;
using detail::face_positions;
using detail::kind_of;

SearchStorage::SearchStorage() : tables_(std::make_unique<Tables>()) {}
SearchStorage::~SearchStorage() = default;
SearchStorage::SearchStorage(const SearchStorage&) : SearchStorage() {}
SearchStorage& SearchStorage::operator=(const SearchStorage&) { return *this; }
SearchStorage::SearchStorage(SearchStorage&&) noexcept = default;
SearchStorage& SearchStorage::operator=(SearchStorage&&) noexcept = default;

namespace {

constexpr double kNoPlane = std::numeric_limits<double>::infinity();

/// Face f's prepared forms: its prepared triangle (tri3), whether its bilinear facet passes the reference's
/// checks and its certificate (bilinear quad4); a curved face's certificate forgotten (made again on its
/// next use).
void prepare_face(FaceIndex& index, const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                  const SearchOptions& options, int face, const mesh::FaceNodes& nodes) {
  const auto f = static_cast<std::size_t>(face);
  if (!index.curved.empty()) index.curved.forget(f);
  index.checked[f] = 0;
  if (nodes.type == mesh::FaceType::kTri3 && !index.triangles.empty())
    index.triangles.construct(f) = projection::prepare_triangle(detail::triangle_nodes(master, face));
  if (!index.bilinear.empty()) index.bilinear.construct(f);  // lambda_floor 0: no certificate
  if (nodes.type == mesh::FaceType::kQuad4 && kind_of(master, options, face) == SurfaceKind::kBilinear) {
    // closest_on_face's patch: the face's configuration relative to its first node, as the certificate
    // builds it (its patch and length; a face with a node that is not finite is not checked).
    const geometry::Configuration config = face_configuration(master, normals, SurfaceKind::kBilinear, face);
    const bool finite = std::all_of(config.nodes.begin(), config.nodes.end(),
                                    [&](const Vec3& x) { return (x - config.nodes[0]).allFinite(); });
    if (config.nodes[0].allFinite() && finite) {
      const BilinearCertificate c = BilinearCertificate::prepare(config.nodes);
      index.checked[f] = std::isfinite(c.length) && !geometry::is_degenerate_segment(c.patch.nodes()) ? 1 : 0;
      if (index.checked[f] != 0 && !index.bilinear.empty()) index.bilinear[f] = c;
    }
  }
}

/// Face f's centre (the mean of its corners) and size (the longest corner distance).
void face_extent(FaceIndex& index, const mesh::SurfaceMesh& master, int face) {
  const auto f = static_cast<std::size_t>(face);
  const std::span<const int> corners = master.face_corners(face);
  Vec3 centre = Vec3::Zero();
  for (int c : corners) centre += master.positions[static_cast<std::size_t>(c)];
  centre /= static_cast<double>(corners.size());
  double size = 0.0;  // squared until the end
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec3& x = master.positions[static_cast<std::size_t>(corners[i])];
    for (std::size_t j = i + 1; j < corners.size(); ++j)
      size = std::max(size, (x - master.positions[static_cast<std::size_t>(corners[j])]).squaredNorm());
  }
  index.centres[f] = centre;
  index.sizes[f] = std::sqrt(size);  // sqrt is monotonic: the same bits as the largest norm
}

/// A triangle's EdgePlanes from the points whose convex hull holds it, its corners first (a degenerate or
/// non-finite triangle: no planes, h infinite). h_e is rounded up by 1e-12 of the points' largest |P|_1, far
/// above the rounding of m_e.P (3 eps |P|_1; bound_within rounds m_e.S down alike).
EdgePlanes edge_planes(std::span<const Vec3> hull) {
  const EdgePlanes none{{}, {kNoPlane, kNoPlane, kNoPlane}};
  const Vec3 normal = (hull[1] - hull[0]).cross(hull[2] - hull[0]);
  double scale = 0.0;
  for (const Vec3& x : hull) scale = std::max(scale, x.cwiseAbs().sum());
  EdgePlanes planes;
  for (std::size_t e = 0; e < 3; ++e) {
    const Vec3 out = (hull[(e + 1) % 3] - hull[e]).cross(normal);
    const double length = out.norm();
    if (!(length > 0.0) || !std::isfinite(length)) return none;
    const Vec3 m = out * (1.0 / length);
    double h = -std::numeric_limits<double>::infinity();
    for (const Vec3& x : hull) h = std::max(h, m.dot(x));
    planes.m[e] = m;
    planes.h[e] = h + 1e-12 * scale;
  }
  return planes;
}

/// Face f's centre, sphere, box (of the points whose convex hull holds it: nodes, control points) and size.
void bound_face(FaceIndex& index, const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                const SearchOptions& options, int face, const mesh::FaceNodes& nodes) {
  const auto f = static_cast<std::size_t>(face);
  face_extent(index, master, face);
  const Vec3 centre = index.centres[f];
  double squared_radius = 0.0;
  // The bounding sphere and box of the points whose convex hull holds the face (nodes, control points).
  Vec3 box_lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 box_hi = -box_lo;
  const auto include = [&](const Vec3& x) {
    squared_radius = std::max(squared_radius, (x - centre).squaredNorm());
    box_lo = box_lo.cwiseMin(x);
    box_hi = box_hi.cwiseMax(x);
  };
  for (int c : nodes) include(master.positions[static_cast<std::size_t>(c)]);
  // A curved face lies in the convex hull of its control points, not of its nodes: the sphere holds those.
  if (nodes.type == mesh::FaceType::kQuad8) {
    const geometry::SerendipityQuad quad8(face_positions<8>(master, nodes));
    for (const Vec3& x : quad8.bezier_control_points()) include(x);
  } else if (nodes.type == mesh::FaceType::kTri6) {
    const geometry::QuadraticTriangle tri6(face_positions<6>(master, nodes));
    const std::array<Vec3, 6> hull = tri6.bezier_control_points();
    for (const Vec3& x : hull) include(x);
    if (!index.planes.empty()) index.planes[f] = edge_planes(hull);
  } else if (nodes.type == mesh::FaceType::kTri3) {
    if (!index.planes.empty())
      index.planes[f] = edge_planes(std::span<const Vec3>(detail::triangle_nodes(master, face)));
  } else if (master.face_corners(face).size() == 4 &&
             kind_of(master, options, face) == SurfaceKind::kGregory) {
    const geometry::Configuration config = face_configuration(master, normals, SurfaceKind::kGregory, face);
    std::array<Vec3, 4> unit;
    if (geometry::GregoryPatch::diagnose(config.nodes, config.normals, &unit) ==
        geometry::GregoryDefect::kNone) {
      // The patch lies in the convex hull of its control points (each interior point mixes two of them).
      for (const Vec3& x : geometry::GregoryPatch::control_points_of(config.nodes, unit)) include(x);
    }
  }
  if (!index.planes.empty() && nodes.type != mesh::FaceType::kTri3 && nodes.type != mesh::FaceType::kTri6)
    index.planes[f].h.fill(kNoPlane);
  index.radii[f] = std::sqrt(squared_radius);  // the largest distance: sqrt is monotonic
  index.box_lo[f] = box_lo;
  index.box_hi[f] = box_hi;
}

/// How far a Gregory patch's control points (GregoryPatch::control_points_of, SPEC 3) can lie from its nodes,
/// from the nodes and normals alone: L (2/3 + 11 rho / 9), L = `size` (the longest node distance,
/// face_extent's) and rho the largest ratio of the two edges at a node projected on its tangent plane (larger
/// over smaller); infinite where that ratio is not safely computed (an edge projected to less than 1e-6 L, a
/// normal's length out of range).
///   An edge point E(X->Y) = X + P_X (Y - X) / 3 lies within L / 3 of X. The interior point near X of edge XY
/// is E(X->Y) + b1, b1 = ((k0 + k1) a0 + k0 a3 + 2 h0 c1 + h1 c0) / 3 with unit a0, a3; |k0|, |k1| <= L / 3
/// (each the dot of a unit vector and an edge point's offset); |c0| <= L / 3, |c1| <= L + 2 L / 3; h0 =
/// c0.b0 / c0.c0, so |h0| <= |b0| / |c0|, the ratio of X's two projected edges, and |h1| likewise at Y. So
/// |b1| <= L (1 + 11 rho / 3) / 3, and the point lies within L / 3 + |b1| of X (the point near Y of Y alike).
/// The bound is returned with a relative slack of 1e-6 (the rounding of the points and of rho).
double gregory_reach(const geometry::Configuration& config, double size) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double longest = size * size;  // the face's size (face_extent): its longest node distance, squared
  double rho = 1.0;                    // squared
  for (int i = 0; i < 4; ++i) {
    const Vec3& n = config.normals[i];
    const double nn = n.squaredNorm();
    if (!(nn > 1e-150 && nn < 1e150)) return kInf;
    const Vec3 next = config.nodes[(i + 1) % 4] - config.nodes[i];
    const Vec3 prev = config.nodes[(i + 3) % 4] - config.nodes[i];
    const double a = (next - (n.dot(next) / nn) * n).squaredNorm();
    const double b = (prev - (n.dot(prev) / nn) * n).squaredNorm();
    const double small = std::min(a, b);
    if (!(small > 1e-12 * longest)) return kInf;
    rho = std::max(rho, std::max(a, b) / small);
  }
  const double reach = size * (2.0 / 3.0 + 11.0 / 9.0 * std::sqrt(rho)) * (1.0 + 1e-6);
  return std::isfinite(reach) ? reach : kInf;
}

/// Face f's centre and size, and a box of it that may be loose (the index's box_lo, box_hi; a face bound as
/// bound_face's otherwise): a Gregory patch's nodes' box widened by gregory_reach, with a slack for the
/// rounding of points far from the origin.
void loose_bound(FaceIndex& index, const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                 const SearchOptions& options, int face, const mesh::FaceNodes& nodes) {
  if (nodes.type != mesh::FaceType::kQuad4 || kind_of(master, options, face) != SurfaceKind::kGregory) {
    bound_face(index, master, normals, options, face, nodes);
    return;
  }
  const auto f = static_cast<std::size_t>(face);
  face_extent(index, master, face);
  const geometry::Configuration config = face_configuration(master, normals, SurfaceKind::kGregory, face);
  Vec3 lo = config.nodes[0], hi = config.nodes[0];
  for (const Vec3& x : config.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const double widen = gregory_reach(config, index.sizes[f]) +
                       1e-12 * (lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).maxCoeff() + index.sizes[f]);
  index.box_lo[f] = lo - Vec3::Constant(widen);
  index.box_hi[f] = hi + Vec3::Constant(widen);
}

/// Whether a face's box (finite) lies farther than `reach` from every point of `region`.
bool beyond(const Vec3& lo, const Vec3& hi, const PointBox& region, double reach) {
  if (!lo.allFinite() || !hi.allFinite()) return false;
  const Vec3 gap = (lo - region.hi).cwiseMax(region.lo - hi).cwiseMax(Vec3::Zero());
  return !(gap.squaredNorm() <= reach * reach);
}

/// How far a point's distance to a box can move when the box moves from [was_lo, was_hi] to [lo, hi]: the
/// norm of the largest movement of its bounds along each axis. A box that is not finite (its face never a
/// candidate) moving to another that is not costs nothing; one becoming finite, or ceasing to, is infinite.
double box_movement(const Vec3& was_lo, const Vec3& was_hi, const Vec3& lo, const Vec3& hi) {
  const bool was = was_lo.allFinite() && was_hi.allFinite(), is = lo.allFinite() && hi.allFinite();
  if (!was || !is) return was == is ? 0.0 : std::numeric_limits<double>::infinity();
  return (lo - was_lo).cwiseAbs().cwiseMax((hi - was_hi).cwiseAbs()).norm();
}

/// index_faces' faces, each on its own (threads for a large surface: the answers do not depend on them): the
/// faces with a `moved` node where the index is `kept`, else all; and the largest movement of a box since the
/// kept index (FaceIndex::box_drift).
void index_each(FaceIndex& index, const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                const SearchOptions& options, const std::vector<std::uint8_t>& moved, bool kept) {
  const std::size_t n = index.centres.size();
  double drift = 0.0;
#pragma omp parallel for reduction(max : drift) schedule(static) if (n >= 4096)
  for (std::size_t f = 0; f < n; ++f) {
    const auto face = static_cast<int>(f);
    const mesh::FaceNodes nodes = master.face_nodes(face);
    if (kept && std::none_of(nodes.begin(), nodes.end(),
                             [&](int c) { return moved[static_cast<std::size_t>(c)] != 0; }))
      continue;
    const Vec3 was_lo = kept ? index.box_lo[f] : Vec3::Zero(), was_hi = kept ? index.box_hi[f] : Vec3::Zero();
    prepare_face(index, master, normals, options, face, nodes);
    bound_face(index, master, normals, options, face, nodes);
    if (kept) drift = std::max(drift, box_movement(was_lo, was_hi, index.box_lo[f], index.box_hi[f]));
  }
  index.box_drift = kept ? drift * (1.0 + 1e-12) : std::numeric_limits<double>::infinity();
}

/// index_faces' faces with a `region`: each face's centre, size and a box of it (loose_bound), the capture
/// distance from the sizes (capture_distance's), then every face whose box lies beyond that distance of the
/// region left out (its box empty, its sphere 0, nothing prepared) and the others prepared and bound.
void index_region(FaceIndex& index, const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                  const SearchOptions& options, const PointBox& region) {
  const std::size_t n = index.centres.size();
  double largest = 0.0;
#pragma omp parallel for reduction(max : largest) schedule(static) if (n >= 4096)
  for (std::size_t f = 0; f < n; ++f) {
    const auto face = static_cast<int>(f);
    loose_bound(index, master, normals, options, face, master.face_nodes(face));
    largest = std::max(largest, index.sizes[f]);
  }
  const double capture =
      options.capture_distance > 0.0 ? options.capture_distance : options.capture_relative * largest;
  // Beyond the capture distance (with a slack far above bound_within's) no query point's reach finds a face.
  const double reach = capture * (1.0 + 1e-6);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::size_t left_out = 0;
#pragma omp parallel for reduction(+ : left_out) schedule(static) if (n >= 4096)
  for (std::size_t f = 0; f < n; ++f) {
    const auto face = static_cast<int>(f);
    if (beyond(index.box_lo[f], index.box_hi[f], region, reach)) {
      index.box_lo[f] = Vec3::Constant(kInf);
      index.box_hi[f] = Vec3::Constant(-kInf);
      index.radii[f] = 0.0;
      index.checked[f] = 0;
      ++left_out;
      continue;
    }
    const mesh::FaceNodes nodes = master.face_nodes(face);
    prepare_face(index, master, normals, options, face, nodes);
    if (nodes.type == mesh::FaceType::kQuad4 && kind_of(master, options, face) == SurfaceKind::kGregory)
      bound_face(index, master, normals, options, face, nodes);
  }
  index.left_out = left_out;
  index.box_drift = kInf;
}

}  // namespace

FaceIndex index_faces(const mesh::SurfaceMesh& master, std::span<const Vec3> normals,
                      const SearchOptions& options, std::shared_ptr<const NodeFaces>* topology,
                      FaceIndex&& recycled, double unit, bool keep, const PointBox* region) {
  FaceIndex index = std::move(recycled);  // its buffers: every moved face's entries rewritten below
  const auto n = static_cast<std::size_t>(master.face_count());
  index.centres.resize(n);
  index.radii.resize(n);
  index.box_lo.resize(n);
  index.box_hi.resize(n);
  index.sizes.resize(n);
  index.checked.resize(n);
  // The faces at each node: the kept ones where the connectivity has not changed (the caller's, else the
  // recycled index's).
  const bool same_faces = topology != nullptr && *topology != nullptr && (*topology)->matches(master);
  if (same_faces) {
    index.topology = *topology;
  } else if (topology == nullptr && index.topology != nullptr && index.topology->matches(master)) {
    // kept as it is
  } else {
    index.topology = std::make_shared<const NodeFaces>(master);
    if (topology != nullptr) *topology = index.topology;
  }
  // The nodes that moved since the kept index was built (all of them without one): a face with none keeps
  // its entries, bit for bit what they would be computed again.
  const std::size_t node_count = master.positions.size();
  const bool gregory = options.surface == SurfaceKind::kGregory && normals.size() == node_count;
  const bool kept = keep && same_faces && index.built_unit == unit &&
                    index.built_positions.size() == node_count &&
                    (!gregory || index.built_normals.size() == node_count);
  // A kept index's positions and normals become this state's here (where keep asks for them again).
  std::vector<std::uint8_t> moved(node_count, 1);
  bool any_moved = !kept;
  if (kept) {
#pragma omp parallel for reduction(|| : any_moved) schedule(static) if (node_count >= 16384)
    for (std::size_t i = 0; i < node_count; ++i) {
      moved[i] = !(master.positions[i] == index.built_positions[i]) ||
                 (gregory && !(normals[i] == index.built_normals[i]));
      if (moved[i] == 0) continue;
      any_moved = true;
      index.built_positions[i] = master.positions[i];
      if (gregory) index.built_normals[i] = normals[i];
    }
  }
  // Slots for bilinear certificates, prepared triangles and curved certificates where the surface has such
  // faces (a Gregory surface constructs no bilinear slot: 29 MB a state for 1e5 faces, every page touched).
  bool any_bilinear = false, any_triangle = false, any_curved = false, any_tri6 = false;
#pragma omp parallel for reduction(||                                                  \
                                   : any_bilinear, any_triangle, any_curved, any_tri6) \
    schedule(static) if (n >= 16384)
  for (std::size_t f = 0; f < n; ++f) {
    const mesh::FaceType type = master.face_type(static_cast<int>(f));
    const bool quad4 = type == mesh::FaceType::kQuad4;
    const bool gregory_face = quad4 && kind_of(master, options, static_cast<int>(f)) == SurfaceKind::kGregory;
    any_bilinear = any_bilinear || (quad4 && !gregory_face);
    any_triangle = any_triangle || type == mesh::FaceType::kTri3;
    any_tri6 = any_tri6 || type == mesh::FaceType::kTri6;
    any_curved =
        any_curved || type == mesh::FaceType::kQuad8 || type == mesh::FaceType::kTri6 || gregory_face;
  }
  const bool certified = options.narrow == NarrowPhase::kCertified;
  index.bilinear.reset(certified && any_bilinear ? n : 0);
  index.triangles.reset(certified && any_triangle ? n : 0);
  index.planes.resize(certified && (any_triangle || any_tri6) ? n : 0);
  if (kept) {
    index.curved.keep(certified && any_curved ? n : 0);
  } else {
    index.curved.reset(certified && any_curved ? n : 0);
  }
  index.left_out = 0;
  if (region != nullptr && !keep) {
    index_region(index, master, normals, options, *region);
  } else if (any_moved) {
    index_each(index, master, normals, options, moved, kept);
  } else {
    index.box_drift = 0.0;  // kept, and no node has moved: every face's entries stay
  }
  // A new stamp where a box may have changed (FaceGrid::held).
  static std::atomic<std::uint64_t> stamps{0};
  if (any_moved) index.generation = stamps.fetch_add(1, std::memory_order_relaxed) + 1;
  if (keep && !kept) {
    // This state's positions and normals, copied in parallel (the tables are kept: resize allocates once).
    index.built_positions.resize(node_count);
    index.built_normals.resize(gregory ? node_count : 0);
#pragma omp parallel for schedule(static) if (node_count >= 16384)
    for (std::size_t i = 0; i < node_count; ++i) {
      index.built_positions[i] = master.positions[i];
      if (gregory) index.built_normals[i] = normals[i];
    }
    index.built_unit = unit;
  } else if (keep) {
    index.built_unit = unit;
  } else {
    index.built_unit = 0.0;
  }
  return index;
}

[[nodiscard]] const CurvedCertificate* curved_of(const FaceIndex& index, const mesh::SurfaceMesh& master,
                                                 std::span<const Vec3> normals, const SearchOptions& options,
                                                 int face) {
  if (index.curved.empty()) return nullptr;
  const mesh::FaceType type = master.face_type(face);
  const bool gregory =
      type == mesh::FaceType::kQuad4 && kind_of(master, options, face) == SurfaceKind::kGregory;
  if (type != mesh::FaceType::kQuad8 && type != mesh::FaceType::kTri6 && !gregory) return nullptr;
  const CurvedCertificate& c =
      index.curved.get(static_cast<std::size_t>(face), [&](CurvedCertificate& out, void* room) {
        const mesh::FaceNodes nodes = master.face_nodes(face);
        if (type == mesh::FaceType::kQuad8) {
          out = CurvedCertificate::prepare(geometry::SerendipityQuad(face_positions<8>(master, nodes)));
        } else if (type == mesh::FaceType::kTri6) {
          out = CurvedCertificate::prepare(geometry::QuadraticTriangle(face_positions<6>(master, nodes)));
        } else {
          const geometry::Configuration config =
              face_configuration(master, normals, SurfaceKind::kGregory, face);
          if (!geometry::surface_defect(config, SurfaceKind::kGregory))
            CurvedCertificate::prepare_gregory(out, room, config.nodes, config.normals);
        }
      });
  return c.lambda_floor > 0.0 ? &c : nullptr;
}

}  // namespace contactnn::contact
