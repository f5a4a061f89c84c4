// evaluate-net: apply trained networks, and measure every local-search method's accuracy and speed.
//
// Description:
//   Report mode runs every method of lib/search (networks, Newton with k steps and to convergence, the
//   bilinear closed form, the hybrids) on one or more evaluation sets (gen-configs datasets: the paper's
//   grid, a held-out random sample, a scene's domain; scene pairs files from gen-configs --scene) and
//   compares each with the reference labels: errors, gap errors, inside/outside agreement, failures, and the
//   time per query one at a time and batched at 1 and several threads, all in one run (paper Sections 5.3
//   and 6.3.3: Table 1, Figs 4, 10 and 11). Input mode applies one network (SPEC 6), optionally followed by K
//   Newton steps (SPEC 8), to a user's configurations in world coordinates; with --plan, the method (and
//   network) a scene plan names (scene-study's DIR/plan.toml, SPEC 7).
//
// Sample runs:
//   evaluate-net --config configs/bilinear-paper.toml --weights data/weights/bilinear-8.h5
//                --data data/bilinear.h5 --report reports/bilinear     (one line)
//   evaluate-net --weights data/weights/gregory-48.h5 --weights data/weights/gregory-32.h5
//                --data data/gregory-random.h5 --pairs /tmp/hertz-pairs.csv --report /tmp/frontier
//   evaluate-net --weights data/weights/bilinear-8.h5 --input data/examples/raw-bilinear.csv --output
//   /tmp/pred.csv evaluate-net --weights data/weights/gregory-48.h5 --input data/examples/raw-gregory.csv
//   --output /tmp/p.csv
//                --newton-steps 2
//   evaluate-net --plan /tmp/hertz-study/plan.toml --input /tmp/hertz-pairs.csv --output /tmp/p.csv
//   evaluate-net --frontier reports/frontier/bilinear --frontier_json /tmp/ranking.json
//                --frontier_svg /tmp/frontier.svg --frontier_label bilinear="bilinear, grid"
//
// Writes:
//   report mode: DIR/errors.csv, DIR/speed.csv, DIR/hist_<xi|eta|u|v>.csv and .svg, DIR/report.md,
//                DIR/evaluate-net.config.toml (effective config); a summary on stdout, progress on stderr.
//                DIR is written under a temporary name and put in place whole; an existing DIR is replaced
//                only if it holds nothing but these files.
//   input mode:  OUTPUT (.csv): the input columns, then xi,eta (u,v for Gregory),status; one row per input
//   row,
//                in input order. status: ok; out_of_domain (outside the network's training domain; the
//                prediction is still written); with --newton-steps K > 0 the steps' outcome (ok, outside,
//                no_convergence); invalid (non-finite input), degenerate (no canonical frame), no_segment (a
//                pairs row without coordinates): values empty. Rows are streamed in chunks (bounded memory).
//                With --plan: the same columns for the plan's method (search/local_search.hpp lists the
//                statuses of each); the plan's surface decides the columns read (SPEC 6).
//   frontier mode: a finished report's methods ranked (lib/eval/ranking.hpp: the effective mean error,
//                the fastest method at each accuracy level, the Pareto front) as JSON (--frontier_json), and
//                plotted (--frontier_svg, lib/eval/frontier_plot.hpp); what scripts/frontier reads.
#include <omp.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <thread>

#include "build_info.hpp"
#include "cli_support.hpp"
#include "core/error.hpp"
#include "eval/frontier_plot.hpp"
#include "eval/method_comparison.hpp"
#include "eval/ranking.hpp"
#include "eval/report.hpp"
#include "io/atomic_output.hpp"
#include "io/csv.hpp"
#include "io/dataset_file.hpp"
#include "io/file_identity.hpp"
#include "io/network_file.hpp"
#include "io/output_checks.hpp"
#include "io/plan_file.hpp"
#include "io/raw_configurations.hpp"
#include "search/local_search.hpp"

