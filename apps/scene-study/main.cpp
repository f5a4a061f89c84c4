// scene-study: the local-search method one contact pair of a deck requires, in one process (SPEC 7).
//
// Description:
//   Reads the deck once and searches its pair once (the surface search of SPEC 9), samples the scene's domain
//   (its master segments deformed, the slave anywhere a contact can occur), measures every candidate method
//   on a held-out sample of that domain (closed forms, newton:K, hybrids), trains in memory the scene
//   networks that could pay (the smallest size that reaches the target; a network whose cost alone exceeds a
//   method that already reaches the target is not trained), measures them too, and writes the plan: the
//   fastest method whose held-out error reaches margin x target, a network only where one is the fastest. The
//   report shows the choice beside every alternative on the deck's own pairs (those inside a face: an edge or
//   vertex answer needs no local search) and checks the 8 node orders of every pair.
//   lib/study/scene_study.hpp holds the policy and its defaults (SceneStudyOptions); this file maps flags
//   onto it.
//
// Sample runs:
//   scene-study --scene build/tests/contact/scenes/hertz.inp --surface gregory --output /tmp/hertz-study
//   scene-study --scene build/tests/contact/scenes/flat.inp --pair 1 --surface bilinear --output
//   /tmp/flat-study
//               --count 4000 --epochs 50 --train-networks always        (one line)
//   scene-study --config my-study.toml --scene deck.inp --surface gregory --output reports/deck
//   scene-study --scene run/hertz-slide.inp --results run/hertz-slide.frd --surface bilinear --output /tmp/hs
//               (the networks trained on the whole history's domain and judged on every increment)
//   scripts/scene-study takes the same options (and --build-dir) and runs this program.
//
// Writes (under --output DIR, created if missing):
//   plan.toml               the scene plan (lib/io/plan_file.hpp): evaluate-net --plan, the C and Fortran
//   interfaces network.h5              the plan's network, when its method uses one (evaluate-net --weights
//   reads it too);
//                           a network.h5 of an earlier run is removed when the plan has none
//   pairs.csv               the pair's slave nodes as gen-configs --scene writes them (never training data)
//   history.csv             with --results: every scene network and the plan's method on each increment's
//                           pairs inside a face (lib/study/scene_history.hpp); an earlier run's is removed
//                           without --results
//   report.md, report.json  every method on the held-out sample and on the deck's pairs; the node orders
//   scene-study.config.toml the effective [scene-study] configuration
//   progress on stdout (--quiet: the last line only).
// Exit status: 0 (also when no method reaches the target: the plan and the report say so); 1 when the pair
// has nothing to study (no slave node, or none with a face); 2 a bad option or config key (a missing
// --results file, --domain history without --results); 3 a malformed deck, or a results file that is
// malformed or not the deck's (node ids), naming file and line; 4 an I/O failure; 5 a numerical failure.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/csv.hpp"
#include "io/face_network_file.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "io/network_file.hpp"
#include "io/output_checks.hpp"
#include "io/plan_file.hpp"
#include "search/face_search.hpp"
#include "search/local_search.hpp"
#include "study/face_study.hpp"
#include "study/scene_domain.hpp"
#include "study/scene_history.hpp"
#include "study/scene_report.hpp"

