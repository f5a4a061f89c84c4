// gen-configs: node-segment configurations labelled by Newton closest-point projection.
//
// Description:
//   Enumeration mode enumerates the configurations of the paper's Section 5.1 (bilinear) on the grid and
//   with the filters of a config file, labels each by the reference Newton projection and writes an HDF5
//   dataset (schema: README "Dataset schema"). Label mode labels a user's own configurations given in
//   world coordinates (SPEC section 6).
//
// Sample runs:
//   gen-configs --config configs/bilinear-paper.toml --output data/bilinear.h5
//   gen-configs --config configs/tiny.toml --output /tmp/tiny.h5 --threads 1
//   gen-configs --surface bilinear --input data/examples/raw-bilinear.csv --output /tmp/labels.csv
//
// Writes:
//   enumeration: OUTPUT (.h5), OUTPUT.config.toml (effective config), a summary on stdout, progress on stderr.
//   label mode:  OUTPUT (.csv): the input columns, then xi,eta (u,v for Gregory),status,gap,iterations; one row
//                per input row, in input order. xi, eta and gap are empty unless status is ok or outside.
//                Rows are streamed in chunks (bounded memory for any number of rows).
//   The dataset and its config are committed together (one run's pair); outputs that are inputs are refused.
#include <omp.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <span>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "dataset/enumeration.hpp"
#include "dataset/labeller.hpp"
#include "io/csv.hpp"
#include "io/dataset_file.hpp"
#include "io/file_identity.hpp"
#include "io/raw_configurations.hpp"