namespace {

using namespace contactnn;

/// What a report directory may hold: the files report mode writes (docs/tools.md, "evaluate-net"). Only a
/// directory holding nothing else is replaced.
const std::initializer_list<std::string> kReportFiles = {
    "errors.csv",  "speed.csv",    "hist_xi.csv", "hist_eta.csv", "hist_u.csv", "hist_v.csv",
    "hist_xi.svg", "hist_eta.svg", "hist_u.svg",  "hist_v.svg",   "report.md",  "evaluate-net.config.toml"};

/// The files and switches of one run (every numeric setting lives in eval::ComparisonOptions).
struct Paths {
  std::vector<std::string> weights, data, pairs;
  std::string report, input, output, plan;
  std::string frontier, frontier_json, frontier_svg;
  std::vector<std::string> frontier_labels;  ///< SET=TEXT
  int newton_steps = 0;
  bool quiet = false;
  std::string command_line;
};

/// A network file read and made ready for lib/search.
struct LoadedNetwork {
  std::string path, name, summary;
  std::unique_ptr<search::NetworkModel> model;
};

template <class Real>
LoadedNetwork load_as(const std::string& path) {
  const io::TrainedNetwork<Real> trained = io::read_network<Real>(path);
  LoadedNetwork n;
  n.path = path;
  n.name = std::filesystem::path(path).stem().string();
  for (std::size_t i = 0; i < trained.network.layer_sizes().size(); ++i) {
    n.summary += (i > 0 ? "-" : "") + std::to_string(trained.network.layer_sizes()[i]);
  }
  char u0[32];
  std::snprintf(u0, sizeof u0, "%g", trained.network.u0());
  n.summary += std::string(", ") + (std::is_same_v<Real, float> ? "float" : "double") + ", U0 = " + u0 +
               ", " + std::string(to_string(trained.network.scaling().input_features)) + " inputs, `" + path +
               "`";
  n.model = std::make_unique<search::NetworkModel>(trained.network, trained.domain);
  return n;
}

/// Reads a network in the precision it was trained in.
LoadedNetwork load_network(const std::string& path) {
  return io::read_network_real_type(path) == "float64" ? load_as<double>(path) : load_as<float>(path);
}

/// Input mode (SPEC 6, SPEC 7, SPEC 8): RAW.csv streamed in chunks of io::kRawChunkRows rows through one
/// batched call of lib/search per chunk (network, network+newton:K, or a plan's method); the output appears
/// only when every row is done. `network` may be null for a method without one.
int input_mode(SurfaceKind kind, const search::Method& method, const search::NetworkModel* network,
               const Paths& paths) {
  const search::LocalSearch search(kind, method, {}, network);
  const auto names = coordinate_names(kind);
  const std::vector<std::string> header = {std::string(names[0]), std::string(names[1]), "status"};
  const std::size_t columns = static_cast<std::size_t>(search::LocalSearch::raw_columns(kind));
  std::array<std::int64_t, kStatusCount> counts{};
  std::vector<double> raw, param;
  std::vector<Status> status;
  std::vector<std::string> replaced;
  const std::size_t n = io::map_raw_configurations(
      paths.input, paths.output, kind, header,
      [&](const io::RawChunk& chunk, std::vector<std::vector<std::string>>& rows) {
        raw.clear();
        for (const geometry::Configuration& c : chunk.configs) {
          for (const auto& node : c.nodes) raw.insert(raw.end(), {node.x(), node.y(), node.z()});
          raw.insert(raw.end(), {c.slave.x(), c.slave.y(), c.slave.z()});
          if (columns == 27) {
            for (const auto& v : c.normals) raw.insert(raw.end(), {v.x(), v.y(), v.z()});
          }
        }
        param.resize(2 * chunk.size());
        status.resize(chunk.size());
        search.run(chunk.size(), raw.data(),
                   search::Results<double>{param.data(), nullptr, status.data(), nullptr});
        for (std::size_t r = 0; r < chunk.size(); ++r) {
          if (chunk.no_segment[r] != 0) status[r] = Status::kNoSegment;  // SPEC 7: nothing to predict
          const Status s = status[r];
          const bool has_value = s == Status::kOk || s == Status::kOutside || s == Status::kOutOfDomain;
          CONTACTNN_REQUIRE_AS(
              NumericalError, !has_value || (std::isfinite(param[2 * r]) && std::isfinite(param[2 * r + 1])),
              "'" << paths.input << "' line " << chunk.line_numbers[r] << ": a non-finite estimate");
          rows[r] = {has_value ? io::format_double(param[2 * r]) : "",
                     has_value ? io::format_double(param[2 * r + 1]) : "", std::string(to_string(s))};
          ++counts[static_cast<std::size_t>(s)];
        }
      },
      &replaced);
  cli::warn_about_raw_output("evaluate-net's", paths.input, paths.output, replaced, n);
  std::printf("evaluate-net: %lld rows -> %s (%s)\n", static_cast<long long>(n), paths.output.c_str(),
              method.name().c_str());
  for (int s = 0; s < kStatusCount; ++s) {
    if (counts[static_cast<std::size_t>(s)] == 0) continue;
    std::printf("  %-15s %lld\n", std::string(to_string(static_cast<Status>(s))).c_str(),
                static_cast<long long>(counts[static_cast<std::size_t>(s)]));
  }
  return 0;
}

int report_mode(const std::vector<LoadedNetwork>& networks, const Paths& paths,
                const eval::ComparisonOptions& options, const std::string& effective_config,
                io::AtomicDirectory& report) {
  // 1. The sets, each of the networks' surface (the first set's when there is no network).
  std::vector<eval::EvaluationSet> sets;
  for (const std::string& path : paths.data) {
    const dataset::LabelledSet set = io::read_dataset(path);
    const auto ok_rows = std::count(set.status.begin(), set.status.end(), Status::kOk);
    CONTACTNN_REQUIRE_AS(
        FormatError, ok_rows > 0,
        "'" << path << "' holds " << set.size()
            << " configurations and none with status ok: nothing to report (no error can be measured)");
    sets.push_back(eval::set_from_dataset(set, std::filesystem::path(path).stem().string(), path,
                                          options.random_placement, options.seed));
  }
  const SurfaceKind kind = !networks.empty() ? networks.front().model->surface()
                           : !sets.empty()   ? sets.front().surface
                                             : SurfaceKind::kBilinear;
  for (const std::string& path : paths.pairs) sets.push_back(eval::set_from_labelled_csv(path, kind));
  for (const eval::EvaluationSet& s : sets) {
    CONTACTNN_REQUIRE_AS(FormatError, s.surface == kind,
                         "'" << s.source << "' is a " << to_string(s.surface) << " set but the study is "
                             << to_string(kind) << (networks.empty() ? "" : " (the networks')"));
  }
  std::vector<eval::EvaluatedNetwork> evaluated;
  for (const LoadedNetwork& n : networks) evaluated.push_back({n.name, n.summary, n.model.get()});

  // 2. The study: accuracy in parallel, timing as stated in the report.
  const auto log = [&](std::string_view line) {
    if (!paths.quiet)
      std::fprintf(stderr, "evaluate-net: %.*s\n", static_cast<int>(line.size()), line.data());
  };
  const eval::ComparisonResult result = eval::compare_methods(sets, evaluated, options, log);

  // 3. Provenance and the report files, written into a temporary directory and put in place whole: an
  //    interrupted or failed run leaves the previous report as it was, never half of each.
  eval::RunInfo info;
  info.command_line = paths.command_line;
  info.cpu_model = eval::cpu_model();
  info.hardware_threads = static_cast<int>(std::thread::hardware_concurrency());
  info.accuracy_threads = omp_get_max_threads();
  info.compiler = CONTACTNN_COMPILER;
  info.build_type = CONTACTNN_BUILD_TYPE;
  info.cxx_flags = CONTACTNN_CXX_FLAGS;
  info.cxx_flags.erase(0, info.cxx_flags.find_first_not_of(' '));
  info.effective_config = effective_config;
  eval::write_report(report.write_path(), result, info, options);
  io::write_text_atomically(report.write_path() / "evaluate-net.config.toml",
                            "# effective configuration written by evaluate-net\n" + effective_config);
  report.commit();

  // 4. Summary: the first network on every set.
  const auto names = coordinate_names(kind);
  std::printf("evaluate-net summary (%zu method(s) on %zu set(s))\n", result.methods.size(),
              result.sets.size());
  for (const eval::SetResult& s : result.sets) {
    for (const eval::MethodErrors& m : s.errors) {
      if (m.method != result.histogram_method &&
          !(result.histogram_method.empty() && &m == &s.errors.front()))
        continue;
      std::printf("  %-16s %s mean |error| %s %.4g, %s %.4g (%lld rows, failures %lld, out of domain %lld)\n",
                  s.name.c_str(), m.method.c_str(), std::string(names[0]).c_str(), m.stats[0].mean_abs,
                  std::string(names[1]).c_str(), m.stats[1].mean_abs, static_cast<long long>(m.rows),
                  static_cast<long long>(m.failures_reference + m.failures_method),
                  static_cast<long long>(m.out_of_domain));
    }
  }
  std::printf("  report           %s/report.md\n", paths.report.c_str());
  return 0;
}

/// Frontier mode: the methods of a finished report (DIR/errors.csv, DIR/speed.csv) ranked as JSON and
/// plotted, one panel per set, titled "LABEL: SET (ROWS queries)" (the label from --frontier_label, if any).
int frontier_mode(const Paths& paths) {
  const eval::ComparisonResult result = eval::read_report_tables(paths.frontier);
  std::vector<std::pair<std::string, std::string>> labels;
  for (const std::string& item : paths.frontier_labels) {
    const auto eq = item.find('=');
    CONTACTNN_REQUIRE_AS(InvalidArgument, eq != std::string::npos && eq > 0,
                         "--frontier_label '" << item << "': expected SET=TEXT");
    labels.emplace_back(item.substr(0, eq), item.substr(eq + 1));
  }
  if (!paths.frontier_json.empty()) {
    io::write_text_atomically(paths.frontier_json, eval::ranking_json(result));
  }
  if (!paths.frontier_svg.empty()) {
    std::vector<eval::FrontierPanel> panels;
    for (const eval::SetResult& s : result.sets) {
      std::string title = s.name + " (" + std::to_string(s.errors.front().stats[0].rows) + " queries)";
      for (const auto& [set, text] : labels) {
        if (set == s.name) title = text + ": " + title;
      }
      panels.push_back({title, eval::frontier_points(s, result.surface)});
    }
    io::write_text_atomically(paths.frontier_svg, eval::frontier_svg(panels));
  }
  std::printf("evaluate-net: %zu set(s) of %s ranked%s%s\n", result.sets.size(), paths.frontier.c_str(),
              paths.frontier_json.empty() ? "" : (" -> " + paths.frontier_json).c_str(),
              paths.frontier_svg.empty() ? "" : (" -> " + paths.frontier_svg).c_str());
  return 0;
}

/// The options naming files, and the modes they select (docs/tools.md, "evaluate-net").
void add_file_options(CLI::App& app, Paths& paths) {
  app.add_option(
         "--weights", paths.weights,
         "network file of train-net (.h5); report mode: repeat for several networks, each with its methods")
      ->check(CLI::ExistingFile);
  auto* data =
      app.add_option("--data", paths.data, "report mode: labelled dataset of gen-configs (.h5); repeatable")
          ->check(CLI::ExistingFile);
  auto* pairs =
      app.add_option(
             "--pairs", paths.pairs,
             "report mode: labelled RAW.csv (gen-configs --scene pairs, label mode output); repeatable")
          ->check(CLI::ExistingFile);
  auto* report = app.add_option("--report", paths.report, "report mode: output directory");
  auto* input = app.add_option("--input", paths.input, "input mode: RAW.csv of world configurations (SPEC 6)")
                    ->check(CLI::ExistingFile);
  auto* output = app.add_option("--output", paths.output, "input mode: predictions .csv");
  auto* plan =
      app.add_option("--plan", paths.plan,
                     "input mode: a scene plan (scene-study's plan.toml, SPEC 7) in place of --weights: its "
                     "method, with its network if it names one")
          ->check(CLI::ExistingFile);
  auto* steps =
      app.add_option("--newton-steps", paths.newton_steps,
                     "input mode: safeguarded Newton steps after the network's estimate (SPEC 8; 0: the "
                     "network alone)")
          ->transform(cli::integer_in(0, 1000));
  input->needs(output);
  output->needs(input);
  steps->needs(input);
  plan->needs(input)->excludes(steps)->excludes(app.get_option("--weights"));
  input->excludes(data)->excludes(pairs)->excludes(report);
}

/// Frontier mode's options, after every other (the effective config keeps its order of keys).
void add_frontier_options(CLI::App& app, Paths& paths) {
  auto* frontier = app.add_option("--frontier", paths.frontier,
                                  "frontier mode: a finished report directory (errors.csv, speed.csv) whose "
                                  "methods are ranked and plotted")
                       ->check(CLI::ExistingDirectory);
  auto* json = app.add_option("--frontier_json", paths.frontier_json, "frontier mode: the ranking (.json)");
  auto* svg = app.add_option("--frontier_svg", paths.frontier_svg, "frontier mode: the plot (.svg)");
  auto* label = app.add_option("--frontier_label", paths.frontier_labels,
                               "frontier mode: SET=TEXT, the start of set SET's panel title; repeatable");
  json->needs(frontier);
  svg->needs(frontier);
  label->needs(svg);
  for (const char* other : {"--data", "--pairs", "--report", "--input", "--plan", "--weights"}) {
    frontier->excludes(app.get_option(other));
  }
}

/// The comparison's settings: every default lives in eval::ComparisonOptions and search::SearchOptions;
/// flags only map onto them.
void add_comparison_options(CLI::App& app, eval::ComparisonOptions& options, int& threads, bool& quiet) {
  app.add_option(
         "--methods", options.methods,
         "report mode: comma-separated search methods (network, newton:K, newton, closed_form, "
         "network+newton:K, closed_form+newton:K, start+newton:K with --start_offset; default: the default "
         "list); empty: the default list")
      ->default_str("");
  app.add_option(
         "--start_offset", options.start_offset,
         "report mode: start+newton:K starts from each reference point moved this far (parameter units) "
         "in a random direction; -1: no starts, the method is refused")
      ->check(cli::real_in(-1.0, 1e6));
  app.add_option("--threads", threads,
                 "OpenMP threads of the accuracy part and input mode (0: OpenMP's default)")
      ->transform(cli::integer_in(0, cli::kMaxThreads));
  app.add_flag("--quiet", quiet, "no progress lines");
  app.add_option("--seed", options.seed, "seed of the placements and the timing sample")
      ->transform(cli::integer_in(0, cli::kMaxSeed));
  app.add_option("--random_placement", options.random_placement,
                 "datasets placed at random in world coordinates instead of their own frame");
  app.add_option("--max_fixed_iterations", options.max_fixed_iterations,
                 "the default methods include newton:1..this")
      ->transform(cli::integer_in(1, 100));
  app.add_option("--failure_box_margin", options.failure_box_margin,
                 "an estimate more than this many domain widths outside the domain is a failure")
      ->check(cli::kPositive);
  app.add_option("--converged_max_iterations", options.search.max_iterations,
                 "Newton to convergence: iteration limit")
      ->transform(cli::integer_in(1, search::kMaxIterations));
  app.add_option("--converged_tol_param", options.search.tol_param,
                 "Newton to convergence: step tolerance (parameter units)")
      ->check(cli::real_in(0.0, search::kMaxTolParam));
  app.add_option("--hist_bins", options.hist_bins, "bins of the error histograms")
      ->transform(cli::integer_in(1, 100000));
  app.add_option("--hist_range", options.hist_range,
                 "histogram range [-r, r]; 0: a nice number above the 99.9th percentile of |error|")
      ->check(cli::real_in(0.0, 1e6));
  app.add_option("--timing", options.timing, "measure the speed of every method");
  app.add_option("--timing_queries", options.timing_queries, "queries per timed pass")
      ->transform(cli::integer_in(1, 100000000));
  app.add_option("--timing_threads", options.timing_threads, "threads of the multi-thread batched timing")
      ->transform(cli::integer_in(1, cli::kMaxThreads));
  app.add_option("--timing_repetitions", options.timing_options.repetitions, "timed passes per method")
      ->transform(cli::integer_in(1, 1000));
  app.add_option("--timing_warmup_passes", options.timing_options.warmup_passes,
                 "untimed passes per method first")
      ->transform(cli::integer_in(0, 100));
}

/// The mode the files ask for, checked: InvalidArgument for none or a mix.
void check_mode(const Paths& paths) {
  const bool report_mode_asked = !paths.data.empty() || !paths.pairs.empty();
  CONTACTNN_REQUIRE_AS(
      InvalidArgument,
      !paths.input.empty() || (report_mode_asked && !paths.report.empty()) || !paths.frontier.empty(),
      "give either --data DATASET.h5 and/or --pairs PAIRS.csv with --report DIR (report mode), or "
      "--input RAW.csv --output PRED.csv (input mode), or --frontier DIR (frontier mode)");
  CONTACTNN_REQUIRE_AS(InvalidArgument, paths.report.empty() || report_mode_asked,
                       "--report needs --data or --pairs");
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       paths.input.empty() || paths.weights.size() == 1 || !paths.plan.empty(),
                       "input mode applies one network or a plan: give exactly one --weights (got "
                           << paths.weights.size() << ") or --plan");
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       paths.frontier.empty() || !paths.frontier_json.empty() || !paths.frontier_svg.empty(),
                       "--frontier needs --frontier_json FILE and/or --frontier_svg FILE");
}

