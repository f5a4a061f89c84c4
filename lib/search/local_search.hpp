// The run-time local search (paper Sections 2-4; SPEC 2, 4, 8): for batches of slave-node / master-segment
// pairs in world coordinates, the local coordinates of the closest point, the gap, a status and the Newton
// steps taken, by one Method. What an FE code links (contactnn::search): no HDF5, no CLI, no training code.
//
// Queries are processed in blocks of block_size() (structure of arrays inside a block; the loops over the
// block's lanes vectorise), blocks in parallel with OpenMP. Every query's result depends on that query only:
// it is bit for bit the same for any count, position in the batch, block and thread count (a query outside a
// whole block runs the same code one lane wide; the tests compare both).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "core/conventions.hpp"
#include "search/method.hpp"
#include "search/network_model.hpp"
#include "search/search_options.hpp"

namespace contactnn::search {

/// Where run() writes, for `count` queries (any pointer marked optional may be nullptr: not computed).
template <class Real>
struct Results {
  /// count x 2: (xi, eta) for bilinear, (u, v) for Gregory, in the caller's own node order (start+newton:K
  /// reads it first: each query's start). Finite for every status: the estimate for ok, outside,
  /// no_convergence, degenerate (Newton: the last iterate before the failure) and out_of_domain (the
  /// network's extrapolation); the domain centre for invalid and, network methods, degenerate.
  Real* param = nullptr;
  /// count (optional): g = n.(S - P) at the reported point, n the unit normal P_s x P_t of the caller's own
  /// parametrisation (SPEC 2), world units; < 0 is penetration. 0 where the status is invalid or degenerate
  /// or the normal vanishes there. For a network, at its estimate (for Gregory this builds the patch). Real =
  /// float: a gap beyond the float range is the largest float of its sign. four_triangles: +-|S - P| for its
  /// own point P on the four triangles, the sign of (S - P) . (C - A) x (D - B) (see LocalSearch::run).
  Real* gap = nullptr;
  /// count: ok, outside, no_convergence, degenerate, invalid, out_of_domain (see LocalSearch::run).
  Status* status = nullptr;
  /// count (optional): Newton steps taken (0 for network, closed_form and four_triangles).
  std::int32_t* iterations = nullptr;
  /// count (optional): where the reported point lies on the segment: face for status ok, edge or vertex for a
  /// point SearchOptions::closest_point_on_face moved to the boundary; face also for the other statuses
  /// (whose point is not on the segment: read the status).
  Location* location = nullptr;
};

namespace detail {
struct Plan;
}

/// One method on one surface kind, with its options and (network methods) its network, fixed at construction;
/// run() is const and may be called from several threads at once.
class LocalSearch {
 public:
  /// Throws InvalidArgument for a network method without `network` or with a network of another surface kind,
  /// a step count below 0 or above Method::kMaxSteps, four_triangles on Gregory segments or with Newton
  /// steps, or options out of range (max_iterations < 1, tol_param or domain_margin < 0, box margins < 0,
  /// max_step_widths <= 0, max_halvings < 0). `network` must outlive this object.
  LocalSearch(SurfaceKind kind, Method method, SearchOptions options = {},
              const NetworkModel* network = nullptr);

