// The scene study (SPEC 7, "model only what a scene requires"): for one contact pair of a deck, the cheapest
// local-search method that reaches the accuracy the scene needs, a network only where one pays.
//
// What scene-study runs, one step each (apps/scene-study/main.cpp), in one process on one reading of the
// deck:
//  1. search_pairs: the surface search (SPEC 9) of every slave node: the deck's own pairs, each with its
//  location
//     (face, edge, vertex). Only the pairs whose point lies inside a quadrilateral face (location face) are
//     the local search's work, so only they judge the methods; an edge or vertex answer needs no network.
//  2. sample_domain: the scene's domain (dataset::sample_scene: its master segments deformed, the slave
//  anywhere
//     a contact can occur), a training sample and a held-out sample of another seed, labelled by the
//     reference. The capture distance is widened to 1.25 x the largest offset of the deck's own slave nodes
//     from their segments (the paper's nearest-node pairs, far ones too), as gen-configs --scene --sampling
//     random does.
//  3. measure_methods on the held-out sample: every candidate method without a network (closed forms,
//  newton:K,
//     hybrids) and, with untrained weights, the network of each size, whose cost does not depend on its
//     weights: a size whose network alone is slower than a method that already reaches the target cannot pay
//     and is not trained (TrainNetworks::kAuto).
//  4. train_networks: the scene networks, in memory. The sizes in increasing order; the first whose held-out
//     mean |error| is within margin x target is the scene network and bigger ones are dropped; when none is,
//     the best is trained on to long_epochs (its training continues: the same network as a fresh run of
//     long_epochs) and kept if it does better. Sizes train at the same time on the available threads, each
//     trainer on one thread; an idle thread carries the best finished size on towards long_epochs ahead of
//     time. Every network is bit for bit the one train-net makes from the same sample and settings.
//  5. measure_methods again, with every trained network's methods, and choose_plan: the fastest method
//  (batched,
//     1 thread, on the held-out sample) whose effective mean |error| (failures counted as one domain width)
//     is at most margin x target; where none is, the most accurate.
//  6. check_node_orders: every quadrilateral pair in each of the 8 node orders of its segment (SPEC 4) gives
//     the same reference label (1e-12) and the same answer of the plan's method and of the scene network
//     (1e-6).
//  7. The report (report_markdown, report_json) and the plan (plan.hpp).
//  With --results RUN.frd (scene_history.hpp, issue 29): step 2 draws the domain from the deck and every
//  increment of the run (DomainStates::kHistory, the default then), and after step 6 every scene network and
//  the plan's method are judged on each increment's pairs inside a face (history.csv, a report section).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "contact/scene.hpp"
#include "core/log.hpp"
#include "dataset/enumeration.hpp"
#include "dataset/labelled_set.hpp"
#include "dataset/scene_sampling.hpp"
#include "eval/accuracy.hpp"
#include "eval/evaluation_set.hpp"
#include "eval/timing.hpp"
#include "mlp/network.hpp"
#include "search/network_model.hpp"
#include "study/plan.hpp"