/// No output may be an input, and a report directory is replaced only if it holds nothing but an earlier
/// report (both checked before any work): the report directory to write into, or null.
std::unique_ptr<io::AtomicDirectory> check_outputs(const CLI::App& app, const Paths& paths) {
  std::vector<io::OutputDirectory> directories;
  if (!paths.report.empty()) directories.push_back({"--report", paths.report, kReportFiles, true});
  std::vector<io::NamedPath> inputs = {{"--input", paths.input},
                                       {"--config", cli::config_path(app)},
                                       {"--plan", paths.plan},
                                       {"--frontier", paths.frontier}};
  for (const auto& w : paths.weights) inputs.push_back({"--weights", w});
  for (const auto& d : paths.data) inputs.push_back({"--data", d});
  for (const auto& p : paths.pairs) inputs.push_back({"--pairs", p});
  io::require_outputs({{"--output", paths.output},
                       {"--frontier_json", paths.frontier_json},
                       {"--frontier_svg", paths.frontier_svg}},
                      directories, inputs);
  if (paths.report.empty()) return nullptr;
  return std::make_unique<io::AtomicDirectory>(paths.report, kReportFiles, "--report");
}

/// Input mode with a plan: its method, and its network (a path relative to the plan) read in the precision
/// it was trained in.
int plan_mode(const Paths& paths) {
  const io::ScenePlan scene_plan = io::read_plan(paths.plan);
  const std::filesystem::path network_path = io::plan_network_path(scene_plan, paths.plan);
  std::optional<LoadedNetwork> network;
  if (!network_path.empty()) {
    network = load_network(network_path.string());
    CONTACTNN_REQUIRE_AS(FormatError, network->model->surface() == scene_plan.surface,
                         "'" << network_path.string() << "' is a " << to_string(network->model->surface())
                             << " network, the plan '" << paths.plan << "' is for "
                             << to_string(scene_plan.surface) << " surfaces");
  }
  return input_mode(scene_plan.surface, search::Method::parse(scene_plan.method),
                    network ? network->model.get() : nullptr, paths);
}

