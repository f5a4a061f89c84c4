// A local-search method by name: where the iteration starts (the segment centre, a network's estimate, the
// bilinear closed form or the caller's own start) and how many Newton steps follow; or four_triangles, a
// search of its own without iteration.
#pragma once

#include <string>
#include <string_view>

namespace contactnn::search {

/// The methods of lib/search and their names (Method::parse, Method::name):
///   "network"               the network's estimate alone
///   "newton:K"              K plain Newton steps from the domain centre (K >= 0; an FE code's lean Newton)
///   "newton"                plain Newton from the centre until the step is below SearchOptions::tol_param
///   "closed_form"           projection on the bilinear facet's centre plane and the inverse bilinear map; on
///   a
///                           Gregory patch, of the facet of its corner nodes (a start, exact only where flat)
///   "network+newton:K"      the network's estimate, then K safeguarded Newton steps (K >= 0)
///   "closed_form+newton:K"  the closed form, then K safeguarded Newton steps (K >= 0)
///   "start+newton:K"        the caller's start (the param array on input: an FE code's local coordinates of
///                           the same pair at the previous time step), then K safeguarded Newton steps (K >=
///                           0)
///   "four_triangles"        after OpenRadioss's type 7 contact (engine/source/interfaces/int07/i7dst3.F):
///   the
///                           quad split about its centroid O = (A + B + C + D) / 4 into the triangles ABO,
///                           BCO, CDO, DAO, S's exact closest point on each (interior, edge or vertex), the
///                           nearest kept (ties: the first in that order); closed form, no iteration.
///                           Bilinear segments only. A different surface from the bilinear facet (the same
///                           where the segment is a flat parallelogram): its (xi, eta) are those of the point
///                           in the piecewise-linear parametrisation of the four triangles (the nodes at
///                           their corners of [-1, 1]^2, O at (0, 0)), always in [-1, 1]^2; LocalSearch::run
///                           gives its statuses and gap
/// K is at most kMaxSteps (1000) in every form: beyond it a fixed step count is a mistake, not a method
/// (newton:K at K = 1e8 took 1.1 s per query), and "newton" iterates to convergence. A start followed by ":0"
/// steps is the start alone: parse("network+newton:0") == parse("network"), and name() gives the short form,
/// so parse(m.name()) == m for every method parse returns.
struct Method {
  /// kFourTriangles: not a start, the search itself (newton_steps 0; LocalSearch refuses other counts).
  enum class Start { kCentre, kNetwork, kClosedForm, kGiven, kFourTriangles };
  /// The largest K of "...newton:K" that parse accepts (and LocalSearch).
  static constexpr int kMaxSteps = 1000;
  Start start = Start::kCentre;
  int newton_steps = 5;         ///< fixed Newton steps after the start (0 when to_convergence)
  bool to_convergence = false;  ///< kCentre only: iterate until converged (SearchOptions::max_iterations)

  /// Throws InvalidArgument naming the accepted forms for anything else (an unknown start, a missing or
  /// negative or non-numeric K, K above kMaxSteps, trailing characters, "network+newton" without K, Newton
  /// steps after four_triangles).
  [[nodiscard]] static Method parse(std::string_view name);
  [[nodiscard]] std::string name() const;
  /// True when the method needs a NetworkModel.
  [[nodiscard]] bool needs_network() const { return start == Start::kNetwork; }
  /// True when the method reads its starts from the caller (LocalSearch::run's param, on input).
  [[nodiscard]] bool needs_start() const { return start == Start::kGiven; }
  /// True when Newton steps follow a network, closed-form or given start (they are safeguarded).
  [[nodiscard]] bool is_hybrid() const { return start != Start::kCentre && newton_steps > 0; }

  friend bool operator==(const Method&, const Method&) = default;
};

}  // namespace contactnn::search
