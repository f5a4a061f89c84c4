// A local-search method by name: where the iteration starts (the segment centre, a network's estimate, the
// bilinear closed form or the caller's own start) and how many Newton steps follow.
#pragma once

#include <string>
#include <string_view>

namespace contactnn::search {

/// The methods of lib/search and their names (Method::parse, Method::name):
///   "network"               the network's estimate alone
///   "newton:K"              K plain Newton steps from the domain centre (K >= 0; an FE code's lean Newton)
///   "newton"                plain Newton from the centre until the step is below SearchOptions::tol_param
///   "closed_form"           projection on the bilinear facet's centre plane and the inverse bilinear map; on a
///                           Gregory patch, of the facet of its corner nodes (a start, exact only where flat)
///   "network+newton:K"      the network's estimate, then K safeguarded Newton steps (K >= 0)
///   "closed_form+newton:K"  the closed form, then K safeguarded Newton steps (K >= 0)
///   "start+newton:K"        the caller's start (the param array on input: an FE code's local coordinates of
///                           the same pair at the previous time step), then K safeguarded Newton steps (K >= 0)
/// A start followed by ":0" steps is the start alone: parse("network+newton:0") == parse("network"), and name()
/// gives the short form, so parse(m.name()) == m for every method parse returns.
struct Method {
  enum class Start { kCentre, kNetwork, kClosedForm, kGiven };
  Start start = Start::kCentre;
  int newton_steps = 5;         ///< fixed Newton steps after the start (0 when to_convergence)
  bool to_convergence = false;  ///< kCentre only: iterate until converged (SearchOptions::max_iterations)

  /// Throws InvalidArgument naming the accepted forms for anything else (an unknown start, a missing or
  /// negative or non-numeric K, trailing characters, "network+newton" without K).
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
