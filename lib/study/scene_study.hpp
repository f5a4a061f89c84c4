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
//     is at most margin x target (in the order measured, a later method displacing an earlier one only
//     where 10% faster: closer times are noise); where none is, the most accurate.
//  6. check_node_orders: every quadrilateral pair in each of the 8 node orders of its segment (SPEC 4) gives
//     the same reference label (1e-12) and the same answer of the plan's method and of the scene network
//     (1e-6).
//  7. The report (report_markdown, report_json) and the plan (io/plan_file.hpp).
//  With --results RUN.frd (scene_history.hpp, issue 29): step 2 draws the domain from the deck and every
//  increment of the run (DomainStates::kHistory, the default then), and after step 6 every scene network and
//  the plan's method are judged on each increment's pairs inside a face (history.csv, a report section).
//
// One header a step, each stating its contract: this one the options (SceneStudyOptions, resolved) and the
// log; scene_pairs.hpp step 1 (and the pairs' CSV row gen-configs --scene writes too); scene_domain.hpp step
// 2 and the capture policy of every scene domain; scene_networks.hpp steps 3-4 (the schedule in
// training_schedule.cpp); method_measurement.hpp steps 3 and 5 (the choice in plan_choice.cpp);
// node_orders.hpp step 6; scene_report.hpp step 7. The plan file is lib/io's (io/plan_file.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/log.hpp"
#include "dataset/enumeration.hpp"
#include "dataset/scene_sampling.hpp"
#include "eval/timing.hpp"

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

}  // namespace contactnn::study
