// The run-time local search on the face types of SPEC 9 beside the 4-node quad of LocalSearch: the flat
// triangle (tri3), the 6-node quadratic triangle (tri6) and the 8-node serendipity quad (quad8). For batches
// of slave-node / face pairs in world coordinates: the local coordinates of the closest point, the gap, a
// status and the Newton steps taken, by one Method. Blocks of queries as structures of arrays (the loops over
// a block's lanes vectorise), blocks in parallel with OpenMP; no allocation in run().
//
// The methods (Method's names; docs/library.md "Faces" has the table of what each face type takes):
//   tri3:       closed_form is exact (the projection on the triangle's plane, a 2 x 2 solve): no iteration
//               and no network is needed. The Newton methods are accepted (one step from anywhere is exact).
//   tri6/quad8: newton:K and newton from the face's centre; closed_form, the estimate of the corner facet
//   (the
//               corner triangle's projection; the quad's corners as a bilinear facet, LocalSearch's closed
//               form on them); closed_form+newton:K and start+newton:K (safeguarded steps, as LocalSearch's
//               hybrids); network and network+newton:K with a FaceNetwork of the face type
//               (face_network.hpp).
// Statuses and gaps follow LocalSearch::run (SPEC 2): ok or outside by the face's domain enlarged by
// SearchOptions::domain_margin; degenerate for a collapsed face (coincident corners, no area, a corner of
// zero angle); no_convergence; invalid for a non-finite input; out_of_domain for a network's query outside
// its training domain. The gap is n.(S - P) with n the unit P_s x P_t of the face's own parametrisation (its
// node order, SPEC 9), in world units, and never larger than S's distance to the face's nearest node. Every
// method computes in the caller's node order: near the face every order gives the same point to rounding; a
// slave far from a curved face may reach another stationary point of the extrapolated surface in another
// order (docs/library.md "Faces").
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

#include "core/conventions.hpp"
#include "search/local_search.hpp"
#include "search/method.hpp"
#include "search/search_options.hpp"

namespace contactnn::search {

/// The face types of FaceSearch (SPEC 9's node order and local coordinates): tri3 and tri6 in (r, s), r, s >=
/// 0, r + s <= 1, corner 1 at (0, 0), 2 at (1, 0), 3 at (0, 1), then (tri6) the mid-side nodes of edges 1-2,
/// 2-3, 3-1; quad8 in (xi, eta) in [-1, 1]^2, corners as SPEC 1, then the mid-side nodes of edges 1-2, 2-3,
/// 3-4, 4-1.
enum class FaceKind : std::uint8_t { kTri3 = 0, kTri6 = 1, kQuad8 = 2 };

/// "tri3", "tri6", "quad8".
[[nodiscard]] std::string_view to_string(FaceKind kind);
/// The inverse of to_string; InvalidArgument naming the three otherwise.
[[nodiscard]] FaceKind face_kind_from_string(std::string_view name);
/// Nodes of a face: 3, 6 or 8.
[[nodiscard]] constexpr int face_node_count(FaceKind kind) {
  return kind == FaceKind::kTri3 ? 3 : (kind == FaceKind::kTri6 ? 6 : 8);
}
/// Values per query in FaceSearch::run's raw rows: the nodes' x, y, z in the face's order, then S's: 12,
/// 21, 27.
[[nodiscard]] constexpr int face_raw_columns(FaceKind kind) { return 3 * face_node_count(kind) + 3; }

class FaceNetwork;

namespace detail {
struct FacePlan;
}

/// One method on one face type, with its options and (network methods) its network, fixed at construction;
/// run() is const and may be called from several threads at once.
class FaceSearch {
 public:
  /// Throws InvalidArgument for four_triangles (a quad4 method), a network method on tri3 (the closed form is
  /// exact there) or without a network of the face type, and options out of range as LocalSearch's. `network`
  /// must outlive this object.
  FaceSearch(FaceKind kind, Method method, SearchOptions options = {}, const FaceNetwork* network = nullptr);

  /// Runs the method on `count` queries: `raw` holds count rows of face_raw_columns(kind) values (the nodes'
  /// coordinates in the face's order, then S's). Real is float or double; the geometry is computed in double.
  /// `threads` <= 0: OpenMP's default. out.param, out.status must not be null; start+newton:K reads its
  /// starts from out.param. SearchOptions::closest_point_on_face moves an answer outside the face to the
  /// nearest point of its boundary (the curved edges of tri6 and quad8 included), status ok, location edge or
  /// vertex, gap
  /// +-|S - P| signed by the face normal at P.
  template <class Real>
  void run(std::size_t count, const Real* raw, const Results<Real>& out, int threads = 0) const;

  [[nodiscard]] FaceKind face() const;
  [[nodiscard]] const Method& method() const;
  [[nodiscard]] const SearchOptions& options() const;
  [[nodiscard]] int block_size() const;

 private:
  std::shared_ptr<const detail::FacePlan> plan_;
};

}  // namespace contactnn::search
