// evaluate-net: apply a trained network, and measure its accuracy and speed against Newton's method.
//
// Description:
//   Report mode applies the network of a train-net file to every configuration of a gen-configs dataset and
//   compares it, and plain Newton with 1..10 fixed iterations and Newton to convergence, with the dataset's
//   Newton labels; it times every method on one thread from the same raw world coordinates (paper Sections
//   5.3 and 6.3.3: Table 1, Figs 4, 10 and 11). Input mode applies the network to a user's configurations in
//   world coordinates (SPEC section 6).
//
// Sample runs:
//   evaluate-net --config configs/bilinear-paper.toml --weights data/weights/bilinear-8.h5
//                --data data/bilinear.h5 --report reports/bilinear     (one line)
//   evaluate-net --weights data/weights/bilinear-8.h5 --input data/examples/raw-bilinear.csv --output /tmp/pred.csv
//
// Writes:
//   report mode: DIR/errors.csv, DIR/speed.csv, DIR/hist_<xi|eta|u|v>.csv and .svg, DIR/report.md,
//                DIR/evaluate-net.config.toml (effective config); a summary on stdout, progress on stderr.
//                DIR is written under a temporary name and put in place whole; an existing DIR is replaced
//                only if it holds nothing but these files.
//   input mode:  OUTPUT (.csv): the input columns, then xi,eta (u,v for Gregory),status; one row per input row,
//                in input order. status: ok, out_of_domain (outside the network's training domain; the
//                prediction is still written), invalid (non-finite input; xi, eta empty) or degenerate (no
//                normalised frame exists; xi, eta empty). Rows are streamed in chunks (bounded memory).
#include <omp.h>

#include <cstdio>
#include <memory>
#include <span>
#include <thread>

#include "build_info.hpp"
#include "cli_support.hpp"
#include "core/error.hpp"
#include "eval/network_predictor.hpp"
#include "eval/report.hpp"
#include "eval/study.hpp"
#include "io/csv.hpp"
#include "io/atomic_output.hpp"
#include "io/dataset_file.hpp"
#include "io/file_identity.hpp"
#include "io/network_file.hpp"
#include "io/raw_configurations.hpp"

namespace {

using namespace contactnn;

/// What a report directory may hold: the files report mode writes (README "evaluate-net"). Only a directory
/// holding nothing else is replaced.
const std::initializer_list<std::string> kReportFiles = {
    "errors.csv",  "speed.csv",   "hist_xi.csv", "hist_eta.csv", "hist_u.csv", "hist_v.csv",
    "hist_xi.svg", "hist_eta.svg", "hist_u.svg", "hist_v.svg",  "report.md",  "evaluate-net.config.toml"};

/// The files and switches of one run (every numeric setting lives in eval::StudyOptions).
struct Paths {
  std::string weights, data, report, input, output;
  bool quiet = false;
  std::string command_line;
};

std::string join_command_line(int argc, char** argv) {
  std::string out;
  for (int i = 0; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.find_first_of(" \t\"'$\\") != std::string::npos) {
      std::string quoted = "'";
      for (const char c : arg) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      arg = quoted + "'";
    }
    out += (i > 0 ? " " : "") + arg;
  }
  return out;
}

template <class Real>
std::string network_summary(const mlp::Network<Real>& network) {
  std::string s;
  for (std::size_t i = 0; i < network.layer_sizes().size(); ++i) {
    s += (i > 0 ? "-" : "") + std::to_string(network.layer_sizes()[i]);
  }
  char u0[32];
  std::snprintf(u0, sizeof u0, "%g", network.u0());
  return s + ", " + (std::is_same_v<Real, float> ? "float" : "double") + ", U0 = " + u0;
}