namespace contactnn::study {

/// Which scene networks are trained: kAuto only the sizes whose network could be the fastest method that
/// reaches the target (step 3); kAlways every size (as scripts/scene-study did before the plan); kNever none.
enum class TrainNetworks { kAuto, kAlways, kNever };
[[nodiscard]] std::string_view to_string(TrainNetworks mode);
/// "auto", "always" or "never"; InvalidArgument otherwise.
[[nodiscard]] TrainNetworks train_networks_from_string(std::string_view name);

/// Which states of the scene its domain (step 2) is drawn from: kRest the deck as read; kHistory the rest
/// state and every increment of a solver's results (scene-study --results, issue 29: the union of the
/// increments' segments, so that the network serves every state the simulation reaches); kAuto kHistory when
/// the study has results, kRest otherwise.
enum class DomainStates { kAuto, kRest, kHistory };
[[nodiscard]] std::string_view to_string(DomainStates states);
/// "auto", "rest" or "history"; InvalidArgument otherwise.
[[nodiscard]] DomainStates domain_states_from_string(std::string_view name);

/// Every policy default of the study, in one place. Each field is a key of the [scene-study] config section
/// (scene-study --help names them). A 0 or an empty value marked "surface default" takes the surface's value
/// (resolved()).
struct SceneStudyOptions {
  // The scene's domain: gen-configs' own defaults (dataset::SceneDomainOptions explains each).
  dataset::SceneDomainOptions domain;
  /// The states the domain covers (scene-study --domain); kAuto: the whole history with --results.
  DomainStates domain_states = DomainStates::kAuto;
  /// Whether the domain's slave nodes pass the segment test of Eqs 3-6 (domain.segment_test): "on", "off", or
  /// "auto": off for a history study (--results: its networks are judged on the surface search's pairs of
  /// every increment, some of which fail the test), on otherwise (the paper's pairs; the studies of
  /// results/scenes.md).
  std::string segment_test = "auto";
  /// Whose offsets the capture covers (1.25 x the largest |gap| / shortest edge, of every state drawn):
  /// "nearest_node" the paper's nearest-node pairs of every corner slave node, far ones too (as gen-configs
  /// --scene --sampling random); "surface" the surface search's pairs on 4-node quadrilaterals, the pairs the
  /// local search serves (a deck whose slave surface reaches far beyond the master, as forming-stroke's
  /// sheet, gets a capture of several element sizes from nearest-node pairs that the surface search leaves
  /// without a face).
  std::string capture_pairs = "nearest_node";
  /// Configurations of the scene's domain to train from. 60000: thin, curved tool radii need samples across
  /// their width; 20000 left two CalculiX decks above the target.
  std::int64_t count = 60000;
  /// The held-out sample: count / heldout_divisor configurations (at least 100), seed + heldout_seed_offset.
  std::int64_t heldout_divisor = 4;
  std::uint64_t heldout_seed_offset = 1000;
  std::uint64_t seed = 1;  ///< seed of the training sample, the pattern draw and the networks' weights

  /// Mean |error| to reach, parameter units: surface default 0.005 (bilinear, xi units, domain width 2),
  /// 0.0025 (Gregory, u units, width 1): the paper's Neuro48 errs 0.0039 / 0.0048 on its own domain.
  double target = 0.0;
  /// A method reaches the target when its held-out error is at most margin x target (the pairs are not the
  /// held-out sample: the margin leaves room for the difference).
  double margin = 0.8;

  // The scene networks.
  std::vector<int> sizes;  ///< hidden sizes, smallest first; surface default {8, 16, 32} or {16, 32, 48}
  /// A second hidden layer of this many units behind every size (0: one hidden layer, the paper's networks):
  /// --sizes 48 --second-layer 48 trains 16-48-48-2.
  int second_layer = 0;
  int epochs = 1000;  ///< training epochs of each size (the paper's 10000 iterations are passes; 1000 do)
  /// When no size reaches the target: the best trained on to this many epochs (0 or at most epochs: no second
  /// round). On metalforming.inp's tool radius, 6000 passes over 60000 configurations reached what 400000 did
  /// not.
  int long_epochs = 6000;
  TrainNetworks train_networks = TrainNetworks::kAuto;
  double train_fraction = 0.8;        ///< of count: training patterns
  double validation_fraction = 0.25;  ///< validation patterns per training pattern (the best epoch is kept)
  std::string input_features = "affine";  ///< core/input_features.hpp: thin segments stay well conditioned
  double input_quantile = 0.005;          ///< inputs' q and 1-q quantiles map to -1 and 1
  /// Online back-propagation with momentum (configs/<surface>-paper.toml's [train-net]): learning rate
  /// surface default 0.02 (bilinear) or 0.01 (Gregory), constant.
  double learning_rate = 0.0;
  double momentum = 0.9;
  double u0 = 2.0;
  double target_low = 0.1;
  double target_high = 0.9;

  // The methods.
  /// Candidate methods without a network, comma-separated search::Method names; empty: default_methods().
  std::string methods;
  /// The methods of every scene network (search::Method names that need one).
  std::string network_methods = "network,network+newton:1,network+newton:2";
  /// An estimate further than this many domain widths outside the domain is a failure
  /// (eval::compare_with_labels).
  double failure_box_margin = 0.5;

  // Timing: batched, 1 thread, on the held-out sample (eval::time_methods).
  std::int64_t timing_queries = 20000;  ///< queries per timed pass (held-out rows, cycled when fewer)
  eval::TimingOptions timing;           ///< repetitions and warm-up passes