namespace {

using namespace contactnn;

void print_summary(const dataset::EnumerationSummary& s, const std::string& output) {
  std::printf("gen-configs summary\n");
  std::printf("  grid candidates        %lld\n", static_cast<long long>(s.grid_points));
  std::printf("  after geometric filters %lld\n", static_cast<long long>(s.geometric_kept));
  std::printf("  written                %lld  -> %s\n", static_cast<long long>(s.kept), output.c_str());
  std::printf("  time                   %.2f s (%.0f configurations/s labelled)\n", s.seconds,
              s.seconds > 0 ? static_cast<double>(s.geometric_kept) / s.seconds : 0.0);
  std::printf("  status counts (all labelled candidates):\n");
  for (int i = 0; i < kStatusCount; ++i) {
    if (s.status_counts[static_cast<std::size_t>(i)] == 0) continue;
    std::printf("    %-15s %lld\n", std::string(to_string(static_cast<Status>(i))).c_str(),
                static_cast<long long>(s.status_counts[static_cast<std::size_t>(i)]));
  }
  std::printf("  Newton iterations of the written labels (histogram):\n");
  for (std::size_t k = 0; k < s.iteration_histogram.size(); ++k) {
    if (s.iteration_histogram[k] == 0) continue;
    std::printf("    %2zu%s %lld\n", k, k + 1 == s.iteration_histogram.size() ? "+" : " ",
                static_cast<long long>(s.iteration_histogram[k]));
  }
}

/// Label mode's computation for one chunk of rows: the reference projection of each configuration. The seam
/// where the batched search library plugs in: a span of configurations in, one label per configuration out.
void label_chunk(std::span<const geometry::Configuration> configs, SurfaceKind surface,
                 const projection::ProjectionOptions& options, std::span<dataset::Label> labels) {
  const auto n = static_cast<std::int64_t>(configs.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (std::int64_t i = 0; i < n; ++i) {
    labels[static_cast<std::size_t>(i)] = dataset::label_configuration(configs[static_cast<std::size_t>(i)], surface, options);
  }
}

/// A label as the output's fields xi,eta (u,v),status,gap,iterations: values only where converged.
std::vector<std::string> label_fields(const dataset::Label& l) {
  const bool has_value = l.status == Status::kOk || l.status == Status::kOutside;
  return {has_value ? io::format_double(l.param[0]) : "", has_value ? io::format_double(l.param[1]) : "",
          std::string(to_string(l.status)), has_value ? io::format_double(l.gap) : "", std::to_string(l.iterations)};
}

/// Label mode: RAW.csv streamed through label_chunk in chunks of io::kRawChunkRows rows, so memory stays
/// bounded for any number of rows; the output appears only when every row is labelled.
int label_mode(SurfaceKind surface, const std::string& input, const std::string& output,
               const projection::ProjectionOptions& options) {
  const auto names = coordinate_names(surface);
  const std::vector<std::string> header = {std::string(names[0]), std::string(names[1]), "status", "gap", "iterations"};
  std::vector<std::string> replaced;
  std::vector<dataset::Label> labels;
  io::map_raw_configurations(
      input, output, surface, header,
      [&](std::span<const geometry::Configuration> configs, std::span<const std::size_t>,
          std::vector<std::vector<std::string>>& rows) {
        labels.resize(configs.size());
        label_chunk(configs, surface, options, labels);
        for (std::size_t i = 0; i < labels.size(); ++i) rows[i] = label_fields(labels[i]);
      },
      &replaced);
  for (const auto& name : replaced) {
    std::fprintf(stderr, "warning: input column '%s' is replaced by gen-configs' own '%s' column\n", name.c_str(),
                 name.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace contactnn;
  CLI::App app{"gen-configs: enumerate node-segment configurations and label them by Newton projection"};
  cli::add_exit_code_footer(app);
  cli::add_config_option(app, "gen-configs");

  // 1. Options. Every default lives in the options structs of lib/; flags only map onto them.
  dataset::EnumerationOptions options;
  std::string surface_name = "bilinear";
  std::string input, output;
  int threads = 0;
  bool quiet = false;
  auto& f = options.filters;
  app.add_option("--surface", surface_name, "bilinear or gregory")->check(CLI::IsMember({"bilinear", "gregory"}));
  app.add_option("--input", input, "label mode: RAW.csv of world configurations (SPEC 6)")->check(CLI::ExistingFile);
  app.add_option("--output", output, "dataset .h5 (enumeration) or labels .csv (label mode)")->required();
  app.add_option("--threads", threads, "OpenMP threads (0: OpenMP's default)")->transform(cli::integer_in(0, cli::kMaxThreads));
  app.add_flag("--quiet", quiet, "no progress line");
  app.add_option("--seed", options.seed, "seed of the Gregory node-normal sampling")->transform(cli::integer_in(0, cli::kMaxSeed));
  app.add_option("--d_xy_points", options.d_xy_points, "grid points per axis, x and y of D")->transform(cli::integer_in(1, 400));
  app.add_option("--c_xy_points", options.c_xy_points, "grid points per axis, x and y of C")->transform(cli::integer_in(1, 400));
  app.add_option("--c_z_points", options.c_z_points, "grid points, z of C")->transform(cli::integer_in(1, 400));
  app.add_option("--s_xy_points", options.s_xy_points, "grid points per axis, x and y of S")->transform(cli::integer_in(1, 400));
  app.add_option("--s_z_points", options.s_z_points, "grid points, z of S")->transform(cli::integer_in(1, 400));
  app.add_option("--normal_sets", options.normal_sets, "Gregory: node-normal sets per configuration")
      ->transform(cli::integer_in(1, 1000));
  app.add_option("--require_projection_inside", options.require_projection_inside,
                 "keep only configurations whose projection lies inside the segment");
  app.add_option("--xy_limit", f.xy_limit, "|x|, |y| of C, D, S below this")->check(cli::kPositive);
  app.add_option("--z_limit", f.z_limit, "|z| of C, S below this")->check(cli::kPositive);
  app.add_option("--ad_not_longer_than_ab", f.ad_not_longer_than_ab, "|AD| <= |AB|");
  app.add_option("--nearest_node_a", f.nearest_node_a, "A is the master node nearest S");
  app.add_option("--segment_test_a", f.segment_test_a, "S passes the segment test (Eqs 3-6) at A");
  app.add_option("--convex", f.convex, "the segment is strictly convex");
  app.add_option("--min_angle_degrees", f.min_angle_degrees, "smallest interior angle")->check(CLI::Range(0.0, 180.0));
  app.add_option("--max_angle_degrees", f.max_angle_degrees, "largest interior angle")->check(CLI::Range(0.0, 180.0));
  app.add_option("--max_normal_tilt_tangent", f.max_normal_tilt_tangent, "Gregory: tangent of the largest normal tilt")
      ->check(cli::kPositive);
  app.add_option("--max_iterations", options.projection.max_iterations, "Newton iterations per start")
      ->transform(cli::integer_in(1, 10000));
  app.add_option("--tol_param", options.projection.tol_param, "Newton step tolerance (parameter units)")
      ->check(cli::kPositive);
  app.add_option("--starts_per_axis", options.projection.starts_per_axis, "Newton starts per parameter axis")
      ->transform(cli::integer_in(1, 10));
  app.add_option("--domain_margin", options.projection.domain_margin, "parameter slack counted as inside")
      ->check(cli::kNonNegative);

  return cli::run(app, argc, argv, [&]() -> int {
    // 2. Threads, surface, and what must hold before any work: settings that contradict each other, an
    //    output that is an input.
    if (threads > 0) omp_set_num_threads(threads);
    options.surface = surface_from_string(surface_name);
    CONTACTNN_REQUIRE_AS(InvalidArgument, f.min_angle_degrees <= f.max_angle_degrees,
                         "min_angle_degrees " << f.min_angle_degrees << " is above max_angle_degrees "
                                              << f.max_angle_degrees << ": no segment could pass");
    const std::filesystem::path effective_config = input.empty() ? cli::effective_config_path(output) : "";
    io::require_distinct({{"--output", output}, {"the effective config", effective_config}},
                         {{"--input", input}, {"--config", cli::config_path(app)}});

    // 3. Label mode: a user's CSV in, the same rows with labels out.
    if (!input.empty()) return label_mode(options.surface, input, output, options.projection);

    // 4. Enumeration mode: enumerate, label, write the dataset and the effective config (committed together,
    //    so the pair always comes from one run), summarise. The outputs are checked writable first.
    io::require_writable(output);
    if (!io::written_in_place(output)) io::require_writable(cli::effective_config_path(output));
    cli::Progress progress("gen-configs: labelling", quiet);
    dataset::EnumerationSummary summary;
    dataset::LabelledSet set = dataset::enumerate_configurations(
        options, summary, [&](std::int64_t done, std::int64_t total) { progress.update(done, total); });
    progress.finish();
    // Without the keys that do not change the data, so the file is byte-identical for any output path,
    // thread count or verbosity.
    set.config_toml = cli::effective_config(app, "gen-configs", {"output", "input", "threads", "quiet"});
    const auto dataset_file = io::write_dataset_uncommitted(output, set);
    const auto config_file = cli::write_effective_config(app, "gen-configs", output);
    io::commit_together({dataset_file.get(), config_file.get()});
    print_summary(summary, output);
    return 0;
  });
}