/// Input mode's computation for one chunk of rows: the network's estimate of each configuration (domain
/// check included). The seam where the batched search library plugs in: a span of configurations in, one
/// estimate per configuration out.
template <class Real>
void predict_chunk(std::span<const geometry::Configuration> configs, SurfaceKind kind,
                   const eval::NetworkPredictor<Real>& predictor, const geometry::TrainingDomain& domain,
                   std::span<eval::Estimate> estimates) {
  const auto n = static_cast<std::int64_t>(configs.size());
#pragma omp parallel
  {
    eval::NetworkPredictor<Real> local = predictor;
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      const auto r = static_cast<std::size_t>(i);
      estimates[r] = eval::network_estimate(configs[r], kind, local, &domain);
    }
  }
}

/// Input mode: RAW.csv streamed through predict_chunk in chunks of io::kRawChunkRows rows (bounded memory
/// for any number of rows); the output appears only when every row is done.
template <class Real>
int input_mode(const io::TrainedNetwork<Real>& trained, const Paths& paths) {
  const SurfaceKind kind = trained.domain.surface;
  const eval::NetworkPredictor<Real> predictor(trained.network);
  const auto names = coordinate_names(kind);
  const std::vector<std::string> header = {std::string(names[0]), std::string(names[1]), "status"};
  std::array<std::int64_t, kStatusCount> counts{};
  std::vector<eval::Estimate> estimates;
  std::vector<std::string> replaced;
  const std::size_t n = io::map_raw_configurations(
      paths.input, paths.output, kind, header,
      [&](const io::RawChunk& chunk, std::vector<std::vector<std::string>>& rows) {
        const std::span<const std::size_t> lines = chunk.line_numbers;
        estimates.resize(chunk.size());
        predict_chunk(chunk.configs, kind, predictor, trained.domain, std::span<eval::Estimate>(estimates));
        for (std::size_t r = 0; r < estimates.size(); ++r) {
          if (chunk.no_segment[r] != 0) estimates[r].status = Status::kNoSegment;  // SPEC 7: nothing to predict
          const eval::Estimate& e = estimates[r];
          const bool has_value = e.status == Status::kOk || e.status == Status::kOutOfDomain;
          CONTACTNN_REQUIRE_AS(NumericalError, !has_value || (std::isfinite(e.param[0]) && std::isfinite(e.param[1])),
                               "'" << paths.weights << "' predicted a non-finite value for '" << paths.input
                                   << "' line " << lines[r]);
          rows[r] = {has_value ? io::format_double(e.param[0]) : "", has_value ? io::format_double(e.param[1]) : "",
                     std::string(to_string(e.status))};
          ++counts[static_cast<std::size_t>(e.status)];
        }
      },
      &replaced);
  for (const auto& name : replaced) {
    std::fprintf(stderr, "warning: input column '%s' is replaced by evaluate-net's own '%s' column\n", name.c_str(),
                 name.c_str());
  }
  std::printf("evaluate-net: %lld rows -> %s\n", static_cast<long long>(n), paths.output.c_str());
  for (int s = 0; s < kStatusCount; ++s) {
    if (counts[static_cast<std::size_t>(s)] == 0) continue;
    std::printf("  %-15s %lld\n", std::string(to_string(static_cast<Status>(s))).c_str(),
                static_cast<long long>(counts[static_cast<std::size_t>(s)]));
  }
  return 0;
}

