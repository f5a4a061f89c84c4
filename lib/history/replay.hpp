// A simulation replayed increment by increment (SPEC 10 histories): at every increment of a CalculiX result
// file, the contact pair's surface search done fresh and by tracking (contact/tracking.hpp), the local search
// of each method on the pairs inside faces, warm starts from the previous increment, and agreement with
// CalculiX's own contact output. What `replay` runs and reports.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "contact/narrow_phase.hpp"
#include "contact/surface_search.hpp"
#include "contact/tracking.hpp"
#include "io/frd_results.hpp"
#include "mesh/contact_model.hpp"
#include "search/network_model.hpp"

namespace contactnn::history {

struct ReplayOptions {
  int pair = 0;                   ///< SPEC 7's K
  contact::SearchOptions search;  ///< surface, capture distance (the surface search's)
  contact::TrackingOptions tracking;
  /// Cold local-search methods timed and judged on the pairs inside a segment face (lib/search names).
  std::vector<std::string> methods = {"newton:3", "newton:5", "closed_form", "closed_form+newton:2"};
  /// Warm starts: start+newton:K from the previous increment's point, for each K here, on the nodes that
  /// keep their face.
  std::vector<int> warm_steps = {0, 1, 2, 3};
  const search::NetworkModel* network = nullptr;  ///< for network methods (must outlive the replay)
  int repeats = 3;                                ///< timings: the fastest of this many runs of each call
  int threads = 1;                                ///< OpenMP threads of every timed phase
  /// Where search.narrow is not the reference: also the search as it was before the certificate
  /// (contact::NarrowPhase::kReference), fresh and tracked, timed in the same run, and its answers compared.
  bool beside_reference = true;
  /// The plan in the loop (issue 38): where set, the surface search is also run with this method on face
  /// interiors (SearchOptions::interior, contact/narrow_phase.hpp), fresh and tracked, timed in the same run,
  /// and its answers judged against the exact search's (PlanRow). Must outlive the replay.
  const contact::FaceLocator* plan = nullptr;
  std::string plan_label;    ///< how the report names it (e.g. "plan.toml: newton:2")
  double plan_target = 0.0;  ///< the plan's target (mean |error|, parameter units); 0: none
};

/// The plan's surface search at one increment against the exact search's answers (the same slave points).
struct PlanRow {
  double ns_fresh = 0.0;    ///< per slave node: the plan's fresh surface search
  double ns_tracked = 0.0;  ///< per slave node: the plan's tracked search
  long by_method = 0;       ///< slave points whose point the method gave (Contact::by_method)
  /// Slave points whose exact answer lies inside a face and whose point the exact answer gave all the same
  /// (the method refused the pair or put it outside the face: FaceLocator).
  long fallbacks = 0;
  long refused = 0;     ///< slave points the exact search answers and the plan's does not (must be 0)
  long other_face = 0;  ///< slave points the plan answers on another face than the exact search
  /// max(|d s|, |d t|) of the local coordinates against the exact point (parameter units, the face's own
  /// order), over the points the method gave; one domain width (2 bilinear and quad8, 1 Gregory and
  /// triangles) for a point on another face than the exact one.
  double mean_error = 0.0;
  double max_error = 0.0;
  /// |P - P_exact| / the face's size (its longest corner distance), over every slave point both answer.
  double mean_distance = 0.0;
  double max_distance = 0.0;
};

/// One method's local search on one increment's pairs inside faces.
struct MethodRow {
  std::string method;
  long queries = 0;
  double ns_per_query = 0.0;  ///< batched, the fastest of `repeats`
  double mean_error = 0.0;  ///< mean of max(|d xi|, |d eta|) against the surface search's point (local units)
  double max_error = 0.0;
  long failures = 0;  ///< status not ok / outside
};

/// Everything measured at one increment.
struct IncrementRow {
  int increment = 0;  ///< SPEC 10's N
  int step = 0;
  double time = 0.0;
  long slaves = 0;
  long found = 0;                   ///< slave nodes with a point
  std::array<long, 3> locations{};  ///< face, edge, vertex
  long faces_changed = 0;           ///< found nodes whose face differs from the previous increment's
  long tracking_differences = 0;    ///< nodes whose tracked face, point (1e-12 of its face) or gap differs
  std::vector<std::string> differences;  ///< the first few of them, each a Markdown table row (report.md)
  contact::TrackingCounts tracking;
  double ns_scene = 0.0;     ///< per slave node: the pair's nodes moved, node normals (RunStates::move_to)
  double ns_fresh = 0.0;     ///< per slave node: the fresh surface search
  double ns_tracked = 0.0;   ///< per slave node: the tracked search
  long reference_faces = 0;  ///< faces whose closest point needed the reference (no certificate)
  /// ReplayOptions::beside_reference: the reference search's times (0 when not run), and the nodes whose
  /// fresh answer differs from it (status, face, location; point or gap by more than 1e-10 of the face size).
  double ns_fresh_reference = 0.0;
  double ns_tracked_reference = 0.0;
  long reference_differences = 0;
  std::vector<MethodRow> methods;  ///< cold methods, then start+newton:K (warm, the kept faces only)
  long calculix_contacts = 0;  ///< the pair's slave nodes with COPEN < 0 in the file (-1: no CONTACT block)
  long calculix_found = 0;     ///< of those, with a point
  double calculix_largest_difference = 0.0;  ///< max |gap - COPEN| over those found
  PlanRow plan;                              ///< ReplayOptions::plan (zeros without one)
};

/// Replays every increment of `results` on pair options.pair of `model` (its states: RunStates, the scene
/// built once). `progress` (may be empty) is called after each increment with (done, total).
[[nodiscard]] std::vector<IncrementRow> replay(mesh::ContactModel model, const io::FrdResults& results,
                                               const ReplayOptions& options,
                                               const std::function<void(int, int)>& progress = {});

/// The plan's answers `plan` judged against the exact search's `exact` (the same slave points) on `master`
/// (PlanRow; its times are left 0). InvalidArgument if the sizes differ.
[[nodiscard]] PlanRow judge_plan(const mesh::SurfaceMesh& master, SurfaceKind surface,
                                 const std::vector<contact::Contact>& exact,
                                 const std::vector<contact::Contact>& plan);

/// report.md (summary and per-increment tables), increments.csv, and the SVG plots time.svg (ns per slave
/// node of each phase), error.svg (mean |error| of each method, log scale) and locations.svg (contacts by
/// location) in `directory` (created), each written atomically. `title` names the run (deck, pair, results
/// file).
void write_replay_report(const std::string& directory, const std::string& title, const ReplayOptions& options,
                         const std::vector<IncrementRow>& rows);

}  // namespace contactnn::history
