// train-net: trains a sigmoid multi-layer network to map normalised configurations to local coordinates.
//
// Description:
//   Reads a dataset of gen-configs, draws the training and validation patterns at random from its rows with
//   status ok (the paper: "1000 patterns are randomly selected for training"), trains a fully connected
//   sigmoid network (Eqs 12-14) by back-propagation with momentum, online (the paper's ordinary BP) or in
//   (mini-)batches, and writes the frozen network: weights, scaling, training domain, provenance.
//   Checkpoints are written every N epochs and --resume continues one bit-identically.
//
// Sample runs:
//   train-net --config configs/bilinear-paper.toml --data data/bilinear.h5 \
//             --output data/weights/bilinear-8.h5
//   train-net --config configs/bilinear-paper.toml --data data/bilinear.h5 --output /tmp/b.h5 --hidden 32,16
//   train-net --config configs/bilinear-paper.toml --data data/bilinear.h5 --output /tmp/b.h5 \
//             --checkpoint-every 500 --resume --export-header /tmp/bilinear_8.h
//
// Writes:
//   OUTPUT                   the network file (docs/files.md, "Network file"), atomically
//   OUTPUT.config.toml       the effective [train-net] configuration
//   OUTPUT.checkpoint.h5     with --checkpoint-every N: network plus trainer state, every N epochs
//   FILE.h                   with --export-header: a self-contained C99 header of the network
//   a progress line on stderr (at most 4 per second) and a summary on stdout.
//   The network, its config and the header are committed together at the end (one run's files, never a
//   mix); an output that is an input, a directory that cannot be written or a --export-header that is a
//   directory is refused before the first epoch. SIGINT/SIGTERM leave the last checkpoint for --resume.
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/csv.hpp"
#include "io/dataset_file.hpp"
#include "io/file_identity.hpp"
#include "io/network_file.hpp"
#include "io/output_checks.hpp"
#include "mlp/pattern_selection.hpp"
#include "mlp/random.hpp"
#include "mlp/trainer.hpp"
#include "search/export_c_header.hpp"