namespace {

using namespace contactnn;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// "16,32,48" -> {16, 32, 48}; InvalidArgument naming --sizes otherwise.
std::vector<int> parse_sizes(const std::string& text) {
  return cli::integer_list(text, 1, std::numeric_limits<int>::max(),
                           "--sizes: expected comma-separated hidden sizes >= 1, smallest first");
}

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The network of the plan as a network file: the trained network, its domain, and how it was made.
void write_plan_network(const fs::path& path, const study::SceneNetwork& n, const study::SceneStudyOptions& o,
                        const std::string& deck, int pair, const std::string& config) {
  io::NetworkProvenance p;
  p.config_toml = config;
  p.seed = o.seed;
  p.dataset_path = "scene-study: the domain of pair " + std::to_string(pair) + " of " + deck + " (in memory)";
  p.training_mode = "online";
  p.training_patterns = static_cast<std::int64_t>(static_cast<double>(o.count) * o.train_fraction);
  p.validation_patterns = std::llround(o.validation_fraction * static_cast<double>(p.training_patterns));
  p.epochs_run = n.epochs;
  p.best_epoch = n.best_epoch;
  p.validation_loss = n.validation_loss;
  io::write_network(path, *n.network, n.domain, p);
}

/// --face's --sizes: comma-separated sizes, each one hidden layer (48) or two (48x48).
std::vector<std::vector<int>> parse_face_sizes(const std::string& text) {
  std::vector<std::vector<int>> sizes;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::vector<int> layers;
    std::stringstream layer_text(item);
    std::string layer;
    while (std::getline(layer_text, layer, 'x')) {
      const std::vector<int> one = parse_sizes(layer);
      layers.insert(layers.end(), one.begin(), one.end());
    }
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, layers.size() == 1 || layers.size() == 2,
        "--sizes with --face: each size is one layer (48) or two (48x48), got " << quote_text(text));
    sizes.push_back(layers);
  }
  CONTACTNN_REQUIRE_AS(InvalidArgument, !sizes.empty(), "--sizes: no size in " << quote_text(text));
  return sizes;
}

/// scene-study --face: the study of the pair's quadratic faces (lib/study/face_study.hpp). Writes report.md
/// and, when the chosen method uses one, face-network.h5 (io::write_face_network).
int run_face_mode(const std::string& scene_path, int pair, search::FaceKind kind,
                  const study::FaceStudyOptions& f, const std::string& output,
                  const std::vector<io::NamedPath>& inputs, bool check_only, bool quiet,
                  const std::string& command_line, double general_curvature) {
  const fs::path dir(output);
  io::require_outputs({}, {{"--output", dir, {"report.md", "face-network.h5"}}}, inputs);
  if (check_only) return 0;
  const auto say = [&](std::string_view line) {
    if (!quiet) std::printf("  %.*s\n", static_cast<int>(line.size()), line.data()), std::fflush(stdout);
  };
  if (general_curvature >= 0.0) {
    // The general network: the best size's network is written, whatever the choice (it is what data/weights
    // ships; the report says whether it pays).
    if (!quiet) std::printf("scene-study: general %s domain\n", std::string(search::to_string(kind)).c_str());
    const study::FaceStudy st = study::run_general_face_study(kind, f, general_curvature, say);
    std::string report = study::face_study_markdown(st, "", 0) + "\nCommand: `" + command_line + "`\n";
    const auto best =
        std::min_element(st.networks.begin(), st.networks.end(),
                         [](const auto& a, const auto& b) { return a.heldout_error < b.heldout_error; });
    io::make_output_directory("--output", dir);
    io::write_face_network(
        dir / "face-network.h5", kind, *best->network, best->feature_min, best->feature_max,
        "scene-study --face " + std::string(search::to_string(kind)) + " --general --curvature " +
            std::to_string(general_curvature) + ": " + best->name + ", " + std::to_string(best->epochs) +
            " epochs, held-out mean |error| " + std::to_string(best->heldout_error));
    io::write_text_atomically(dir / "report.md", report);
    std::printf("scene-study: general %s network %s, held-out mean |error| %.4g; %.1f s\n",
                std::string(search::to_string(kind)).c_str(), best->name.c_str(), best->heldout_error,
                st.seconds);
    return 0;
  }
  if (!quiet)
    std::printf("scene-study: %s pair %d, %s faces\n", scene_path.c_str(), pair,
                std::string(search::to_string(kind)).c_str());
  const mesh::ContactModel model = io::read_inp_deck(scene_path);
  (void)cli::warn_unapplied_geometry("scene-study", scene_path);
  const contact::Scene scene = contact::make_scene(model, pair);
  const study::FacePairs probe = study::face_pairs(scene, kind);
  if (probe.faces == 0 || probe.pairs.size() == 0) {
    std::fprintf(
        stderr,
        "scene-study: pair %d of %s has %d %s faces and %zu slave nodes inside them: nothing to study\n",
        pair, scene_path.c_str(), probe.faces, std::string(search::to_string(kind)).c_str(),
        probe.pairs.size());
    return 1;
  }
  const study::FaceStudy st = study::run_face_study(scene, kind, f, say);
  std::string report = study::face_study_markdown(st, scene_path, pair);
  report += "\nCommand: `" + command_line + "`\n";
  io::make_output_directory("--output", dir);
  const fs::path network_file = dir / "face-network.h5";
  int network = st.chosen >= 0 ? st.methods[static_cast<std::size_t>(st.chosen)].network : -1;
  if (network >= 0) {
    const study::FaceNetworkResult& n = st.networks[static_cast<std::size_t>(network)];
    io::write_face_network(network_file, kind, *n.network, n.feature_min, n.feature_max,
                           "scene-study --face " + std::string(search::to_string(kind)) + ": pair " +
                               std::to_string(pair) + " of " + scene_path + ", " + n.name + ", " +
                               std::to_string(n.epochs) + " epochs");
  } else {
    fs::remove(network_file);  // an earlier run's: this choice uses none
  }
  io::write_text_atomically(dir / "report.md", report);
  if (st.chosen >= 0) {
    const study::FaceMethodResult& c = st.methods[static_cast<std::size_t>(st.chosen)];
    std::printf(
        "scene-study: %s faces: %s, held-out effective mean |error| %.4g (target %g), pairs %.4g, %.1f "
        "ns/query; %.1f s\n",
        std::string(search::to_string(kind)).c_str(), c.name.c_str(), c.heldout_effective, f.target,
        c.pairs_mean, c.batched_ns, st.seconds);
  } else {
    std::printf("scene-study: %s faces: no method reaches the target %g; %.1f s\n",
                std::string(search::to_string(kind)).c_str(), f.target, st.seconds);
  }
  return 0;
}

