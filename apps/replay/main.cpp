// replay: a simulation replayed increment by increment (SPEC 10 histories).
//
// Description:
//   Reads a deck and a CalculiX result file, and at every increment of the file: moves the deck's nodes to
//   the increment's coordinates, searches the contact pair's master surface fresh and by tracking (a
//   Verlet list with warm starts, lib/contact/tracking.hpp: the same answers, counted), runs the local
//   search of each method on the pairs inside faces, warm starts (start+newton:K from the previous
//   increment's point on the nodes that keep their face), and compares the gaps with CalculiX's own
//   contact openings where the file has them. Timings per slave node of each phase.
//
// Sample runs:
//   replay --scene hertz-slide.inp --results hertz-slide.frd --report /tmp/replay-hertz
//   replay --scene DECK.inp --pair 1 --results RUN.frd --surface gregory --methods newton:5,closed_form
//          --warm_steps 0,1,2 --threads 2 --report /tmp/replay
//   replay --scene forming-stroke.inp --results forming-stroke.frd --plan study/plan.toml --report /tmp/r
//
// --plan PLAN (a scene-study plan.toml) or --method NAME: the surface search is also run with that method on
// face interiors (contact/narrow_phase.hpp: a pair it refuses or puts outside the face takes the exact
// closest point), fresh and tracked, timed beside the exact search, and its answers judged against the exact
// ones per increment (report.md's section "The plan in the loop", increments.csv's plan:* columns).
//
// Writes (in --report): report.md, increments.csv, time.svg, error.svg, locations.svg; a summary on stdout,
// progress on stderr.
#include <chrono>
#include <cstdio>
#include <optional>
#include <sstream>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "history/plan_search.hpp"
#include "history/replay.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "io/network_model_file.hpp"
#include "io/output_checks.hpp"
#include "search/method.hpp"

namespace {

using namespace contactnn;

/// The command line's values that are not ReplayOptions fields themselves.
struct Paths {
  std::string deck, results, report, surface = "bilinear", methods, warm_steps, weights, narrow = "certified";
  std::string plan, method;
  bool quiet = false, trust_nodes = false;
};

/// Step 1: the options; every default lives in history::ReplayOptions.
void add_options(CLI::App& app, history::ReplayOptions& options, Paths& paths) {
  app.add_option("--scene", paths.deck, "the deck (.inp, SPEC 7)")->required()->check(CLI::ExistingFile);
  app.add_option("--pair", options.pair, "the *CONTACT PAIR data line, from 0")
      ->transform(cli::integer_in(0, 1000000));
  app.add_option("--results", paths.results, "CalculiX's .frd of a run of the deck (SPEC 10)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--report", paths.report, "folder for report.md, increments.csv and the plots")->required();
  app.add_option("--surface", paths.surface, "bilinear or gregory (with --plan: the plan's, by default)")
      ->check(CLI::IsMember({"bilinear", "gregory"}));
  app.add_option("--methods", paths.methods,
                 "cold local-search methods, comma-separated (default newton:3,newton:5,"
                 "closed_form,closed_form+newton:2)");
  app.add_option("--warm_steps", paths.warm_steps,
                 "K of start+newton:K from the previous increment, comma-separated "
                 "(default 0,1,2,3)");
  app.add_option("--weights", paths.weights, "a network file, for network methods")->check(CLI::ExistingFile);
  auto* plan = app.add_option("--plan", paths.plan,
                              "a scene plan (scene-study's plan.toml): the surface search also run with its "
                              "method on face interiors, judged against the exact search and timed beside it")
                   ->check(CLI::ExistingFile);
  app.add_option("--method", paths.method,
                 "as --plan, with this lib/search method (a network method takes --weights)")
      ->excludes(plan);
  app.add_option("--capture_distance", options.search.capture_distance,
                 "surface search: faces within this distance (default: the largest master face size)")
      ->check(cli::kPositive);
  app.add_option(
         "--narrow", paths.narrow,
         "surface search: certified (one Newton run where a certificate proves it the face's nearest, the "
         "reference elsewhere; the reference search is also run beside it) or reference (the grid of "
         "starts on every face, as before the certificate)")
      ->check(CLI::IsMember({"certified", "reference"}));
  app.add_option("--margin", options.tracking.margin_relative,
                 "tracking: list margin in units of the capture distance")
      ->check(cli::real_in(0.0, 100.0));
  app.add_option("--repeats", options.repeats, "timings: the fastest of this many runs")
      ->transform(cli::integer_in(1, 100));
  app.add_option("--threads", options.threads, "OpenMP threads of every phase")
      ->transform(cli::integer_in(1, cli::kMaxThreads));
  app.add_flag(
      "--trust-results-nodes", paths.trust_nodes,
      "take the .frd's node coordinates even where they are not the deck's (another mesh with the same "
      "node ids is refused otherwise)");
  app.add_flag("--quiet", paths.quiet, "no progress line");
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) parts.push_back(part);
  return parts;
}

