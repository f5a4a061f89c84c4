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
//
// Writes (in --report): report.md, increments.csv, time.svg, error.svg, locations.svg; a summary on stdout,
// progress on stderr.
#include <chrono>
#include <cstdio>
#include <sstream>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "history/replay.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "io/network_model_file.hpp"
#include "io/output_checks.hpp"
#include "search/method.hpp"

int main(int argc, char** argv) {
  using namespace contactnn;
  CLI::App app{
      "replay: a CalculiX history replayed increment by increment: surface search fresh and tracked, "
      "local search, warm starts, CalculiX's contact output"};
  cli::add_exit_code_footer(app);
  cli::add_config_option(app, "replay");

  // 1. Options; every default lives in history::ReplayOptions.
  history::ReplayOptions options;
  std::string deck, results_path, report, surface_name = "bilinear", methods, warm_steps, weights;
  bool quiet = false;
  app.add_option("--scene", deck, "the deck (.inp, SPEC 7)")->required()->check(CLI::ExistingFile);
  app.add_option("--pair", options.pair, "the *CONTACT PAIR data line, from 0")
      ->transform(cli::integer_in(0, 1000000));
  app.add_option("--results", results_path, "CalculiX's .frd of a run of the deck (SPEC 10)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--report", report, "folder for report.md, increments.csv and the plots")->required();
  app.add_option("--surface", surface_name, "bilinear or gregory")
      ->check(CLI::IsMember({"bilinear", "gregory"}));
  app.add_option("--methods", methods,
                 "cold local-search methods, comma-separated (default newton:3,newton:5,"
                 "closed_form,closed_form+newton:2)");
  app.add_option("--warm_steps", warm_steps,
                 "K of start+newton:K from the previous increment, comma-separated "
                 "(default 0,1,2,3)");
  app.add_option("--weights", weights, "a network file, for network methods")->check(CLI::ExistingFile);
  app.add_option("--capture_distance", options.search.capture_distance,
                 "surface search: faces within this distance (default: the largest master face size)")
      ->check(cli::kPositive);
  std::string narrow_name = "certified";
  app.add_option(
         "--narrow", narrow_name,
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
  bool trust_nodes = false;
  app.add_flag(
      "--trust-results-nodes", trust_nodes,
      "take the .frd's node coordinates even where they are not the deck's (another mesh with the same "
      "node ids is refused otherwise)");
  app.add_flag("--quiet", quiet, "no progress line");

  return cli::run(app, argc, argv, [&]() -> int {
    // 1b. The report directory, before anything is read or written: it is replaced whole (an earlier report
    //     only), so it may be no input and hold none (exit 2), and it must be writable (exit 4).
    const std::initializer_list<std::string> report_files = {"report.md", "increments.csv", "time.svg",
                                                             "error.svg", "locations.svg"};
    io::require_outputs({}, {{"--report", report, report_files, true}},
                        {{"--scene", deck},
                         {"--results", results_path},
                         {"--weights", weights},
                         {"--config", cli::config_path(app)}});
    io::AtomicDirectory report_directory(report, report_files, "--report");
    // 2. Settings: surface, methods, the network.
    options.search.surface = surface_from_string(surface_name);
    options.search.narrow =
        narrow_name == "reference" ? contact::NarrowPhase::kReference : contact::NarrowPhase::kCertified;
    const auto split = [](const std::string& text) {
      std::vector<std::string> parts;
      std::stringstream in(text);
      for (std::string part; std::getline(in, part, ',');) parts.push_back(part);
      return parts;
    };
    if (!methods.empty()) options.methods = split(methods);
    if (!warm_steps.empty()) {
      options.warm_steps.clear();
      for (const std::string& k : split(warm_steps)) {
        const search::Method m = search::Method::parse("start+newton:" + k);
        options.warm_steps.push_back(m.newton_steps);
      }
    }
    std::unique_ptr<search::NetworkModel> network;
    if (!weights.empty()) {
      network = io::read_network_model(weights);
      options.network = network.get();
    }
    // 3. The deck and the results file (their node ids must match: exit 3 otherwise).
    mesh::ContactModel model = io::read_inp_deck(deck);
    const std::vector<std::string> unapplied = cli::warn_unapplied_geometry("replay", deck);
    const io::FrdResults results = io::read_frd(results_path);
    if (!trust_nodes) io::check_node_block(model, results);
    // 4. Replay every increment; 5. the report.
    cli::Progress progress("replay: increments", quiet);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<history::IncrementRow> rows =
        history::replay(model, results, options, [&](int done, int total) { progress.update(done, total); });
    progress.finish();
    const std::string title = deck + " pair " + std::to_string(options.pair) + ", " + results_path;
    history::write_replay_report(report_directory.write_path().string(), title, options, rows);
    report_directory.commit();
    long differences = 0, found = 0, slaves = 0;
    for (const auto& r : rows) {
      differences += r.tracking_differences;
      found += r.found;
      slaves += r.slaves;
    }
    std::printf(
        "replay summary\n  increments           %zu\n  slave node states    %ld (%ld with a point)\n"
        "  tracking differences %ld\n  beyond capture       %ld slave node states (no face within the "
        "capture distance: no_segment)\n  not applied          %zu keyword(s) that change the contact "
        "geometry%s\n  report               %s/report.md\n  time                 %.2f s\n",
        rows.size(), slaves, found, differences, slaves - found, unapplied.size(),
        unapplied.empty() ? "" : " (named on stderr)", report.c_str(),
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
  });
}