  /// Runs the method on `count` queries: `raw` holds count rows of 15 (bilinear) or 27 (Gregory) values in
  /// the order of SPEC 6: ax ay az bx by bz cx cy cz dx dy dz sx sy sz, then nax ... ndz (node normals, any
  /// positive length). Real is float or double (inputs and outputs); the geometry is computed in double, a
  /// network in its own real type. `threads` <= 0: OpenMP's default; below options().min_parallel_count
  /// queries no parallel region is opened. No allocation. `out` by reference: five pointers passed by value
  /// went through the stack, stored one by one and read back two at a time (a stalled store forward in every
  /// call).
  ///
  /// Statuses by method:
  ///  - network: ok; out_of_domain (the canonical configuration is outside the network's training domain;
  ///    the estimate is still reported); degenerate (no canonical frame: a collapsed segment, a straight
  ///    angle at the canonical corner A, Gregory normals in the segment's plane or on both sides); invalid (a
  ///    non-finite input).
  ///  - newton:K: after K undamped steps from the centre, ok or outside by the domain enlarged by
  ///    domain_margin; degenerate (a collapsed bilinear segment as the labels judge it: coincident nodes,
  ///    zero area, a corner of zero angle; a Gregory patch that does not exist; a singular step),
  ///    no_convergence (a non-finite step); both keep the last iterate. invalid for a non-finite input.
  ///  - newton: as newton:K, iterating until the step is at most tol_param; no_convergence after
  ///  max_iterations.
  ///  - closed_form: ok or outside; no_convergence where the projected point lies beyond the fold of the
  ///    bilinear map (the estimate is still reported); degenerate (no plane, or a collapsed segment as for
  ///    newton:K; on a Gregory patch also a patch that does not exist); invalid. On a Gregory patch it is the
  ///    closed form of the bilinear facet of the corner nodes, (u, v) = ((xi + 1) / 2, (eta + 1) / 2): an
  ///    estimate, exact only where the patch is that facet.
  ///  - network+newton:K, closed_form+newton:K: the start, then K safeguarded steps (box, step cap,
  ///    halving): ok or outside; no_convergence when a step does not reduce |S - P| after max_halvings
  ///    halvings (the previous iterate is kept) or the iterate ends on the box's edge beyond the domain.
  ///    Where the box is the domain (the Gregory default), an iterate held on its edge is outside when |S -
  ///    P| still falls outward there (the edge point is reported, not the stationary point beyond it), else
  ///    ok; degenerate (a collapsed segment, both Newton systems singular, or no Gregory patch); invalid. A
  ///    network start without a canonical frame (e.g. a straight angle at the canonical corner) is refined
  ///    from the centre; an out_of_domain estimate is refined from itself, and where that refinement fails,
  ///    again from the centre (its steps add up).
  ///  - four_triangles (bilinear only; Method lists its construction, after OpenRadioss's i7dst3.F): the
  ///  nearest
  ///    point P of the four triangles ABO, BCO, CDO, DAO about the centroid O, exact, no iteration, reported
  ///    in the triangles' piecewise-linear parametrisation, so always in [-1, 1]^2. ok where P is inside the
  ///    quad or S projects onto its boundary point; outside where P lies on the quad's outer boundary (an
  ///    edge AB, BC, CD, DA or a corner) and S does not project onto it: the projection of S on the plane of
  ///    P's triangle, in that triangle's parametrisation extended over its plane, lies more than
  ///    domain_margin (max norm) from P's (xi, eta). (A triangle of no area, |n|^2 <= 1e-24 |e1|^2 |e2|^2,
  ///    has no interior and no plane: a point it gives is ok.) degenerate for a collapsed segment as for
  ///    newton:K; invalid for a non-finite input. The gap is +-|S - P|, negative where (S - P) . (C - A) x (D
  ///    - B) < 0: that vector, the sum of the four triangles' area vectors, orients the segment as P_xi x
  ///    P_eta does (OpenRadioss's type 7 is two-sided and its penetration unsigned). On a flat parallelogram
  ///    P and (xi, eta) are the bilinear facet's closest point for S inside, and the gap is the facet's;
  ///    elsewhere it is another surface (through the same four nodes and the same centre, flat between them).
  ///  - start+newton:K: as the hybrids, from the caller's start, which run() reads from out.param (each
  ///    query's row before it writes it): an FE code's local coordinates of the pair at the previous time
  ///    step. invalid also for a start that is not finite. On a Gregory patch a failed refinement (or one
  ///    ending outside) is tried again from the centre, as a network's. "start" (K = 0): the start itself,
  ///    ok or outside, with its gap.
  template <class Real>
  void run(std::size_t count, const Real* raw, const Results<Real>& out, int threads = 0) const;

  [[nodiscard]] SurfaceKind surface() const;
  [[nodiscard]] const Method& method() const;
  [[nodiscard]] const SearchOptions& options() const;
  [[nodiscard]] const NetworkModel* network() const;
  /// Queries per block of the batched path (32 or 16, by method; see search_kernel.hpp).
  [[nodiscard]] int block_size() const;
  /// Values per query in `raw`: 15 or 27.
  [[nodiscard]] static constexpr int raw_columns(SurfaceKind kind) {
    return kind == SurfaceKind::kBilinear ? 15 : 27;
  }

 private:
  std::shared_ptr<const detail::Plan> plan_;
};

}  // namespace contactnn::search