/// Step 2: settings: surface, methods, the network, the plan (whose surface is the search's unless --surface
/// names another: InvalidArgument).
std::unique_ptr<search::NetworkModel> apply_settings(const CLI::App& app, const Paths& paths,
                                                     history::ReplayOptions& options,
                                                     std::optional<history::PlanSearch>& plan) {
  options.search.surface = surface_from_string(paths.surface);
  options.search.narrow =
      paths.narrow == "reference" ? contact::NarrowPhase::kReference : contact::NarrowPhase::kCertified;
  if (!paths.methods.empty()) options.methods = split(paths.methods);
  if (!paths.warm_steps.empty()) {
    options.warm_steps.clear();
    for (const std::string& k : split(paths.warm_steps)) {
      options.warm_steps.push_back(search::Method::parse("start+newton:" + k).newton_steps);
    }
  }
  std::unique_ptr<search::NetworkModel> network;
  if (!paths.weights.empty()) {
    network = io::read_network_model(paths.weights);
    options.network = network.get();
  }
  if (!paths.plan.empty()) {
    plan.emplace(history::load_plan_search(paths.plan));
    const bool surface_given = app.count("--surface") > 0;
    CONTACTNN_REQUIRE_AS(InvalidArgument, !surface_given || plan->plan.surface == options.search.surface,
                         "--surface " << paths.surface << ": the plan '" << paths.plan << "' is for "
                                      << to_string(plan->plan.surface) << " surfaces");
    options.search.surface = plan->plan.surface;
    options.plan_target = plan->plan.target;
  } else if (!paths.method.empty()) {
    plan.emplace(history::method_search(paths.method, options.search.surface, paths.weights));
  }
  if (plan) {
    options.plan = plan->locator.get();
    options.plan_label = plan->label;
  }
  return network;
}

/// The summary on stdout.
void print_summary(const std::vector<history::IncrementRow>& rows, const history::ReplayOptions& options,
                   std::size_t unapplied, const std::string& report, double seconds) {
  long differences = 0, found = 0, slaves = 0, refused = 0, missed = 0;
  for (const auto& r : rows) {
    differences += r.tracking_differences;
    found += r.found;
    slaves += r.slaves;
    refused += r.plan.refused;
    if (options.plan_target > 0.0 && r.plan.mean_error > options.plan_target) ++missed;
  }
  std::printf(
      "replay summary\n  increments           %zu\n  slave node states    %ld (%ld with a point)\n"
      "  tracking differences %ld\n  beyond capture       %ld slave node states (no face within the "
      "capture distance: no_segment)\n  not applied          %zu keyword(s) that change the contact "
      "geometry%s\n",
      rows.size(), slaves, found, differences, slaves - found, unapplied,
      unapplied > 0 ? " (named on stderr)" : "");
  if (options.plan != nullptr) {
    std::printf("  plan                 %s: %ld refused, target missed at %ld increment(s)\n",
                options.plan_label.c_str(), refused, missed);
  }
  std::printf("  report               %s/report.md\n  time                 %.2f s\n", report.c_str(),
              seconds);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "replay: a CalculiX history replayed increment by increment: surface search fresh and tracked, "
      "local search, warm starts, CalculiX's contact output, a plan's search in the loop"};
  cli::add_exit_code_footer(app);
  cli::add_config_option(app, "replay");
  history::ReplayOptions options;
  Paths paths;
  add_options(app, options, paths);

  return cli::run(app, argc, argv, [&]() -> int {
    // 1b. The report directory, before anything is read or written: it is replaced whole (an earlier report
    //     only), so it may be no input and hold none (exit 2), and it must be writable (exit 4).
    const std::initializer_list<std::string> report_files = {"report.md", "increments.csv", "time.svg",
                                                             "error.svg", "locations.svg"};
    io::require_outputs({}, {{"--report", paths.report, report_files, true}},
                        {{"--scene", paths.deck},
                         {"--results", paths.results},
                         {"--weights", paths.weights},
                         {"--plan", paths.plan},
                         {"--config", cli::config_path(app)}});
    io::AtomicDirectory report_directory(paths.report, report_files, "--report");
    // 2. Settings: surface, methods, the network, the plan.
    std::optional<history::PlanSearch> plan;
    const std::unique_ptr<search::NetworkModel> network = apply_settings(app, paths, options, plan);
    // 3. The deck and the results file (their node ids must match: exit 3 otherwise).
    mesh::ContactModel model = io::read_inp_deck(paths.deck);
    const std::vector<std::string> unapplied = cli::warn_unapplied_geometry("replay", paths.deck);
    const io::FrdResults results = io::read_frd(paths.results);
    if (!paths.trust_nodes) io::check_node_block(model, results);
    // 4. Replay every increment; 5. the report.
    cli::Progress progress("replay: increments", paths.quiet);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<history::IncrementRow> rows = history::replay(
        std::move(model), results, options, [&](int done, int total) { progress.update(done, total); });
    progress.finish();
    const std::string title = paths.deck + " pair " + std::to_string(options.pair) + ", " + paths.results;
    history::write_replay_report(report_directory.write_path().string(), title, options, rows);
    report_directory.commit();
    print_summary(rows, options, unapplied.size(), paths.report,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
  });
}
