// Step 7 of the scene study (scene_study.hpp): everything the report shows (SceneStudyResult), the pairs'
// errors of every measured method, the plan file's content (io/plan_file.hpp) and the report as Markdown
// (report.md) and JSON (report.json, what scripts/scene-table reads).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "eval/accuracy.hpp"
#include "io/plan_file.hpp"
#include "study/method_measurement.hpp"
#include "study/node_orders.hpp"
#include "study/scene_networks.hpp"
#include "study/scene_pairs.hpp"
#include "study/scene_study.hpp"

namespace contactnn::study {

/// Everything the report shows.
struct SceneStudyResult {
  std::string deck;
  int pair = 0;
  SurfaceKind surface = SurfaceKind::kBilinear;
  SceneStudyOptions options;  ///< resolved
  std::string command_line;
  std::size_t slave_nodes = 0;
  long no_segment = 0;
  std::array<long, 3> locations{};
  long quad4 = 0;
  double deck_offset = 0.0;
  dataset::SceneDomainOptions domain;
  std::int64_t heldout_rows = 0;
  std::uint64_t heldout_seed = 0;
  std::vector<std::string> not_trained;  ///< sizes_that_may_pay's reasons
  NetworkTraining training;
  std::vector<MethodMeasurement> measured;  ///< on the held-out sample
  std::size_t chosen = 0;                   ///< index in `measured`
  /// The same methods on the face pairs and on every quad4 pair (same order as `measured`; empty without
  /// pairs).
  std::vector<eval::MethodErrors> face_errors, quad4_errors;
  NodeOrderCheck node_orders;
  double seconds_to_plan = 0.0;
  double seconds = 0.0;
  /// With --results (scene_history.hpp): the results file, its increments, and the history's report section
  /// (Markdown) and summary (a JSON object), appended to report.md and report.json; empty without.
  std::string results;
  int history_increments = 0;
  std::string history_markdown, history_json;
  [[nodiscard]] const MethodMeasurement& plan() const { return measured[chosen]; }
  /// The method's errors on the face pairs meet the target (max mean |error| <= target, no failure); true
  /// when there is no face pair.
  [[nodiscard]] bool plan_meets_target_on_pairs() const;
};

/// The pairs' errors of every measured method (face and quad4 sets; accuracy only).
void judge_on_pairs(const ScenePairs& pairs, SurfaceKind surface,
                    const std::vector<const SceneNetwork*>& networks, SceneStudyResult& result);

/// The plan file's content for `result`: its chosen method, `network_file` (relative to the plan; empty for
/// none) and every measurement.
[[nodiscard]] io::ScenePlan make_plan(const SceneStudyResult& result, const std::string& network_file);

[[nodiscard]] std::string report_markdown(const SceneStudyResult& result);
/// The summary scripts/scene-table reads (report.json).
[[nodiscard]] std::string report_json(const SceneStudyResult& result);

}  // namespace contactnn::study