/// Everything the command line gives: the study's options (every default lives in study::SceneStudyOptions;
/// flags only map onto it) and the program's own.
struct Args {
  study::SceneStudyOptions o;
  std::string scene_path, output, surface_name, face_name, sizes, results_path,
      train_networks = std::string(study::to_string(o.train_networks)),
      domain_states = std::string(study::to_string(o.domain_states));
  int pair = 0;
  bool check_only = false, quiet = false, general = false, trust_nodes = false;
  double curvature = 0.1;
};

/// The options of what is studied: the deck, its pair, the surface or face type, the output.
void add_input_options(CLI::App& app, Args& a) {
  std::string &scene_path = a.scene_path, &surface_name = a.surface_name, &face_name = a.face_name;
  int& pair = a.pair;
  bool& general = a.general;
  double& curvature = a.curvature;
  app.add_option("--scene", scene_path, "the deck (.inp, SPEC 7; required unless --face with --general)")
      ->check(CLI::ExistingFile);
  app.add_option("--pair", pair, "the *CONTACT PAIR data line, counted from 0")
      ->transform(cli::integer_in(0, 1000000));
  app.add_option("--surface", surface_name, "bilinear or gregory (required unless --face)")
      ->check(CLI::IsMember({"bilinear", "gregory"}));
  app.add_option(
         "--face", face_name,
         "tri6 or quad8: study the pair's quadratic master faces of that type instead (FaceSearch's "
         "methods, face networks; lib/study/face_study.hpp); --sizes then takes layers as 48 or 48x48")
      ->check(CLI::IsMember({"tri6", "quad8"}));
  app.add_flag(
      "--general", general,
      "with --face: no deck; the paper-like general domain of the face type (how data/weights' face networks "
      "are made)");
  app.add_option("--curvature", curvature,
                 "with --general: mid-side nodes off their chords' midpoints, x the edge")
      ->check(cli::real_in(0.0, 0.49));
}