  /// Threads of the sampling, the accuracy runs and the training (sizes train side by side); 0: OpenMP's
  /// default.
  int threads = 0;
};

/// `options` with every surface default filled in. InvalidArgument for values out of range (count < 100, no
/// size, a size outside 1..NetworkModel::kMaxWidth, epochs < 1, target or margin <= 0, fractions out of
/// range, an unknown input map or method, a network method in `methods`, a method without network in
/// `network_methods`).
[[nodiscard]] SceneStudyOptions resolved(SceneStudyOptions options, SurfaceKind surface);

/// The candidate methods without a network, for `surface`: the closed form and its hybrids, newton:1..5 and
/// newton to convergence; for bilinear also four_triangles where lib/search has it.
[[nodiscard]] std::string default_methods(SurfaceKind surface);

/// Progress lines of the scene study (core/log.hpp).
using StudyLog = ProgressLog;

// ---------------------------------------------------------------------------------------------- 1. pairs

/// The deck's own pairs (step 1).
struct ScenePairs {
  contact::SceneResult result;      ///< the surface search, one pair per slave node
  std::array<long, 3> locations{};  ///< pairs by Location: face, edge, vertex
  long quad4 = 0;                   ///< pairs on a 4-node quadrilateral (the SPEC 7 configurations)
  eval::EvaluationSet face;         ///< quad4 pairs with location face: what judges the methods
  eval::EvaluationSet quad4_pairs;  ///< every quad4 pair, edges and vertices included (for comparison)
};

/// The surface search over the scene's slave nodes with the reference labels (`surface`, projection
/// defaults).
[[nodiscard]] ScenePairs search_pairs(const contact::Scene& scene, SurfaceKind surface);

/// The pairs as gen-configs --scene writes them (SPEC 7 and 9 columns): the text of DIR/pairs.csv.
[[nodiscard]] std::string pairs_csv(const contact::Scene& scene, const ScenePairs& pairs,
                                    SurfaceKind surface);

// --------------------------------------------------------------------------------------------- 2. domain

struct SceneDomain {
  dataset::SceneDomainOptions domain;  ///< the domain drawn (capture widened to the deck's offsets)
  double deck_offset = 0.0;            ///< largest |gap| / shortest edge of the deck's nearest-node pairs
  dataset::LabelledSet train;          ///< options.count configurations, seed
  dataset::LabelledSet heldout;        ///< count / heldout_divisor, seed + heldout_seed_offset
  eval::EvaluationSet heldout_set;     ///< the held-out sample as queries (its own frame)
  std::uint64_t heldout_seed = 0;
};

/// Step 2. InvalidArgument for a scene without master segments.
[[nodiscard]] SceneDomain sample_domain(const contact::Scene& scene, SurfaceKind surface,
                                        const SceneStudyOptions& options, const StudyLog& log = {});
/// Step 2 over several states of one pair (DomainStates::kHistory): the segments of every state are drawn
/// from (by area, as one scene's), and the capture covers the largest deck offset of any state. `states`
/// non-empty, each with master segments; with one state this is the overload above.
[[nodiscard]] SceneDomain sample_domain(const std::vector<const contact::Scene*>& states, SurfaceKind surface,
                                        const SceneStudyOptions& options, const StudyLog& log = {});

// ------------------------------------------------------------------------------------------- 3. networks

/// A scene network: trained, or (weights untrained) for timing only.
struct SceneNetwork {
  std::string name;  ///< "16-32-2", "16-32-2-long" (trained on to long_epochs)
  int hidden = 0;
  int epochs = 0;      ///< epochs run (the kept parameters may be an earlier epoch's)
  int best_epoch = 0;  ///< epoch of the kept parameters (best validation loss)
  std::shared_ptr<const mlp::Network<float>> network;
  geometry::TrainingDomain domain;
  std::shared_ptr<const search::NetworkModel> model;
  double heldout_mean_abs[2] = {0.0, 0.0};  ///< the network alone on the held-out sample
  double seconds = 0.0;                     ///< training time (wall, on its own thread)
  double validation_loss = 0.0;
  [[nodiscard]] double heldout_error() const { return std::max(heldout_mean_abs[0], heldout_mean_abs[1]); }
};

/// The networks of every size with untrained weights (initialised from the seed): their cost is a trained
/// network's, so step 3 can time them before any training.
[[nodiscard]] std::vector<SceneNetwork> untrained_networks(const SceneDomain& domain, SurfaceKind surface,
                                                           const SceneStudyOptions& options);

struct NetworkTraining {
  std::vector<SceneNetwork> tried;  ///< in the order they finished: each size, then the long round's
  int scene = -1;                   ///< index in `tried` of the scene network (-1: none trained)
  bool reached = false;             ///< the scene network is within margin x target on the held-out sample
  double seconds = 0.0;             ///< wall time of the whole step
};

/// Step 4 for `sizes` (a subset of options.sizes, in increasing order; empty: nothing is trained).
[[nodiscard]] NetworkTraining train_networks(const SceneDomain& domain, SurfaceKind surface,
                                             const SceneStudyOptions& options, const std::vector<int>& sizes,
                                             const StudyLog& log = {});

// ---------------------------------------------------------------------------------------- 5. measurements

/// One method on the held-out sample.
struct MethodMeasurement {
  std::string name;    ///< e.g. "closed_form", "network+newton:1[16-32-2]"
  std::string method;  ///< the search::Method name
  int network = -1;    ///< index into the networks measured, -1: none
  eval::MethodErrors errors;
  double effective_mean = 0.0;  ///< eval::effective_mean_error
  double batched_ns = 0.0;      ///< ns per query, batched, 1 thread: the fastest of the timed passes
  bool reaches = false;         ///< effective_mean <= margin x target
};

/// Every method of `methods` (comma-separated, no network) and `network_methods` with each of `networks` on
/// `set`: accuracy (options.threads) and batched 1-thread speed, all timed in one round-robin; each method's
/// time is its fastest pass (another process can only slow a pass down).
[[nodiscard]] std::vector<MethodMeasurement> measure_methods(const eval::EvaluationSet& set,
                                                             SurfaceKind surface, const std::string& methods,
                                                             const std::string& network_methods,
                                                             const std::vector<const SceneNetwork*>& networks,
                                                             const SceneStudyOptions& options);

/// The sizes worth training (step 3): with kAlways all, kNever none; with kAuto each size whose untrained
/// network alone (in `measured`, named "network[<name>]") is faster than the fastest method of `measured`
/// that reaches the target (every size when none does). `why` gets one line per size left out.
[[nodiscard]] std::vector<int> sizes_that_may_pay(const std::vector<MethodMeasurement>& measured,
                                                  const std::vector<SceneNetwork>& untrained,
                                                  const SceneStudyOptions& options,
                                                  std::vector<std::string>* why);

/// The plan's method (step 5): the index in `measured` of the fastest that reaches the target, else of the
/// most accurate (ties: the faster). InvalidArgument for an empty list.
[[nodiscard]] std::size_t choose_plan(const std::vector<MethodMeasurement>& measured);

// ---------------------------------------------------------------------------------------- 6. node orders

struct NodeOrderCheck {
  long pairs = 0;             ///< quad4 pairs checked (x 8 orders)
  double label = 0.0;         ///< largest difference of the reference's coordinates from the identity order's
  double label_gap = 0.0;     ///< the same for the gap (its sign follows the orientation)
  double plan_method = 0.0;   ///< the plan's method
  double scene_network = -1;  ///< the scene network alone (-1: none)
  bool passed = true;         ///< label <= 1e-12 (relative to 1) and the methods <= 1e-6
  [[nodiscard]] std::string summary() const;
};

/// Step 6 on every quad4 pair of `pairs` (any location): the reference labels and, through lib/search, `plan`
/// and `scene` (nullable) in the 8 node orders.
[[nodiscard]] NodeOrderCheck check_node_orders(const ScenePairs& pairs, SurfaceKind surface,
                                               const search::LocalSearch& plan,
                                               const search::LocalSearch* scene);

// --------------------------------------------------------------------------------------------- 7. report

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
[[nodiscard]] ScenePlan make_plan(const SceneStudyResult& result, const std::string& network_file);

[[nodiscard]] std::string report_markdown(const SceneStudyResult& result);
/// The summary scripts/scene-table reads (report.json).
[[nodiscard]] std::string report_json(const SceneStudyResult& result);

}  // namespace contactnn::study
