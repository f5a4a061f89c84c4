// Every tolerance and limit of lib/search, with its default and the reason for it.
#pragma once

#include <cstddef>

namespace contactnn::search {

/// The range of each option (check_search_options refuses what lies outside; contactnn.h documents the same).
/// Each bound keeps one query's work bounded: at most kMaxIterations Newton steps (newton), at most
/// Method::kMaxSteps (newton:K, hybrids), each with at most kMaxHalvings halvings; and each real is finite,
/// so that no margin or tolerance makes every answer `ok` or every step converged.
inline constexpr int kMaxIterations = 1000;      ///< max_iterations in 1..1000, as Method::kMaxSteps
inline constexpr int kMaxHalvings = 60;          ///< max_halvings in 0..60: 2^-60 of a step is below rounding
inline constexpr double kMaxTolParam = 1.0;      ///< tol_param in [0, 1] parameter units
inline constexpr double kMaxDomainMargin = 1.0;  ///< domain_margin in [0, 1] parameter units
inline constexpr double kMaxBoxMargin = 1.0;     ///< gregory_box_margin, bilinear_box_margin in [0, 1] widths
inline constexpr double kMaxStepWidths = 1.0;    ///< max_step_widths in (0, 1] domain widths

struct SearchOptions {
  /// "newton" (to convergence): iteration limit. Quadratic convergence needs fewer than 10 steps from the
  /// centre on the paper's domains; 50 leaves room for slow cases without letting a divergent one run on.
  int max_iterations = 50;
  /// "newton": converged when the Newton step (max norm, parameter units) is at most this; the hybrids stop
  /// a lane early on the same test. 1e-10 of a domain width is far below any contact tolerance; tighter
  /// than rounding-level it would never be met on ill-conditioned segments.
  double tol_param = 1e-10;
  /// ok versus outside: a final point within this distance of the parameter domain (parameter units) is
  /// inside. The reference solver's domain_margin, so that statuses are comparable.
  double domain_margin = 1e-10;
  /// Hybrids on a Gregory patch: iterates stay in the domain enlarged by this many domain widths. 0: the
  /// segment itself, [0, 1]^2. Outside it the patch is an extrapolation whose rational interior points are
  /// singular on lines through the corners (SPEC 3); a network estimate a little beyond a corner (u + v
  /// near 0) gave Newton steps that walked away from the answer. Measured on 100000 held-out Gregory
  /// configurations (configs/gregory-random.toml, seed 202) with the shipped Neuro48, network+newton:3:
  /// mean |error| 4.7e-7 / 1.4e-6 and max 0.041 / 0.079 with the box [-0.1, 1.1]^2, 4.8e-8 / 1.8e-7 and
  /// 0.0035 / 0.0068 with [0, 1]^2. A node whose nearest point on the segment is on its boundary, the
  /// distance still falling outward, is reported outside at that boundary point (not at the extrapolated
  /// stationary point the reference solver reports).
  double gregory_box_margin = 0.0;
  /// Hybrids on a bilinear facet: [-1.5, 1.5]^2. The facet is defined everywhere, but a point more than a
  /// quarter width beyond an edge is no contact on this segment, and a warped quad's far stationary points
  /// (the other root, beyond the fold) lie further out: the box keeps a bad start from walking there.
  double bilinear_box_margin = 0.25;
  /// Hybrids: a Newton step longer than this many domain widths (max norm) is shortened to it before the
  /// box. Half a width: the start is already an estimate; a longer step means the quadratic model is not
  /// trusted (the reference solver's cap).
  double max_step_widths = 0.5;
  /// Hybrids: a step that does not reduce |S - P| is halved this many times before the lane stops with
  /// status no_convergence (keeping the previous iterate). Each halving costs one surface evaluation for the
  /// whole block, so only a few.
  int max_halvings = 3;
  /// Network methods: test each query against the network's training domain (status out_of_domain). A query
  /// on a tie averages the network over its canonical forms in the domain; without the test, over all of
  /// them.
  bool check_domain = true;
  /// The closest point of the whole face (SPEC 9): a query whose method answers `outside` is moved to the
  /// nearest point of its segment's boundary (edges and vertices), with status ok, its gap +-|S - P| and
  /// Results::location edge or vertex. Off: SPEC 2's stationary point outside the segment, as the labels of
  /// RAW.csv report it. A query answered inside pays one status test.
  bool closest_point_on_face = false;
  /// Below this many queries run() stays on the calling thread: an OpenMP region costs microseconds.
  std::size_t min_parallel_count = 512;
};

/// InvalidArgument naming the field, its value and its range for an option outside the ranges above (NaN and
/// infinities included): what LocalSearch, FaceSearch, the C interface and the tools refuse.
void check_search_options(const SearchOptions& options);

}  // namespace contactnn::search