template <class Real>
int report_mode(const io::TrainedNetwork<Real>& trained, const Paths& paths, const eval::StudyOptions& options,
                const std::string& effective_config, io::AtomicDirectory& report) {
  // 1. The dataset must be of the network's surface, and hold something to report on.
  const dataset::LabelledSet set = io::read_dataset(paths.data);
  CONTACTNN_REQUIRE_AS(FormatError, set.surface == trained.domain.surface,
                       "'" << paths.data << "' is a " << to_string(set.surface) << " dataset but '" << paths.weights
                           << "' is a " << to_string(trained.domain.surface) << " network");
  const auto ok_rows = std::count(set.status.begin(), set.status.end(), Status::kOk);
  CONTACTNN_REQUIRE_AS(FormatError, ok_rows > 0,
                       "'" << paths.data << "' holds " << set.size()
                           << " configurations and none with status ok: nothing to report (no error can be measured)");

  // 2. The study: accuracy in parallel, timing on this thread.
  const eval::NetworkPredictor<Real> predictor(trained.network);
  const auto log = [&](std::string_view line) {
    if (!paths.quiet) std::fprintf(stderr, "evaluate-net: %.*s\n", static_cast<int>(line.size()), line.data());
  };
  const eval::StudyResult result = eval::run_study(set, predictor, trained.domain, options, log);

  // 3. Provenance and the report files.
  eval::RunInfo info;
  info.command_line = paths.command_line;
  info.dataset_path = paths.data;
  info.network_path = paths.weights;
  info.network_summary = network_summary(trained.network);
  info.cpu_model = eval::cpu_model();
  info.hardware_threads = static_cast<int>(std::thread::hardware_concurrency());
  info.accuracy_threads = omp_get_max_threads();
  info.compiler = CONTACTNN_COMPILER;
  info.build_type = CONTACTNN_BUILD_TYPE;
  info.cxx_flags = CONTACTNN_CXX_FLAGS;
  info.cxx_flags.erase(0, info.cxx_flags.find_first_not_of(' '));
  info.effective_config = effective_config;
  // Written into a temporary directory and put in place whole: an interrupted or failed run leaves the
  // previous report as it was, never half of each.
  eval::write_report(report.write_path(), result, info, options);
  io::write_text_atomically(report.write_path() / "evaluate-net.config.toml",
                            "# effective configuration written by evaluate-net\n" + effective_config);
  report.commit();

  // 4. Summary.
  const auto names = coordinate_names(set.surface);
  const eval::MethodErrors& net = result.errors.front();
  std::printf("evaluate-net summary (%lld configurations)\n", static_cast<long long>(result.rows));
  std::printf("  network mean |error|   %s %.4g, %s %.4g (failures %lld, out of domain %lld)\n",
              std::string(names[0]).c_str(), net.stats[0].mean_abs, std::string(names[1]).c_str(),
              net.stats[1].mean_abs, static_cast<long long>(net.stats[0].failures),
              static_cast<long long>(result.network_out_of_domain));
  const eval::NetworkCostInIterations cost = eval::network_cost_in_iterations(result);
  if (cost.available) {
    std::printf("  network cost           %.2f Newton iterations (fitted line, medians; %.2f from minima)\n",
                cost.equivalent_iterations, cost.equivalent_iterations_min);
  }
  std::printf("  report                 %s/report.md\n", paths.report.c_str());
  return 0;
}

