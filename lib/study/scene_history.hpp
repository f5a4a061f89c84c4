// A scene over its history (issue 29, item 2): the scene study's networks and its plan judged on every
// increment of a solver's run (SPEC 10), and the states whose union is the domain a network trained for the
// whole history is drawn from.
//
// scene-study --results RUN.frd reads the results once, walks the pair's states (history::RunStates: the
// scene built once from the deck, its nodes moved to each increment: the node block's coordinates plus the
// increment's DISP, as gen-configs --results and replay move them; history_states), and after the study
// judges on each increment's pairs inside a 4-node quadrilateral face (the surface search of SPEC 9, labelled
// by the reference):
//  - every scene network alone ("network[16-32-2]") and the plan's method;
//  - per increment: the mean |error| of each local coordinate (xi units for bilinear, u units for Gregory),
//    the largest |error|, failures (eval::compare_with_labels), and the fraction of those pairs outside the
//    training domain of the method's network (the network alone's out_of_domain status, SearchOptions::
//    check_domain); a method without a network has no domain ("-");
//  - the plan's method in the surface search, as replay --plan runs it (SearchOptions::interior: a
//    contact::FaceLocator of the plan's method and network, on every face interior of every slave node),
//    judged against the exact search by history::judge_plan: the slave points whose point the method gave,
//    the fallbacks (an exact answer inside a face whose point the method did not give: refused or outside
//    the face) and the refused (a slave point the exact search answers and the plan's does not; 0 by the
//    locator's design).
// An increment meets the acceptance target when the worse coordinate's mean |error| is at most the study's
// target, no estimate fails, and at most kMaxOutOfDomain of its pairs are out of the network's domain; for
// the plan's method also when its surface search refuses none. history_markdown (one table per method, a row
// per increment; the worst increment of each) goes into report.md, history_csv into history.csv.
#pragma once

#include <string>
#include <vector>

#include "contact/scene.hpp"
#include "history/replay.hpp"
#include "io/frd_results.hpp"
#include "mesh/contact_model.hpp"
#include "study/scene_domain.hpp"
#include "study/scene_report.hpp"

namespace contactnn::study {

/// The acceptance target's bound on the pairs outside a network's training domain, per increment (1%).
inline constexpr double kMaxOutOfDomain = 0.01;

/// One increment of a history: the pair's scene with the deck's nodes moved to it.
struct HistoryState {
  int increment = 0;  ///< SPEC 10's N (from 1)
  int step = 0;       ///< the .frd's step of the increment
  double time = 0.0;  ///< the .frd's total time of the increment
  contact::Scene scene;
};

/// Pair `pair` of `model` at every increment of `results` (SPEC 10), in file order: history::RunStates'
/// states, each kept. Errors of RunStates (FormatError naming the results file and line when its nodes are
/// not the deck's; those of contact::make_scene). `log` gets one line per 10 increments read.
[[nodiscard]] std::vector<HistoryState> history_states(mesh::ContactModel model,
                                                       const io::FrdResults& results, int pair,
                                                       const StudyLog& log = {});

/// One judged method at one increment, on the increment's pairs inside a quadrilateral face.
struct HistoryCell {
  eval::MethodErrors errors;  ///< the method's errors (rows: the pairs inside a face)
  long out_of_domain = 0;     ///< pairs whose network alone answers out_of_domain (0 without a network)
  [[nodiscard]] double out_of_domain_fraction() const {
    return errors.rows > 0 ? static_cast<double>(out_of_domain) / static_cast<double>(errors.rows) : 0.0;
  }
  [[nodiscard]] double worse_mean() const {
    return std::max(errors.stats[0].mean_abs, errors.stats[1].mean_abs);
  }
};

/// A method judged over the history.
struct HistoryMethod {
  std::string name;    ///< as in the study's measurements, e.g. "network[8-16-2]", "closed_form"
  std::string method;  ///< the search::Method name
  int network = -1;    ///< index into the study's networks, -1: none
  bool plan = false;   ///< the plan's method
  bool scene = false;  ///< the scene network alone (NetworkTraining::scene)
  /// " (the scene network)", " (the plan's method)", both, or "".
  [[nodiscard]] std::string role() const;
};

struct HistoryJudgement {
  std::string results;  ///< the .frd as given
  SurfaceKind surface = SurfaceKind::kBilinear;
  double target = 0.0;
  std::string domain;  ///< "rest" or "history": what the networks were trained on
  std::vector<int> increments, steps;
  std::vector<double> times;
  std::vector<long> slave_nodes, no_segment;   ///< per increment
  std::vector<std::array<long, 3>> locations;  ///< per increment: pairs at a face, edge, vertex
  std::vector<long> quad4;                     ///< per increment: pairs on 4-node quadrilaterals
  std::vector<HistoryMethod> methods;
  std::vector<std::vector<HistoryCell>> cells;  ///< [method][increment]
  /// Per increment: the plan's method in the surface search against the exact search (history::judge_plan;
  /// its times 0); empty when no method is the plan's.
  std::vector<history::PlanRow> plan_search;
  /// The increment meets the target for method m (no face pair: met; the plan's method: none refused).
  [[nodiscard]] bool meets(std::size_t m, std::size_t increment) const;
  /// Index of the increment with the largest worse-coordinate mean |error| of method m (failures first).
  [[nodiscard]] std::size_t worst(std::size_t m) const;
};

/// The methods judged: every network of `networks` alone (`scene`: the index of the scene network, -1 none),
/// then the plan's method `measured[chosen]` (once, when it is not one of them).
[[nodiscard]] std::vector<HistoryMethod> history_methods(const std::vector<const SceneNetwork*>& networks,
                                                         int scene,
                                                         const std::vector<MethodMeasurement>& measured,
                                                         std::size_t chosen);

/// Judges `methods` on every state's pairs inside a quadrilateral face (search_pairs). `log`: one line per
/// increment. options.threads for the accuracy runs; options.failure_box_margin as the study.
[[nodiscard]] HistoryJudgement judge_history(const std::vector<HistoryState>& states, SurfaceKind surface,
                                             const std::vector<const SceneNetwork*>& networks,
                                             const std::vector<HistoryMethod>& methods,
                                             const SceneStudyOptions& options, const StudyLog& log = {});

/// The per-increment results as CSV: one row per method and increment (history.csv).
[[nodiscard]] std::string history_csv(const HistoryJudgement& judgement);
/// The report's section: a summary (worst increment of each method, increments that miss the target), then
/// one table per method with a row per increment.
[[nodiscard]] std::string history_markdown(const HistoryJudgement& judgement);
/// The summary as a JSON object (report.json's "history").
[[nodiscard]] std::string history_json(const HistoryJudgement& judgement);

}  // namespace contactnn::study