namespace {

using namespace contactnn;
using Clock = std::chrono::steady_clock;
using mlp::MatrixRM;

/// What the app decides beyond mlp::TrainOptions (every default here is documented in --help and
/// docs/tools.md).
struct NetSettings {
  std::string hidden = "8";              ///< hidden layer sizes, comma-separated
  double u0 = 2.0;                       ///< U0 of Eq 12
  std::string precision = "float";       ///< float or double
  std::size_t train_count = 1000;        ///< training patterns drawn from the ok rows
  double validation_fraction = 0.2;      ///< validation patterns = this * train_count, disjoint from training
  double target_low = 0.1;               ///< sigmoid value of the domain's lower end
  double target_high = 0.9;              ///< sigmoid value of the domain's upper end
  double input_quantile = 0.0;           ///< inputs' q .. 1-q order statistics map to [-1, 1] (0: min .. max)
  std::string input_features = "paper";  ///< the input map: paper (SPEC 4 as is) or affine
};

std::vector<int> parse_hidden(const std::string& text) {
  const std::vector<int> sizes =
      cli::integer_list(text, 1, 4096, "--hidden: expected comma-separated layer sizes in 1..4096");
  CONTACTNN_REQUIRE_AS(InvalidArgument, !sizes.empty(), "--hidden: at least one hidden layer size is needed");
  return sizes;
}

std::string c_prefix(const std::filesystem::path& header) {
  std::string p = header.stem().string();
  for (char& c : p) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  if (p.empty() || std::isdigit(static_cast<unsigned char>(p[0]))) p = "net_" + p;
  return p;
}

std::string format_duration(double seconds) {
  char buf[32];
  const long s = std::lround(std::max(0.0, seconds));
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

/// The outputs of a run, checked before any work: none is an input, each can be written (its directory
/// exists and takes a new file, it is not a directory), and the checkpoint has a regular file to sit beside.
void check_outputs(const CLI::App& app, const std::string& data_path, const std::filesystem::path& output,
                   const std::filesystem::path& checkpoint_path, bool checkpoints,
                   const std::string& header_path) {
  const bool in_place = io::written_in_place(output);
  CONTACTNN_REQUIRE_AS(InvalidArgument, !(checkpoints && in_place),
                       "--checkpoint-every and --resume need --output to name a file: '"
                           << output.string()
                           << "' is not a regular file (the checkpoint is OUTPUT.checkpoint.h5)");
  io::require_outputs(
      {{"--output", output},
       {"the checkpoint", checkpoints ? checkpoint_path : std::filesystem::path()},
       {"the effective config", in_place ? std::filesystem::path() : cli::effective_config_path(output)},
       {"--export-header", header_path}},
      {}, {{"--data", data_path}, {"--config", cli::config_path(app)}});
}

/// The rows a run trains on: the dataset, its checksum, its rows with status ok, their network inputs (the
/// features through the chosen input map, core/input_features.hpp) and the training and validation draw.
struct TrainingData {
  dataset::LabelledSet set;
  std::string checksum;
  std::vector<std::uint32_t> ok_rows;
  mlp::PatternSelection selection;
  MatrixRM<double> inputs;
  int n_features = 0;
};

TrainingData read_training_data(const NetSettings& net_settings, const mlp::TrainOptions& options,
                                const std::string& data_path) {
  TrainingData data;
  data.set = io::read_dataset(data_path);
  data.checksum = io::file_checksum(data_path);
  const dataset::LabelledSet& set = data.set;
  for (Eigen::Index r = 0; r < set.size(); ++r) {
    if (set.status[static_cast<std::size_t>(r)] == Status::kOk)
      data.ok_rows.push_back(static_cast<std::uint32_t>(r));
  }
  const auto validation_count = static_cast<std::size_t>(
      std::llround(net_settings.validation_fraction * static_cast<double>(net_settings.train_count)));
  CONTACTNN_REQUIRE_AS(InvalidArgument, net_settings.train_count + validation_count <= data.ok_rows.size(),
                       "--train_count " << net_settings.train_count << " and --validation_fraction "
                                        << net_settings.validation_fraction << " need "
                                        << net_settings.train_count + validation_count
                                        << " rows with status ok; '" << data_path << "' has "
                                        << data.ok_rows.size());
  data.selection = mlp::select_patterns(data.ok_rows, net_settings.train_count, validation_count,
                                        mlp::Rng::derive_seed(options.seed, 1));
  if (validation_count == 0 && options.patience > 0) {
    std::fprintf(
        stderr,
        "warning: no validation patterns (--validation_fraction %g x --train_count %zu rounds to 0): "
        "--patience has nothing to act on\n",
        net_settings.validation_fraction, net_settings.train_count);
  }
  data.n_features = feature_count(set.surface);
  const InputFeatures input_map = input_features_from_string(net_settings.input_features);
  data.inputs.resize(set.size(), data.n_features);
  for (Eigen::Index r = 0; r < set.size(); ++r) {
    map_input_features(input_map, set.surface, set.features.row(r).data(), data.inputs.row(r).data());
  }
  return data;
}

/// The network's scaling: from the training inputs, the targets' sigmoid range, the input map.
mlp::Scaling training_scaling(const NetSettings& net_settings, const TrainingData& data) {
  MatrixRM<double> train_raw(static_cast<Eigen::Index>(data.selection.training.size()), data.n_features);
  for (Eigen::Index r = 0; r < train_raw.rows(); ++r) {
    train_raw.row(r) = data.inputs.row(data.selection.training[static_cast<std::size_t>(r)]);
  }
  const ParamDomain domain_range = param_domain(data.set.surface);
  mlp::Scaling scaling =
      mlp::Scaling::from_inputs(train_raw, 2, domain_range.lo, domain_range.hi, net_settings.input_quantile);
  scaling.input_features = input_features_from_string(net_settings.input_features);
  scaling.target_low = net_settings.target_low;
  scaling.target_high = net_settings.target_high;
  scaling.validate(data.n_features, 2);
  return scaling;
}

/// Rows' scaled inputs x and targets t, in the network's precision.
template <class Real>
void scaled_patterns(const TrainingData& data, const mlp::Scaling& scaling,
                     const std::vector<std::uint32_t>& rows, MatrixRM<Real>& x, MatrixRM<Real>& t) {
  x.resize(static_cast<Eigen::Index>(rows.size()), data.n_features);
  t.resize(static_cast<Eigen::Index>(rows.size()), 2);
  for (Eigen::Index r = 0; r < x.rows(); ++r) {
    const auto row = rows[static_cast<std::size_t>(r)];
    for (int i = 0; i < data.n_features; ++i)
      x(r, i) = static_cast<Real>(scaling.scale_input(i, data.inputs(row, i)));
    for (int k = 0; k < 2; ++k) t(r, k) = static_cast<Real>(scaling.scale_target(k, data.set.labels(row, k)));
  }
}

/// --resume: the checkpoint must be this run's (architecture, U0, seed, dataset, every config key but
/// epochs); its parameters and trainer state are restored.
template <class Real>
void resume_from_checkpoint(const std::filesystem::path& checkpoint_path, const std::string& checksum,
                            const std::string& config_toml, const mlp::TrainOptions& options,
                            mlp::Network<Real>& network, mlp::Trainer<Real>& trainer, bool quiet) {
  const io::TrainedNetwork<Real> saved = io::read_network<Real>(checkpoint_path);
  CONTACTNN_REQUIRE_AS(
      FormatError, saved.network.layer_sizes() == network.layer_sizes() && saved.network.u0() == network.u0(),
      "checkpoint '" << checkpoint_path.string()
                     << "' holds another architecture or U0 than this run asks for");
  CONTACTNN_REQUIRE_AS(
      FormatError, saved.provenance.seed == options.seed && saved.provenance.dataset_checksum == checksum,
      "checkpoint '" << checkpoint_path.string() << "' was written for seed " << saved.provenance.seed
                     << " and dataset " << saved.provenance.dataset_checksum << ", this run has seed "
                     << options.seed << " and dataset " << checksum);
  // Everything else that shapes the run (scaling, pattern counts, learning rate, mode...) must match too;
  // only the number of epochs may grow. Compared as values, so a checkpoint whose config an earlier
  // version spelled differently (xy_limit=2.0 for 2) still resumes.
  const std::string differences =
      cli::config_differences(saved.provenance.config_toml, config_toml, {"epochs"});
  CONTACTNN_REQUIRE_AS(FormatError, differences.empty(),
                       "checkpoint '"
                           << checkpoint_path.string()
                           << "' was written with another configuration; only epochs may change on "
                              "--resume.\n(checkpoint vs this run)\n"
                           << differences.substr(0, differences.size() - 1));
  network.parameters() = saved.network.parameters();
  trainer.restore(io::read_training_state<Real>(checkpoint_path, network));
  if (!quiet)
    std::fprintf(stderr, "resuming from %s at epoch %d\n", checkpoint_path.string().c_str(),
                 trainer.state().epoch);
}

/// The epochs: a progress line on stderr (at most 4 a second), a checkpoint every checkpoint_every epochs.
/// Returns the seconds they took.
template <class Real>
double run_epochs(mlp::Trainer<Real>& trainer, const mlp::Network<Real>& network,
                  const mlp::TrainOptions& options, const geometry::TrainingDomain& domain,
                  io::NetworkProvenance& provenance, const std::filesystem::path& checkpoint_path,
                  int checkpoint_every, Eigen::Index train_rows, bool has_validation, bool quiet) {
  const auto start = Clock::now();
  auto last_print = start - std::chrono::seconds(1);
  const int first_epoch = trainer.state().epoch;
  auto print_progress = [&](const mlp::EpochReport& r, bool force) {
    const auto now = Clock::now();
    if (quiet || (!force && now - last_print < std::chrono::milliseconds(250))) return;
    last_print = now;
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const double epochs_done = r.epoch - first_epoch;
    const double rate = elapsed > 0 ? epochs_done / elapsed : 0.0;
    const double eta = rate > 0 ? (options.epochs - r.epoch) / rate : 0.0;
    char validation[96] = "no validation set";  // not 'val nan (best inf)'
    if (has_validation) {
      std::snprintf(validation, sizeof validation, "val %.4e (best %.4e @%d)", r.validation_loss,
                    trainer.state().best_validation_loss, trainer.state().best_epoch);
    }
    std::fprintf(stderr, "\repoch %d/%d  train %.4e  %s  %.3g patterns/s  ETA %s   ", r.epoch, options.epochs,
                 r.training_loss, validation, rate * static_cast<double>(train_rows),
                 format_duration(eta).c_str());
    std::fflush(stderr);
  };
  mlp::EpochReport last{};
  trainer.train([&](const mlp::EpochReport& r) {
    last = r;
    print_progress(r, false);
    if (checkpoint_every > 0 && r.epoch % checkpoint_every == 0) {
      provenance.epochs_run = r.epoch;
      provenance.training_loss = r.training_loss;
      provenance.validation_loss = r.validation_loss;
      io::write_network(checkpoint_path, network, domain, provenance, &trainer.state());
    }
    return true;
  });
  if (last.epoch > 0) print_progress(last, true);
  if (!quiet) std::fprintf(stderr, "\n");
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The frozen network, its config and (optionally) its C header, committed together: the three files always
/// come from one run.
template <class Real>
void write_outputs(const CLI::App& app, const mlp::Network<Real>& network,
                   const geometry::TrainingDomain& domain, const io::NetworkProvenance& provenance,
                   const std::filesystem::path& output, const std::string& header_path,
                   const std::string& data_path, const std::string& checksum) {
  const auto network_file = io::write_network_uncommitted(output, network, domain, provenance);
  const auto config_file = cli::write_effective_config(app, "train-net", output);
  std::unique_ptr<io::AtomicOutput> header_file;
  if (!header_path.empty()) {
    search::CHeaderOptions h;
    h.prefix = c_prefix(header_path);
    h.description = "network " + output.filename().string() + ", dataset " + data_path + " (" + checksum +
                    "), seed " + std::to_string(provenance.seed);
    header_file = io::write_text_uncommitted(
        header_path, search::export_c_header(search::NetworkModel(network, domain), h));
  }
  io::commit_together({network_file.get(), config_file.get(), header_file.get()});
}

/// The summary on stdout: losses and the mean |error| over every ok row of the dataset (label units).
template <class Real>
void print_summary(const mlp::Network<Real>& network, const TrainingData& data,
                   const mlp::TrainingState<Real>& state, const io::NetworkProvenance& provenance,
                   const std::filesystem::path& output, double seconds) {
  const MatrixRM<double> predicted = mlp::predict(network, data.set.features);
  double abs_error[2] = {0, 0};
  for (std::uint32_t r : data.ok_rows) {
    for (int k = 0; k < 2; ++k) abs_error[k] += std::abs(predicted(r, k) - data.set.labels(r, k));
  }
  const auto names = coordinate_names(data.set.surface);
  const std::vector<int>& sizes = network.layer_sizes();
  const auto& selection = data.selection;
  const std::size_t ok_count = data.ok_rows.size();
  std::printf("train-net summary\n");
  std::printf("  network          ");
  for (std::size_t l = 0; l < sizes.size(); ++l) std::printf("%s%d", l ? "-" : "", sizes[l]);
  std::printf(" (%s, U0 = %g), %s mode\n", std::is_same_v<Real, float> ? "float" : "double", network.u0(),
              provenance.training_mode.c_str());
  std::printf("  patterns         %zu training, %zu validation (of %zu ok rows)\n", selection.training.size(),
              selection.validation.size(), ok_count);
  std::printf("  epochs           %d (kept parameters of epoch %lld), %.2f s\n", state.epoch,
              static_cast<long long>(provenance.best_epoch ? provenance.best_epoch : state.epoch), seconds);
  // The training error is the last epoch's; the validation error the kept parameters' (the best epoch's with
  // restore_best), so each is labelled.
  if (selection.validation.empty()) {
    std::printf("  mean E_p         training %.4e (last epoch), no validation set\n",
                provenance.training_loss);
  } else {
    std::printf("  mean E_p         training %.4e (last epoch), validation %.4e (epoch %lld)\n",
                provenance.training_loss, provenance.validation_loss,
                static_cast<long long>(provenance.best_epoch ? provenance.best_epoch : state.epoch));
  }
  std::printf("  all ok rows      mean |%s error| %.5f, mean |%s error| %.5f  (%zu rows)\n",
              std::string(names[0]).c_str(), abs_error[0] / static_cast<double>(ok_count),
              std::string(names[1]).c_str(), abs_error[1] / static_cast<double>(ok_count), ok_count);
  std::printf("  written          %s\n", output.string().c_str());
}

template <class Real>
int train(const CLI::App& app, const NetSettings& net_settings, mlp::TrainOptions options,
          const std::string& data_path, const std::filesystem::path& output, int checkpoint_every,
          bool resume, const std::string& header_path, bool quiet, const std::string& config_toml) {
  // 3. Outputs checked now, not after the training; then the data: the dataset, its rows with status ok, the
  //    training and validation draw.
  std::filesystem::path checkpoint_path = output;
  checkpoint_path += ".checkpoint.h5";
  check_outputs(app, data_path, output, checkpoint_path, checkpoint_every > 0 || resume, header_path);
  const TrainingData data = read_training_data(net_settings, options, data_path);

  // 4. Network: architecture, scaling from the training inputs, weights from the seed.
  std::vector<int> sizes{data.n_features};
  for (int n : parse_hidden(net_settings.hidden)) sizes.push_back(n);
  sizes.push_back(2);
  mlp::Network<Real> network(sizes, net_settings.u0, training_scaling(net_settings, data));
  network.initialize(mlp::Rng::derive_seed(options.seed, 0));
  MatrixRM<Real> train_x, train_t, val_x, val_t;
  scaled_patterns(data, network.scaling(), data.selection.training, train_x, train_t);
  scaled_patterns(data, network.scaling(), data.selection.validation, val_x, val_t);
  const dataset::LabelledSet& set = data.set;
  const geometry::TrainingDomain domain = geometry::TrainingDomain::from_features(
      set.surface, set.features.data(), static_cast<long>(set.size()), set.status, set.filters);

  io::NetworkProvenance provenance;
  provenance.config_toml = config_toml;
  provenance.seed = options.seed;
  provenance.dataset_path = data_path;
  provenance.dataset_checksum = data.checksum;
  provenance.training_mode = std::string(mlp::to_string(options.mode));
  provenance.training_patterns = static_cast<std::int64_t>(data.selection.training.size());
  provenance.validation_patterns = static_cast<std::int64_t>(data.selection.validation.size());

  // 5. Trainer, resumed from the checkpoint when asked.
  mlp::Trainer<Real> trainer(network, options, train_x, train_t, val_x, val_t);
  if (resume)
    resume_from_checkpoint(checkpoint_path, data.checksum, config_toml, options, network, trainer, quiet);

  // 6. Epochs: progress line, checkpoints.
  const double seconds = run_epochs(trainer, network, options, domain, provenance, checkpoint_path,
                                    checkpoint_every, train_x.rows(), val_x.rows() > 0, quiet);

  // 7. The frozen network, its config and (optionally) its C header, committed together.
  const auto& state = trainer.state();
  provenance.epochs_run = state.epoch;
  provenance.best_epoch = options.restore_best && val_x.rows() > 0 ? state.best_epoch : 0;
  provenance.training_loss = state.training_loss;
  provenance.validation_loss =
      val_x.rows() > 0 && options.restore_best ? state.best_validation_loss : state.validation_loss;
  write_outputs(app, network, domain, provenance, output, header_path, data_path, data.checksum);

  // 8. Summary: losses and the mean |error| over every ok row of the dataset (label units).
  print_summary(network, data, state, provenance, output, seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace contactnn;
  CLI::App app{"train-net: train a sigmoid network (paper Eqs 12-14) by back-propagation with momentum"};
  cli::add_exit_code_footer(app);
  cli::add_config_option(app, "train-net");

  // 1. Options. Defaults live in mlp::TrainOptions and NetSettings; flags only map onto them.
  mlp::TrainOptions options;
  NetSettings net;
  std::string data, output, header, mode = std::string(mlp::to_string(options.mode));
  int threads = 0, checkpoint_every = 0;
  bool resume = false, quiet = false;
  app.add_option("--data", data, "dataset .h5 written by gen-configs")->required()->check(CLI::ExistingFile);
  app.add_option("--output", output, "network file (.h5) to write")->required();
  app.add_option("--hidden", net.hidden, "hidden layer sizes, comma-separated (8 or 32,16)");
  app.add_option("--u0", net.u0, "U0 of the sigmoid O = 1/(1+exp(-2U/U0))")->check(cli::kPositive);
  app.add_option("--precision", net.precision, "float or double arithmetic")
      ->check(CLI::IsMember({"float", "double"}));
  app.add_option("--mode", mode, "online (one update per pattern) or batch")
      ->check(CLI::IsMember({"online", "batch"}));
  app.add_option("--batch_size", options.batch_size, "batch mode: patterns per update, 0 = all (full batch)")
      ->transform(cli::integer_in(0, std::int64_t{1} << 32));
  app.add_option("--learning_rate", options.learning_rate, "eta of dw = momentum dw - eta dE/dw")
      ->check(cli::kPositive);
  app.add_option("--learning_rate_final", options.learning_rate_final,
                 "eta of the last epoch: eta decays geometrically from --learning_rate to this (0: constant)")
      ->check(cli::kNonNegative);
  app.add_option("--momentum", options.momentum, "momentum (alpha) in [0, 1)")
      ->check(CLI::Range(0.0, 0.999999));
  app.add_option("--epochs", options.epochs, "maximum epochs (the paper's training iterations)")
      ->transform(cli::integer_in(1, 100000000));
  app.add_option("--patience", options.patience,
                 "stop after this many epochs without a better validation error; 0 = never")
      ->transform(cli::integer_in(0, 100000000));
  app.add_option("--restore_best", options.restore_best, "keep the parameters of the best validation error");
  app.add_option("--train_count", net.train_count, "training patterns drawn from the rows with status ok")
      ->transform(cli::integer_in(1, (std::int64_t{1} << 32) - 1));
  app.add_option("--validation_fraction", net.validation_fraction, "validation patterns per training pattern")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option(
         "--input_features", net.input_features,
         "what the network sees: paper (the SPEC 4 features) or affine (the slave and C in the affine frame "
         "of AB and AD, the metric as separate inputs: thin segments stay well conditioned)")
      ->check(CLI::IsMember({"paper", "affine"}));
  app.add_option(
         "--input_quantile", net.input_quantile,
         "each input's q and 1-q order statistics over the training patterns map to -1 and 1 (0: min, max)")
      ->check(CLI::Range(0.0, 0.49));
  app.add_option("--target_low", net.target_low, "sigmoid value the domain's lower end maps to")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--target_high", net.target_high, "sigmoid value the domain's upper end maps to")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--seed", options.seed, "seed of the pattern draw, the initial weights and the shuffles")
      ->transform(cli::integer_in(0, cli::kMaxSeed));
  app.add_option("--threads", threads, "OpenMP threads (0: OpenMP's default)")
      ->transform(cli::integer_in(0, cli::kMaxThreads));
  app.add_option("--checkpoint-every", checkpoint_every,
                 "write OUTPUT.checkpoint.h5 every N epochs (0: never)")
      ->transform(cli::integer_in(0, 100000000));
  app.add_flag("--resume", resume, "continue from OUTPUT.checkpoint.h5");
  app.add_option("--export-header", header, "also write the network as a C99 header FILE.h");
  app.add_flag("--quiet", quiet, "no progress line");

  return cli::run(app, argc, argv, [&]() -> int {
    // 2. Threads and mode.
    if (threads > 0) omp_set_num_threads(threads);
    options.threads = threads;
    options.mode = mlp::training_mode_from_string(mode);
    CONTACTNN_REQUIRE_AS(InvalidArgument,
                         0.0 < net.target_low && net.target_low < net.target_high && net.target_high < 1.0,
                         "--target_low " << net.target_low << " and --target_high " << net.target_high
                                         << ": expected 0 < target_low < target_high < 1");
    (void)parse_hidden(net.hidden);  // a bad --hidden is reported before the dataset is read
    // Provenance without the keys that do not change the network (paths, threads, checkpointing), so a
    // resumed run records the same config as an uninterrupted one.
    const std::string config = cli::effective_config(
        app, "train-net",
        {"data", "output", "threads", "quiet", "resume", "checkpoint-every", "export-header"});
    return net.precision == "double" ? train<double>(app, net, options, data, output, checkpoint_every,
                                                     resume, header, quiet, config)
                                     : train<float>(app, net, options, data, output, checkpoint_every, resume,
                                                    header, quiet, config);
  });
}