template <class Real>
int run_mode(const Paths& paths, const eval::StudyOptions& options, const std::string& effective_config,
             io::AtomicDirectory* report) {
  const io::TrainedNetwork<Real> trained = io::read_network<Real>(paths.weights);
  if (!paths.input.empty()) return input_mode(trained, paths);
  return report_mode(trained, paths, options, effective_config, *report);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace contactnn;
  CLI::App app{"evaluate-net: apply a trained network; measure its accuracy and speed against Newton's method"};
  cli::add_exit_code_footer(app);
  cli::add_config_option(app, "evaluate-net");

  // 1. Options. Every default lives in eval::StudyOptions; flags only map onto it.
  eval::StudyOptions options;
  Paths paths;
  int threads = 0;
  app.add_option("--weights", paths.weights, "network file of train-net (.h5)")->required()->check(CLI::ExistingFile);
  auto* data = app.add_option("--data", paths.data, "report mode: labelled dataset of gen-configs (.h5)")
                   ->check(CLI::ExistingFile);
  auto* report = app.add_option("--report", paths.report, "report mode: output directory");
  auto* input = app.add_option("--input", paths.input, "input mode: RAW.csv of world configurations (SPEC 6)")
                    ->check(CLI::ExistingFile);
  auto* output = app.add_option("--output", paths.output, "input mode: predictions .csv");
  data->needs(report);
  report->needs(data);
  input->needs(output);
  output->needs(input);
  input->excludes(data);
  data->excludes(input);
  app.add_option("--threads", threads, "OpenMP threads of the accuracy part (0: OpenMP's default)")
      ->transform(cli::integer_in(0, cli::kMaxThreads));
  app.add_flag("--quiet", paths.quiet, "no progress lines");
  app.add_option("--seed", options.seed, "seed of the placements and the timing sample")
      ->transform(cli::integer_in(0, cli::kMaxSeed));
  app.add_option("--random_placement", options.random_placement,
                 "accuracy on randomly placed world coordinates instead of the dataset's frame");
  app.add_option("--max_fixed_iterations", options.max_fixed_iterations, "Newton with k = 1..this fixed iterations")
      ->transform(cli::integer_in(1, 100));
  app.add_option("--failure_box_margin", options.failure_box_margin,
                 "an estimate more than this many domain widths outside the domain is a failure")
      ->check(cli::kPositive);
  app.add_option("--converged_max_iterations", options.newton.converged_max_iterations,
                 "Newton to convergence: iteration limit")
      ->transform(cli::integer_in(1, 10000));
  app.add_option("--converged_tol_param", options.newton.converged_tol_param,
                 "Newton to convergence: step tolerance (parameter units)")
      ->check(cli::kPositive);
  app.add_option("--hist_bins", options.hist_bins, "bins of the error histograms")->transform(cli::integer_in(1, 100000));
  app.add_option("--hist_range", options.hist_range,
                 "histogram range [-r, r]; 0: a nice number above the 99.9th percentile of |error|")
      ->check(cli::real_in(0.0, 1e6));
  app.add_option("--timing", options.timing, "measure the speed of every method");
  app.add_option("--timing_queries", options.timing_queries, "configurations per timed pass")
      ->transform(cli::integer_in(1, 100000000));
  app.add_option("--timing_repetitions", options.timing_options.repetitions, "timed passes per method")
      ->transform(cli::integer_in(1, 1000));
  app.add_option("--timing_warmup_passes", options.timing_options.warmup_passes, "untimed passes per method first")
      ->transform(cli::integer_in(0, 100));

  return cli::run(app, argc, argv, [&]() -> int {
    // 2. Mode and threads; no output may be an input, and a report directory is replaced only if it holds
    //    nothing but an earlier report (both checked before any work).
    CONTACTNN_REQUIRE_AS(InvalidArgument, !paths.input.empty() || !paths.data.empty(),
                         "give either --data DATASET.h5 --report DIR (report mode) or --input RAW.csv --output "
                         "PRED.csv (input mode)");
    if (threads > 0) omp_set_num_threads(threads);
    paths.command_line = join_command_line(argc, argv);
    const std::string effective = cli::effective_config(app, "evaluate-net");
    std::vector<io::NamedPath> outputs = {{"--output", paths.output}};
    if (!paths.report.empty()) {
      for (const std::string& name : kReportFiles) {
        outputs.push_back({"--report file '" + name + "'", std::filesystem::path(paths.report) / name});
      }
    }
    io::require_distinct(outputs, {{"--weights", paths.weights},
                                   {"--data", paths.data},
                                   {"--input", paths.input},
                                   {"--config", cli::config_path(app)}});
    std::unique_ptr<io::AtomicDirectory> report_directory;
    if (!paths.report.empty()) {
      report_directory = std::make_unique<io::AtomicDirectory>(paths.report, kReportFiles, "--report");
    }
    if (!paths.output.empty()) io::require_writable(paths.output);

    // 3. Run in the precision the network was trained in.
    const std::string real_type = io::read_network_real_type(paths.weights);
    return real_type == "float64" ? run_mode<double>(paths, options, effective, report_directory.get())
                                  : run_mode<float>(paths, options, effective, report_directory.get());
  });
}