/// The networks, each in the precision it was trained in; names (file stems) must differ, surfaces agree.
std::vector<LoadedNetwork> load_networks(const Paths& paths) {
  std::vector<LoadedNetwork> networks;
  for (const std::string& w : paths.weights) {
    networks.push_back(load_network(w));
    for (std::size_t k = 0; k + 1 < networks.size(); ++k) {
      CONTACTNN_REQUIRE_AS(InvalidArgument, networks[k].name != networks.back().name,
                           "two networks named '" << networks.back().name << "' (" << networks[k].path << ", "
                                                  << w << "): their methods would share names");
      CONTACTNN_REQUIRE_AS(FormatError, networks[k].model->surface() == networks.back().model->surface(),
                           "'" << w << "' is a " << to_string(networks.back().model->surface())
                               << " network, '" << networks[k].path << "' a "
                               << to_string(networks[k].model->surface()) << " one");
    }
  }
  return networks;
}

/// The sets are named by their file stems in every table: InvalidArgument when two share one.
void check_set_names(const Paths& paths) {
  std::vector<std::string> sets = paths.data;
  sets.insert(sets.end(), paths.pairs.begin(), paths.pairs.end());
  for (std::size_t i = 0; i < sets.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      CONTACTNN_REQUIRE_AS(
          InvalidArgument, std::filesystem::path(sets[k]).stem() != std::filesystem::path(sets[i]).stem(),
          "two sets named '" << std::filesystem::path(sets[i]).stem().string() << "' (" << sets[k] << ", "
                             << sets[i] << "): their rows in the report would share a name");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace contactnn;
  CLI::App app{
      "evaluate-net: apply trained networks; measure every local-search method's accuracy and speed"};
  cli::add_exit_code_footer(app);
  cli::add_config_option(app, "evaluate-net");

  // 1. Options: files and modes, the comparison's settings, frontier mode's files.
  eval::ComparisonOptions options;
  Paths paths;
  int threads = 0;
  add_file_options(app, paths);
  add_comparison_options(app, options, threads, paths.quiet);
  add_frontier_options(app, paths);

  return cli::run(app, argc, argv, [&]() -> int {
    // 2. Mode, threads and outputs, checked before any work.
    check_mode(paths);
    if (threads > 0) omp_set_num_threads(threads);
    paths.command_line = cli::join_command_line(argc, argv);
    const std::string effective = cli::effective_config(app, "evaluate-net");
    const std::unique_ptr<io::AtomicDirectory> report_directory = check_outputs(app, paths);

    // 3. Frontier mode: a finished report ranked and plotted.
    if (!paths.frontier.empty()) return frontier_mode(paths);

    // 4. A plan: input mode with its method (and network).
    if (!paths.plan.empty()) return plan_mode(paths);

    // 5. The networks; input mode with the one given.
    const std::vector<LoadedNetwork> networks = load_networks(paths);
    if (!paths.input.empty()) {
      search::Method method = search::Method::parse("network");
      method.newton_steps = paths.newton_steps;
      return input_mode(networks.front().model->surface(), method, networks.front().model.get(), paths);
    }

    // 6. Report mode: every method on every set, compared.
    check_set_names(paths);
    return report_mode(networks, paths, options, effective, *report_directory);
  });
}