/// The options of the study itself (its domain, networks, methods, timing) and the program's flags.
void add_study_options(CLI::App& app, Args& a) {
  study::SceneStudyOptions& o = a.o;
  std::string &output = a.output, &sizes = a.sizes, &results_path = a.results_path,
              &train_networks = a.train_networks, &domain_states = a.domain_states;
  bool &check_only = a.check_only, &quiet = a.quiet, &trust_nodes = a.trust_nodes;
  app.add_option("--output", output, "directory of the plan, the network, the pairs and the report")
      ->required();
  app.add_option("--results", results_path,
                 "a CalculiX .frd of the deck (SPEC 10): the networks and the plan judged on every increment")
      ->check(CLI::ExistingFile);
  app.add_option("--domain", domain_states,
                 "the states the scene's domain is drawn from: rest (the deck), history (the deck and every "
                 "increment of --results) or auto (history with --results, rest without)")
      ->check(CLI::IsMember({"auto", "rest", "history"}));
  app.add_option(
         "--segment-test", o.segment_test,
         "scene domain: slave nodes pass the segment test of Eqs 3-6 (on), or not necessarily (off: as the "
         "surface search pairs them); auto: off with --results, on without")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  app.add_option("--count", o.count,
                 "configurations of the scene's domain to train from (held out: count / 4)")
      ->transform(cli::integer_in(100, 1'000'000'000));
  app.add_option("--seed", o.seed, "seed of the domain's samples, the pattern draw and the weights")
      ->transform(cli::integer_in(0, cli::kMaxSeed - 1000));
  app.add_option("--sizes", sizes,
                 "hidden sizes to try, smallest first (default bilinear 8,16,32; gregory 16,32,48)");
  app.add_option("--second-layer", o.second_layer,
                 "a second hidden layer of this many units behind every size (0: one hidden layer)")
      ->transform(cli::integer_in(0, 128));
  app.add_option("--epochs", o.epochs, "training epochs of each size")
      ->transform(cli::integer_in(1, 100000000));
  app.add_option("--long-epochs", o.long_epochs,
                 "when no size reaches the target, the best is trained on to this many epochs (0 or at most "
                 "--epochs: "
                 "no second round)")
      ->transform(cli::integer_in(0, 100000000));
  app.add_option("--target", o.target, "mean |error| to reach (0: bilinear 0.005, gregory 0.0025)")
      ->check(cli::kNonNegative);
  app.add_option("--margin", o.margin,
                 "a method reaches the target when its held-out error is below margin x target")
      ->check(cli::kPositive);
  app.add_option(
         "--train-networks", train_networks,
         "auto: train the sizes whose network could be the fastest method at the target; always; never")
      ->check(CLI::IsMember({"auto", "always", "never"}));
  app.add_option("--methods", o.methods,
                 "candidate methods without a network, comma-separated (empty: the default list)");
  app.add_option("--network-methods", o.network_methods, "the methods of every scene network");
  app.add_option("--timing-queries", o.timing_queries, "queries per timed pass on the held-out sample")
      ->transform(cli::integer_in(1, 100000000));
  app.add_option("--timing-repetitions", o.timing.repetitions, "timed passes per method (the median is kept)")
      ->transform(cli::integer_in(1, 1000));
  app.add_option("--threads", o.threads,
                 "threads of the sampling, the accuracy runs and the training (0: all)")
      ->transform(cli::integer_in(0, cli::kMaxThreads));
  app.add_option("--deformation", o.domain.deformation,
                 "scene domain: node displacement, fraction of the shortest edge")
      ->check(cli::real_in(0.0, 0.49));
  app.add_option("--capture", o.domain.capture,
                 "scene domain: slave offset along the normal, fraction of the shortest edge (at least 1.25 "
                 "x the deck's)")
      ->check(cli::kPositive);
  app.add_option(
         "--capture-pairs", o.capture_pairs,
         "scene domain: whose offsets the capture covers: nearest_node (every slave node's nearest-node "
         "pair, far ones too) or surface (the surface search's pairs on quadrilaterals)")
      ->check(CLI::IsMember({"nearest_node", "surface"}));
  app.add_option("--normal-tilt-tangent", o.domain.normal_tilt_tangent,
                 "scene domain, Gregory: node normals tilted by up to this")
      ->check(cli::kNonNegative);
  app.add_option("--boundary-fraction", o.domain.boundary_fraction,
                 "scene domain: fraction of foot points on nodes and edges")
      ->check(cli::real_in(0.0, 1.0));
  app.add_option("--input-features", o.input_features, "what the networks see: paper or affine")
      ->check(CLI::IsMember({"paper", "affine"}));
  app.add_option("--input-quantile", o.input_quantile, "inputs' q and 1-q quantiles map to -1 and 1")
      ->check(cli::real_in(0.0, 0.49));
  app.add_flag(
      "--trust-results-nodes", trust_nodes,
      "with --results: take the .frd's node coordinates even where they are not the deck's (another mesh "
      "with the same node ids is refused otherwise)");
  app.add_flag("--check", check_only, "check the options, the deck's path and --output, then stop");
  app.add_flag("--quiet", quiet, "no progress lines");
}

/// scene-study --face: the study's options mapped onto the face study's (only those given on the command line
/// override the face study's own defaults).
study::FaceStudyOptions face_options(const CLI::App& app, const Args& a) {
  const study::SceneStudyOptions& o = a.o;
  study::FaceStudyOptions f;
  f.count = o.count;
  f.heldout = std::max<std::int64_t>(100, o.count / 4);
  f.seed = o.seed;
  if (app.count("--epochs") > 0) f.epochs = o.epochs;
  if (o.target > 0.0) f.target = o.target;
  f.margin = o.margin;
  f.threads = o.threads;
  if (app.count("--deformation") > 0) f.deformation = o.domain.deformation;
  if (app.count("--capture") > 0) f.capture = o.domain.capture;
  if (app.count("--boundary-fraction") > 0) f.boundary_fraction = o.domain.boundary_fraction;
  if (app.count("--input-quantile") > 0) f.input_quantile = o.input_quantile;
  if (app.count("--timing-queries") > 0) f.timing_queries = o.timing_queries;
  if (!o.methods.empty()) f.methods = o.methods;
  if (app.count("--network-methods") > 0) f.network_methods = o.network_methods;
  if (!a.sizes.empty()) f.sizes = parse_face_sizes(a.sizes);
  return f;
}

/// Step 2 of the scene study: the options resolved for the surface; InvalidArgument for settings that
/// contradict each other.
SurfaceKind resolve_scene_options(Args& a) {
  study::SceneStudyOptions& o = a.o;
  const std::string& results_path = a.results_path;
  CONTACTNN_REQUIRE_AS(InvalidArgument, !a.surface_name.empty(),
                       "--surface (bilinear or gregory) or --face is required");
  CONTACTNN_REQUIRE_AS(InvalidArgument, !a.scene_path.empty() && !a.general,
                       "--scene is required (--general goes with --face)");
  const SurfaceKind surface = surface_from_string(a.surface_name);
  if (!a.sizes.empty()) o.sizes = parse_sizes(a.sizes);
  o.train_networks = study::train_networks_from_string(a.train_networks);
  o.domain_states = study::domain_states_from_string(a.domain_states);
  if (o.domain_states == study::DomainStates::kAuto) {
    o.domain_states = results_path.empty() ? study::DomainStates::kRest : study::DomainStates::kHistory;
  }
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       o.domain_states != study::DomainStates::kHistory || !results_path.empty(),
                       "--domain history: the whole history's domain needs --results RUN.frd");
  o.domain.segment_test = o.segment_test == "on" || (o.segment_test == "auto" && results_path.empty());
  o = study::resolved(o, surface);
  return surface;
}

/// Steps 5 to 8: the scene's domain (from the deck's state or every state of its history), the methods
/// without a network beside untrained networks of every size (the sizes that could pay), the scene networks
/// that could pay trained in memory, every method measured and the plan chosen. The result's domain,
/// training, measurements and choice.
study::SceneStudyResult plan_study(const contact::Scene& scene,
                                   const std::vector<study::HistoryState>& history, SurfaceKind surface,
                                   const study::SceneStudyOptions& o, const study::StudyLog& say,
                                   Clock::time_point start) {
  // 5. The scene's domain: a training sample and a held-out one, from the deck's state or from every state
  //    of its history.
  std::vector<const contact::Scene*> states = {&scene};
  if (o.domain_states == study::DomainStates::kHistory) {
    for (const study::HistoryState& h : history) states.push_back(&h.scene);
  }
  const study::SceneDomain domain = study::sample_domain(states, surface, o, say);
  study::SceneStudyResult result;
  result.surface = surface;
  result.options = o;
  result.deck_offset = domain.deck_offset;
  result.domain = domain.domain;
  result.heldout_rows = domain.heldout.size();
  result.heldout_seed = domain.heldout_seed;
  say("domain: " + std::to_string(domain.train.size()) + " configurations to train from, " +
      std::to_string(domain.heldout.size()) + " held out");

  // 6. The methods without a network on the held-out sample, beside untrained networks of every size (a
  //    network's cost does not depend on its weights): the sizes that could pay.
  const std::vector<study::SceneNetwork> untrained = study::untrained_networks(domain, surface, o);
  std::vector<const study::SceneNetwork*> untrained_pointers;
  for (const study::SceneNetwork& n : untrained) untrained_pointers.push_back(&n);
  const std::vector<study::MethodMeasurement> first =
      study::measure_methods(domain.heldout_set, surface, o.methods, "network", untrained_pointers, o);
  const std::vector<int> to_train = study::sizes_that_may_pay(first, untrained, o, &result.not_trained);
  for (const std::string& why : result.not_trained) say(why);

  // 7. The scene networks that could pay, trained in memory.
  result.training = study::train_networks(domain, surface, o, to_train, say);

  // 8. Every method measured on the held-out sample; the plan: the fastest that reaches the target.
  std::vector<const study::SceneNetwork*> networks;
  for (const study::SceneNetwork& n : result.training.tried) networks.push_back(&n);
  result.measured =
      study::measure_methods(domain.heldout_set, surface, o.methods, o.network_methods, networks, o);
  result.chosen = study::choose_plan(result.measured);
  result.seconds_to_plan = seconds_since(start);
  const study::MethodMeasurement& chosen = result.measured[result.chosen];
  say("plan: " + chosen.name + (chosen.reaches ? "" : " (no method reaches the target: the most accurate)"));
  return result;
}

/// The trained networks of `result`, as measure_methods and judge_on_pairs take them.
std::vector<const study::SceneNetwork*> networks_of(const study::SceneStudyResult& result) {
  std::vector<const study::SceneNetwork*> networks;
  for (const study::SceneNetwork& n : result.training.tried) networks.push_back(&n);
  return networks;
}

/// Step 9: the deck's pairs judged; the node orders of every pair.
void judge_pairs(const study::ScenePairs& pairs, SurfaceKind surface,
                 const std::vector<const study::SceneNetwork*>& networks, study::SceneStudyResult& result,
                 const study::StudyLog& say) {
  const study::MethodMeasurement& chosen = result.measured[result.chosen];
  study::judge_on_pairs(pairs, surface, networks, result);
  const auto network_of = [&](int index) {
    return index >= 0 ? networks[static_cast<std::size_t>(index)]->model.get() : nullptr;
  };
  const search::LocalSearch plan_search(surface, search::Method::parse(chosen.method), {},
                                        network_of(chosen.network));
  std::optional<search::LocalSearch> scene_search;
  if (result.training.scene >= 0) {
    scene_search.emplace(surface, search::Method::parse("network"), search::SearchOptions{},
                         network_of(result.training.scene));
  }
  result.node_orders =
      study::check_node_orders(pairs, surface, plan_search, scene_search ? &*scene_search : nullptr);
  say(result.node_orders.summary());
}

/// Step 10: the plan (and its network), history.csv, the report, the effective config.
void write_study(const fs::path& dir, const study::SceneStudyResult& result,
                 const std::vector<const study::SceneNetwork*>& networks,
                 const std::optional<study::HistoryJudgement>& judged, const std::string& config) {
  const study::SceneStudyOptions& o = result.options;
  const study::MethodMeasurement& chosen = result.plan();
  const fs::path network_file = dir / "network.h5";
  if (chosen.network >= 0) {
    write_plan_network(network_file, *networks[static_cast<std::size_t>(chosen.network)], o, result.deck,
                       result.pair, config);
  } else {
    fs::remove(network_file);  // an earlier run's: the plan names none
  }
  io::write_text_atomically(
      dir / "plan.toml", io::plan_to_toml(study::make_plan(result, chosen.network >= 0 ? "network.h5" : "")));
  if (judged) {
    io::write_text_atomically(dir / "history.csv", study::history_csv(*judged));
  } else {
    fs::remove(dir / "history.csv");  // an earlier run's: this one has no history
  }
  io::write_text_atomically(dir / "report.md", study::report_markdown(result));
  io::write_text_atomically(dir / "report.json", study::report_json(result));
  io::write_text_atomically(dir / "scene-study.config.toml",
                            "# effective configuration written by scene-study\n" + config);
}

/// The study's last lines on stdout: the plan and, with --results, each method's worst increment.
void print_summary(const fs::path& dir, const study::SceneStudyResult& result,
                   const std::vector<const study::SceneNetwork*>& networks,
                   const std::optional<study::HistoryJudgement>& judged) {
  const study::SceneStudyOptions& o = result.options;
  const study::MethodMeasurement& chosen = result.plan();
  std::printf(
      "scene-study: plan %s%s -> %s; held-out effective mean |error| %.4g (target %g: %s), %.1f ns/query; "
      "%.1f s\n",
      chosen.method.c_str(),
      chosen.network >= 0 ? (" with " + networks[static_cast<std::size_t>(chosen.network)]->name).c_str()
                          : "",
      (dir / "plan.toml").string().c_str(), chosen.effective_mean, o.target,
      chosen.reaches ? "reached" : "NOT reached", chosen.batched_ns, result.seconds);
  if (judged) {
    for (std::size_t m = 0; m < judged->methods.size(); ++m) {
      const std::size_t w = judged->worst(m);
      double worst_out = 0.0;
      long missed = 0;
      for (std::size_t i = 0; i < judged->increments.size(); ++i) {
        worst_out = std::max(worst_out, judged->cells[m][i].out_of_domain_fraction());
        missed += judged->meets(m, i) ? 0 : 1;
      }
      char out_of_domain[64] = "";
      if (judged->methods[m].network >= 0) {
        std::snprintf(out_of_domain, sizeof out_of_domain, "; at most %.2f%% out of domain",
                      100.0 * worst_out);
      }
      std::printf(
          "scene-study: history %s%s: worst increment %d, mean |error| %.4g%s; target %s on %ld of %zu "
          "increments\n",
          judged->methods[m].name.c_str(), judged->methods[m].role().c_str(), judged->increments[w],
          judged->cells[m][w].worse_mean(), out_of_domain, missed == 0 ? "met" : "missed",
          missed == 0 ? static_cast<long>(judged->increments.size()) : missed, judged->increments.size());
    }
  }
}

/// The scene study (scene_study.hpp's steps 2 to 10) of the deck and pair of `a`.
int run_scene_study(const CLI::App& app, Args& a, const std::vector<io::NamedPath>& inputs,
                    const std::string& command_line, Clock::time_point start) {
  const std::string &scene_path = a.scene_path, &results_path = a.results_path;
  const int pair = a.pair;
  const bool quiet = a.quiet;
  // 2. The options resolved for the surface, and the output directory made and checked before any work.
  const SurfaceKind surface = resolve_scene_options(a);
  const study::SceneStudyOptions& o = a.o;
  const fs::path dir(a.output);
  io::require_outputs({},
                      {{"--output",
                        dir,
                        {"plan.toml", "network.h5", "pairs.csv", "report.md", "report.json", "history.csv",
                         "scene-study.config.toml"}}},
                      inputs);
  if (a.check_only) return 0;
  const std::string config =
      cli::effective_config(app, "scene-study", {"output", "threads", "quiet", "check"});
  const auto say = [&](std::string_view line) {
    if (!quiet) std::printf("  %.*s\n", static_cast<int>(line.size()), line.data()), std::fflush(stdout);
  };
  if (!quiet) std::printf("scene-study: %s pair %d, %s\n", scene_path.c_str(), pair, a.surface_name.c_str());

  // 3. The deck, read once: the pair's master faces, node normals and slave nodes.
  //    With --results, the results file too, checked against the deck before anything is written.
  mesh::ContactModel model = io::read_inp_deck(scene_path);
  (void)cli::warn_unapplied_geometry("scene-study", scene_path);
  std::optional<io::FrdResults> results;
  if (!results_path.empty()) {
    results = io::read_frd(results_path);
    if (!a.trust_nodes) io::check_node_block(model, *results);
  }
  const contact::Scene scene = contact::make_scene(model, pair);
  if (scene.slave_ids.empty()) {
    std::fprintf(stderr, "scene-study: pair %d of %s has no slave nodes: nothing to study\n", pair,
                 scene_path.c_str());
    return 1;
  }

  // 4. The search, once: every slave node's closest point (SPEC 9); pairs.csv.
  const study::ScenePairs pairs = study::search_pairs(scene, surface);
  if (pairs.result.found == 0) {
    std::fprintf(
        stderr,
        "scene-study: none of the %zu slave nodes of pair %d of %s has a master face (all no_segment): "
        "nothing to study\n",
        scene.slave_ids.size(), pair, scene_path.c_str());
    return 1;
  }
  io::make_output_directory("--output", dir);
  io::write_text_atomically(dir / "pairs.csv", study::pairs_csv(scene, pairs, surface));
  say("pairs: face " + std::to_string(pairs.locations[0]) + ", edge " + std::to_string(pairs.locations[1]) +
      ", vertex " + std::to_string(pairs.locations[2]) + ", no_segment " +
      std::to_string(pairs.result.no_segment));

  // 4b. With --results: the pair at every increment of the run (SPEC 10), the nodes moved as gen-configs
  //     --results moves them.
  std::vector<study::HistoryState> history;
  if (results) history = study::history_states(std::move(model), *results, pair, say);

  // 5-8. The scene's domain, the sizes that could pay, trained; every method measured; the plan.
  study::SceneStudyResult result = plan_study(scene, history, surface, o, say, start);
  const std::vector<const study::SceneNetwork*> networks = networks_of(result);
  result.deck = scene_path;
  result.pair = pair;
  result.command_line = command_line;
  result.slave_nodes = scene.slave_ids.size();
  result.no_segment = pairs.result.no_segment;
  result.locations = pairs.locations;
  result.quad4 = pairs.quad4;

  // 9. The deck's pairs judged; the node orders of every pair.
  judge_pairs(pairs, surface, networks, result, say);

  // 9b. With --results: the scene networks and the plan's method on every increment's pairs.
  std::optional<study::HistoryJudgement> judged;
  if (!history.empty()) {
    judged = study::judge_history(
        history, surface, networks,
        study::history_methods(networks, result.training.scene, result.measured, result.chosen), o, say);
    judged->results = results_path;
    judged->domain = std::string(study::to_string(o.domain_states));
    result.history_increments = static_cast<int>(history.size());
    result.history_markdown = study::history_markdown(*judged);
    result.history_json = study::history_json(*judged);
  }
  result.results = results_path;
  result.seconds = seconds_since(start);

  // 10. The plan (and its network), the report.
  write_study(dir, result, networks, judged, config);
  print_summary(dir, result, networks, judged);
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  using namespace contactnn;
  CLI::App app{
      "scene-study: the fastest local-search method that reaches a scene's target, a network only where "
      "one pays (SPEC 7)"};
  cli::add_exit_code_footer(app);
  cli::add_config_option(app, "scene-study");

  // 1. Options. Every default lives in study::SceneStudyOptions; flags only map onto it.
  Args a;
  add_input_options(app, a);
  add_study_options(app, a);

  return cli::run(app, argc, argv, [&]() -> int {
    const auto start = Clock::now();
    if (a.o.threads > 0) omp_set_num_threads(a.o.threads);
    const std::vector<io::NamedPath> inputs = {
        {"--scene", a.scene_path}, {"--results", a.results_path}, {"--config", cli::config_path(app)}};
    if (!a.face_name.empty()) {
      CONTACTNN_REQUIRE_AS(InvalidArgument, a.results_path.empty(), "--face: --results is not supported yet");
      const study::FaceStudyOptions f = face_options(app, a);
      CONTACTNN_REQUIRE_AS(
          InvalidArgument, a.general != !a.scene_path.empty(),
          "--face: give --scene DECK (the deck's faces) or --general (the paper-like domain), not both");
      return run_face_mode(a.scene_path, a.pair, search::face_kind_from_string(a.face_name), f, a.output,
                           inputs, a.check_only, a.quiet, cli::join_command_line(argc, argv),
                           a.general ? a.curvature : -1.0);
    }
    return run_scene_study(app, a, inputs, cli::join_command_line(argc, argv), start);
  });
}
