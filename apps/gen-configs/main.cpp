// gen-configs: node-segment configurations labelled by Newton closest-point projection.
//
// Description:
//   Enumeration mode enumerates the configurations of the paper's Section 5.1 (bilinear) on the grid and
//   with the filters of a config file, labels each by the reference Newton projection and writes an HDF5
//   dataset (schema: docs/files.md, "Dataset"). Label mode labels a user's own configurations given in
//   world coordinates (SPEC section 6).
//
// Sample runs:
//   gen-configs --config configs/bilinear-paper.toml --output data/bilinear.h5
//   gen-configs --config configs/tiny.toml --output /tmp/tiny.h5 --threads 1
//   gen-configs --surface bilinear --input data/examples/raw-bilinear.csv --output /tmp/labels.csv
//   gen-configs --scene build/scenes/hertz.inp --surface gregory --output /tmp/hertz-pairs.csv
//   gen-configs --scene build/scenes/hertz.inp --search nearest_node --output /tmp/hertz-paper-pairs.csv
//   gen-configs --scene run/hertz-slide.inp --results run/hertz-slide.frd --increment all --output
//   /tmp/history.csv gen-configs --scene build/scenes/hertz.inp --surface gregory --sampling random --count
//   20000 --output /tmp/h.h5 gen-configs --config configs/gregory-paper.toml --sampling random --count 100000
//   --seed 2 --output /tmp/g.h5
//
// Writes:
//   enumeration: OUTPUT (.h5), OUTPUT.config.toml (effective config), a summary on stdout, progress on
//   stderr. label mode:  OUTPUT (.csv): the input columns, then xi,eta (u,v for
//   Gregory),status,gap,iterations; one row
//                per input row, in input order. xi, eta and gap are empty unless status is ok or outside.
//                Rows are streamed in chunks (bounded memory for any number of rows).
//   scene mode:  OUTPUT (.csv): one row per slave node of contact pair K of an .inp deck (SPEC 7), in
//                increasing node id: slave,a,b,c,d, the raw columns ax..sz (nax..ndz for Gregory), then the
//                label mode's columns; with the surface search (the default, SPEC 9) then
//                location,px,py,pz,face_type,nodes: face_type quad4, quad8, tri3 or tri6, nodes the face's
//                nodes in its own order (corners, then a quadratic face's mid-side nodes); a face that is not
//                a quad4 leaves a,b,c,d and the raw columns empty and puts its own local coordinates ((xi,
//                eta) of a quad8, (r, s) of a triangle) in the coordinate columns, under either --surface (a
//                quadratic face is its own surface under gregory too). The surface search's slave nodes are
//                every node of the slave faces, mid-side nodes included (SPEC 9); --search nearest_node keeps
//                SPEC 7's corner nodes. With --results RUN.frd the deck's nodes are moved to
//                --increment N|last|all of a CalculiX run (SPEC 10; `all`: every increment's rows, an
//                `increment` column first). A summary with the scene's shape statistics on stdout. With
//                --sampling random --count N: a dataset (.h5) of the scene's domain (scene_sampling.hpp).
//   The dataset and its config are committed together (one run's pair); outputs that are inputs are refused.
#include <omp.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <span>
#include <tuple>
#include <unordered_map>

#include "cli_support.hpp"
#include "contact/scene.hpp"
#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "dataset/enumeration.hpp"
#include "dataset/labeller.hpp"
#include "dataset/sampling.hpp"
#include "dataset/scene_sampling.hpp"
#include "history/plan_search.hpp"
#include "history/run_states.hpp"
#include "io/csv.hpp"
#include "io/dataset_file.hpp"
#include "io/file_identity.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "io/output_checks.hpp"
#include "io/raw_configurations.hpp"
#include "search/search_options.hpp"
#include "study/scene_domain.hpp"
#include "study/scene_pairs.hpp"

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
    labels[static_cast<std::size_t>(i)] =
        dataset::label_configuration(configs[static_cast<std::size_t>(i)], surface, options);
  }
}

/// Label mode: RAW.csv streamed through label_chunk in chunks of io::kRawChunkRows rows, so memory stays
/// bounded for any number of rows; the output appears only when every row is labelled.
int label_mode(SurfaceKind surface, const std::string& input, const std::string& output,
               const projection::ProjectionOptions& options) {
  const auto names = coordinate_names(surface);
  const std::vector<std::string> header = {std::string(names[0]), std::string(names[1]), "status", "gap",
                                           "iterations"};
  std::vector<std::string> replaced;
  std::vector<dataset::Label> labels;
  const std::size_t n = io::map_raw_configurations(
      input, output, surface, header,
      [&](const io::RawChunk& chunk, std::vector<std::vector<std::string>>& rows) {
        labels.resize(chunk.size());
        label_chunk(chunk.configs, surface, options, labels);
        for (std::size_t i = 0; i < labels.size(); ++i) {
          if (chunk.no_segment[i] != 0) labels[i] = dataset::Label{.status = Status::kNoSegment};
          rows[i] = study::label_csv_fields(labels[i]);
        }
      },
      &replaced);
  cli::warn_about_raw_output("gen-configs'", input, output, replaced, n);
  return 0;
}

/// Faces skipped by element type, e.g. "CPE4R face 1, C3D4 face 12", or "none".
std::string faces(const std::map<std::string, int>& skipped) {
  std::string text;
  for (const auto& [kind, count] : skipped)
    text += (text.empty() ? "" : ", ") + kind + " " + std::to_string(count);
  return text.empty() ? std::string("none") : text;
}

/// The slave nodes the surface search found no face for (no_segment: none within the capture distance), and
/// of those the ones behind the master surface (on the inner side of their nearest master node's normal):
/// nodes driven through the master deeper than the capture distance, whose contact the search does not see.
struct BeyondCapture {
  long nodes = 0;
  long behind = 0;
};

BeyondCapture beyond_capture(const contact::Scene& scene, const contact::SceneResult& result) {
  BeyondCapture out;
  std::unordered_map<long, std::size_t> slave_index;
  for (std::size_t i = 0; i < scene.slave_ids.size(); ++i) slave_index.emplace(scene.slave_ids[i], i);
  const std::vector<geometry::Vec3>& master = scene.master.positions;
  for (const contact::NodeSegmentPair& p : result.pairs) {
    if (p.status != contact::PairStatus::kNoSegment) continue;
    ++out.nodes;
    const auto s = slave_index.find(p.slave_id);
    if (s == slave_index.end() || master.empty()) continue;
    const geometry::Vec3& slave = scene.slave_positions[s->second];
    std::size_t nearest = 0;
    for (std::size_t j = 1; j < master.size(); ++j) {
      if ((master[j] - slave).squaredNorm() < (master[nearest] - slave).squaredNorm()) nearest = j;
    }
    if (nearest < scene.master_normals.size() &&
        (slave - master[nearest]).dot(scene.master_normals[nearest]) < 0.0) {
      ++out.behind;
    }
  }
  return out;
}

/// The scene's summary: counts, skipped faces and the shape statistics (min / median / max).
void print_scene_summary(const std::string& deck, const contact::Scene& scene,
                         const contact::SceneResult& result, SurfaceKind surface, const std::string& output,
                         double seconds) {
  const auto spread = [](const char* name, const contact::Spread& s) {
    if (s.count == 0) {
      std::printf("    %-34s -\n", name);
    } else {
      std::printf("    %-34s %.6g / %.6g / %.6g  (%ld values)\n", name, s.min, s.median, s.max, s.count);
    }
  };
  std::printf("gen-configs --scene summary\n");
  std::printf("  deck                 %s\n", deck.c_str());
  std::printf("  pair                 %d: slave '%s' -> master '%s' (%s)\n", scene.pair,
              scene.slave_name.c_str(), scene.master_name.c_str(), scene.where.c_str());
  std::printf("  surface              %s\n", std::string(to_string(surface)).c_str());
  std::printf("  master segments      %zu (%d nodes)\n", scene.master.segments.size(),
              scene.master.node_count());
  if (scene.cyclic_sectors > 0) {
    std::printf("  cyclic symmetry      %d sectors (%s)\n", scene.cyclic_sectors, scene.cyclic_where.c_str());
    std::printf(
        "                       master segments: the sector's and its two neighbours' (+-360/%d deg)\n",
        scene.cyclic_sectors);
  }
  std::printf("  slave nodes          %zu (%d also on the master surface, left out)\n",
              scene.slave_ids.size(), scene.slaves.shared_with_master);
  std::printf("  pairs found          %ld\n", result.found);
  std::printf("  no_segment           %ld\n", result.no_segment);
  std::string statuses;
  for (int i = 0; i < kStatusCount; ++i) {
    const long count = result.label_status_counts[static_cast<std::size_t>(i)];
    if (count > 0) {
      statuses += (statuses.empty() ? "" : ", ") + std::string(to_string(static_cast<Status>(i))) + " " +
                  std::to_string(count);
    }
  }
  std::printf("  label status         %s\n", statuses.empty() ? "-" : statuses.c_str());
  std::printf("  faces skipped        master: %s; slave: %s\n", faces(scene.master.skipped_faces).c_str(),
              faces(scene.slaves.skipped_faces).c_str());
  if (scene.master.inside_out_faces > 0) {
    std::printf("  inside-out elements  %d master faces oriented by their element's centroid\n",
                scene.master.inside_out_faces);
  }
  std::printf("  shape statistics over the found pairs (min / median / max):\n");
  const contact::ShapeStatistics& st = result.statistics;
  spread("interior angle (degrees)", st.interior_angle_degrees);
  spread("aspect ratio (longest/shortest)", st.aspect_ratio);
  spread("warp (/ shortest edge)", st.warp);
  spread("normal offset (gap / size)", st.normal_offset);
  if (surface == SurfaceKind::kGregory) spread("node-normal tilt (tangent)", st.normal_tilt_tangent);
  std::printf("  written              %zu rows -> %s\n", result.pairs.size(), output.c_str());
  std::printf("  time                 %.3f s\n", seconds);
}

/// A deck without pair `pair` is a usage error (exit 2) whose message names the deck.
template <typename Make>
auto in_deck(const std::string& deck, Make make) {
  try {
    return make();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument("'" + deck + "': " + e.what());
  }
}

/// Pair `pair` of the deck at `deck` made ready for the global search.
contact::Scene read_scene(const std::string& deck, int pair) {
  return in_deck(deck, [&] { return contact::make_scene(io::read_inp_deck(deck), pair); });
}

/// Pair `pair` of `model` (read from `deck`) over the increments of `results` (null: the deck's state).
history::RunStates run_states(mesh::ContactModel model, const std::string& deck, int pair,
                              const io::FrdResults* results) {
  return in_deck(deck, [&] { return history::RunStates(std::move(model), pair, results); });
}

/// The increments --increment names (SPEC 10): N, "last" or "all"; indices into results.increments.
std::vector<std::size_t> increments_named(const io::FrdResults& results, const std::string& increment) {
  if (increment == "all") {
    std::vector<std::size_t> all(results.increments.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    return all;
  }
  if (increment == "last") return {io::increment_index(results, io::kLastIncrement)};
  int number = 0;
  const auto [end, error] = std::from_chars(increment.data(), increment.data() + increment.size(), number);
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, error == std::errc() && end == increment.data() + increment.size() && number >= 1,
      "--increment: expected a number from 1, 'last' or 'all', got " << quote_text(increment));
  return {io::increment_index(results, number)};
}

/// Where a scene's state comes from: the deck alone, or the deck moved to increments of a results file.
struct SceneHistory {
  std::string results;       ///< --results RUN.frd, empty for the deck's own state
  std::string increment;     ///< --increment N|last|all
  bool trust_nodes = false;  ///< --trust-results-nodes: the node block is not checked against the deck
};

/// Scene mode (SPEC 7, 9, 10): the pairs of one *CONTACT PAIR of a deck, labelled, as a RAW.csv with node
/// ids; with --results, at one or every increment of a CalculiX run.
int scene_mode(const std::string& deck, int pair, const contact::SearchOptions& options,
               const std::string& output, const SceneHistory& history) {
  const auto start = std::chrono::steady_clock::now();
  // 1. Read the deck (and the results file, whose node ids must be the deck's).
  mesh::ContactModel model = io::read_inp_deck(deck);
  const std::vector<std::string> unapplied = cli::warn_unapplied_geometry("gen-configs", deck);
  std::optional<io::FrdResults> results;
  std::vector<std::size_t> increments = {0};
  if (!history.results.empty()) {
    results = io::read_frd(history.results);
    if (!history.trust_nodes) io::check_node_block(model, *results);
    increments = increments_named(*results, history.increment);
  }
  const bool all = history.increment == "all";

  // 2. The header: SPEC 7's columns (SPEC 10: `increment` first with --increment all), SPEC 9's after them.
  const bool surface_search = options.search == contact::GlobalSearchKind::kSurface;
  const study::PairsCsvLayout layout{options.surface, all, surface_search};
  std::string text;
  io::append_csv_row(text, study::pairs_csv_header(layout));

  // 3. The pair's master faces, node normals and slave nodes, built once (history::RunStates); for each
  //    state: the nodes moved, the search.
  history::RunStates run = run_states(std::move(model), deck, pair, results ? &*results : nullptr);
  if (!surface_search) study::keep_corner_slaves(run.scene());
  const contact::Scene* scene = &run.scene();
  std::optional<contact::SceneResult> result;
  std::array<long, 3> locations{};
  for (const std::size_t increment : increments) {
    if (results) scene = &run.move_to(increment);
    result = contact::search_scene(*scene, options);
    // 4. One row per slave node: ids, world coordinates (round-trip exact), the label, the closest point.
    for (const contact::NodeSegmentPair& p : result->pairs) {
      if (surface_search && p.status != contact::PairStatus::kNoSegment)
        ++locations[static_cast<std::size_t>(p.location)];
      study::append_pair_row(text, *scene, p, layout, all ? results->increments[increment].number : 0);
    }
  }
  io::write_text_atomically(output, text);

  // 5. Summary (of the last state read).
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_scene_summary(deck, *scene, *result, options.surface, output, seconds);
  if (surface_search) {
    const double capture = contact::capture_distance(scene->master, options);
    std::printf("  search               surface (capture distance %.6g)\n", capture);
    // A node beyond the capture distance has no contact; one behind the master surface is a contact lost (a
    // penetration deeper than the capture distance): counted, and said on stderr.
    const BeyondCapture beyond = beyond_capture(*scene, *result);
    std::printf(
        "  beyond capture       %ld slave nodes (no face within %.6g), %ld of them behind the master "
        "surface\n",
        beyond.nodes, capture, beyond.behind);
    if (beyond.behind > 0) {
      std::fprintf(
          stderr,
          "gen-configs: warning: %ld slave node(s) of pair %d lie behind the master surface farther than the "
          "capture distance %.6g from every face: penetrations deeper than it, whose contact the search "
          "does not find (no_segment); give --capture_distance larger than the deepest penetration\n",
          beyond.behind, scene->pair, capture);
    }
    std::printf("  closest points       face %ld, edge %ld, vertex %ld%s\n", locations[0], locations[1],
                locations[2], all ? " (every increment)" : "");
  } else {
    std::printf("  search               nearest_node\n");
  }
  std::printf("  not applied          %zu keyword(s) that change the contact geometry%s\n", unapplied.size(),
              unapplied.empty() ? "" : " (named on stderr)");
  for (const std::string& k : unapplied) std::printf("                       %s\n", k.c_str());
  if (results) {
    const io::FrdIncrement& last = results->increments[increments.back()];
    std::printf("  results              %s: %zu increment%s read (last: %d, step %d, time %.6g)\n",
                history.results.c_str(), increments.size(), increments.size() == 1 ? "" : "s", last.number,
                last.step, last.time);
  }
  // A pair with nothing to search is valid input but almost certainly not what the user meant (a 2-D deck,
  // shell or tetrahedral surfaces, a set that names no element): say so where a script will see it. (The
  // surface search also has the master's other faces: triangles, wedge and quadratic faces.)
  const std::size_t searched =
      surface_search ? static_cast<std::size_t>(scene->master.face_count()) : scene->master.segments.size();
  if (searched == 0 || scene->slave_ids.empty()) {
    std::fprintf(
        stderr,
        "gen-configs: warning: contact pair %d of %s has %zu master segments and %zu slave nodes (faces "
        "skipped, master: %s; slave: %s); %s has no pair\n",
        scene->pair, deck.c_str(), scene->master.segments.size(), scene->slave_ids.size(),
        faces(scene->master.skipped_faces).c_str(), faces(scene->slaves.skipped_faces).c_str(),
        output.c_str());
  }
  return 0;
}

/// Scene domain mode: random configurations of the domain a scene requires (its master segments deformed,
/// the slave anywhere a contact can occur), labelled: the training set of a scene network.
/// The capture distance covers at least the deck's own slave nodes (study::widen_capture:
/// SceneDomainOptions::capture is the least).
dataset::LabelledSet scene_domain(const std::string& deck, int pair, dataset::SceneDomainOptions domain,
                                  const dataset::EnumerationOptions& options, std::int64_t count,
                                  dataset::EnumerationSummary& summary, const dataset::ProgressFn& progress) {
  const contact::Scene scene = read_scene(deck, pair);
  // The segments the paper's search pairs every slave node with: the offsets of all of them, far ones too.
  const double offset = study::nearest_node_offset(scene, options.surface, options.projection);
  study::widen_capture(domain, offset, [](std::string_view line) {
    std::fprintf(stderr, "gen-configs: %.*s\n", static_cast<int>(line.size()), line.data());
  });
  std::vector<dataset::SceneSegment> segments;
  study::append_scene_segments(scene, segments);
  return dataset::sample_scene(segments, domain, options, count, summary, progress);
}

/// What the command line sets: every default lives in the options structs of lib/; flags only map onto them.
struct Settings {
  dataset::EnumerationOptions options;
  std::string surface_name = "bilinear";
  std::string input, output, scene;
  int pair = 0;
  int threads = 0;
  bool quiet = false;
  std::string search_name = "surface";
  contact::SearchOptions search;
  std::string narrow_name = "certified";
  std::string plan_file;
  SceneHistory history;
  dataset::SceneDomainOptions scene_options;
  std::string sampling = "grid";
  std::int64_t count = 0;
  std::optional<history::PlanSearch> plan;  ///< --plan's method, which search.interior points into
};

/// The options that choose the mode and its inputs and outputs: --surface to --quiet.
void add_mode_options(CLI::App& app, Settings& s) {
  app.add_option("--surface", s.surface_name, "bilinear or gregory")
      ->check(CLI::IsMember({"bilinear", "gregory"}));
  app.add_option("--input", s.input, "label mode: RAW.csv of world configurations (SPEC 6)")
      ->check(CLI::ExistingFile);
  auto* input_option = app.get_option("--input");
  auto* scene_option = app.add_option("--scene", s.scene, "scene mode: an Abaqus/CalculiX .inp deck (SPEC 7)")
                           ->check(CLI::ExistingFile);
  scene_option->excludes(input_option);
  input_option->excludes(scene_option);
  // No captured default: the effective config of the other modes must not carry a --pair that needs --scene.
  app.add_option("--pair", s.pair, "scene mode: the *CONTACT PAIR data line, counted from 0 (default 0)")
      ->transform(cli::integer_in(0, 1000000))
      ->needs(scene_option)
      ->default_str("");
  app.add_option(
         "--search", s.search_name,
         "scene mode: surface (the closest point of every master face within the capture distance, SPEC 9) "
         "or nearest_node (the paper's search, SPEC 7)")
      ->check(CLI::IsMember({"surface", "nearest_node"}))
      ->needs(scene_option)
      ->default_str("");
  app.add_option(
         "--capture_distance", s.search.capture_distance,
         "surface search: faces within this distance of a slave node (world units; default: the largest "
         "master face size)")
      ->check(cli::kPositive)
      ->needs(scene_option);
  app.add_option(
         "--narrow", s.narrow_name,
         "surface search: how each face's closest point is found: certified (one Newton run where a "
         "certificate proves it the face's nearest, the reference elsewhere) or reference (the grid of "
         "starts on every face, as before the certificate); the same answers")
      ->check(CLI::IsMember({"certified", "reference"}))
      ->needs(scene_option)
      ->default_str("");
  app.add_option("--plan", s.plan_file,
                 "surface search: a scene plan (scene-study's plan.toml) whose method answers face interiors "
                 "(a pair it refuses or puts outside the face takes the exact closest point); the plan's "
                 "surface")
      ->check(CLI::ExistingFile)
      ->needs(scene_option);
  auto* results_option =
      app.add_option("--results", s.history.results,
                     "scene mode: a CalculiX .frd; the scene at --increment of it (SPEC 10)")
          ->check(CLI::ExistingFile)
          ->needs(scene_option);
  app.add_option("--increment", s.history.increment, "with --results: N (from 1), last or all (default last)")
      ->needs(results_option);
  app.add_flag(
         "--trust-results-nodes", s.history.trust_nodes,
         "with --results: take the .frd's node coordinates even where they are not the deck's (another mesh "
         "with the same node ids is refused otherwise)")
      ->needs(results_option);
  app.add_option("--output", s.output,
                 "dataset .h5 (enumeration), labels .csv (label mode) or pairs .csv (scene mode)")
      ->required();
  app.add_option("--threads", s.threads, "OpenMP threads (0: OpenMP's default)")
      ->transform(cli::integer_in(0, cli::kMaxThreads));
  app.add_flag("--quiet", s.quiet, "no progress line");
}

/// The options of the data: the grid, the scene domain, the sampling, the filters and the projection (--seed
/// to --domain_margin).
void add_data_options(CLI::App& app, Settings& s) {
  dataset::EnumerationOptions& options = s.options;
  auto& f = options.filters;
  app.add_option("--seed", options.seed, "seed of the Gregory node-normal sampling")
      ->transform(cli::integer_in(0, cli::kMaxSeed));
  // The enumeration's grids (SPEC 3), 1 to 400 points each.
  for (const auto& [flag, points, what] :
       {std::tuple{"--d_xy_points", &options.d_xy_points, "grid points per axis, x and y of D"},
        std::tuple{"--c_xy_points", &options.c_xy_points, "grid points per axis, x and y of C"},
        std::tuple{"--c_z_points", &options.c_z_points, "grid points, z of C"},
        std::tuple{"--s_xy_points", &options.s_xy_points, "grid points per axis, x and y of S"},
        std::tuple{"--s_z_points", &options.s_z_points, "grid points, z of S"}}) {
    app.add_option(flag, *points, what)->transform(cli::integer_in(1, 400));
  }
  app.add_option("--normal_sets", options.normal_sets, "Gregory: node-normal sets per configuration")
      ->transform(cli::integer_in(1, 1000));
  app.add_option("--deformation", s.scene_options.deformation,
                 "scene domain: node displacement, fraction of each segment's shortest edge")
      ->check(cli::real_in(0.0, 0.49));
  app.add_option(
         "--capture", s.scene_options.capture,
         "scene domain: slave offset along the normal, fraction of the shortest edge, either side (at "
         "least 1.25 x the deck's own largest)")
      ->check(cli::kPositive);
  app.add_option(
         "--boundary_fraction", s.scene_options.boundary_fraction,
         "scene domain: fraction of slave foot points on the segment's nodes and edges (matching meshes)")
      ->check(cli::real_in(0.0, 1.0));
  app.add_option("--normal_tilt_tangent", s.scene_options.normal_tilt_tangent,
                 "scene domain, Gregory: node normals tilted from the scene's by up to this tangent")
      ->check(cli::kNonNegative);
  app.add_option(
         "--sampling", s.sampling,
         "grid: the paper's enumeration on the grid below; random: --count configurations drawn uniformly "
         "from the same domain (stream --seed)")
      ->check(CLI::IsMember({"grid", "random"}));
  app.add_option("--count", s.count,
                 "random sampling: configurations to draw (0: none; required with random)")
      ->transform(cli::integer_in(0, 1'000'000'000));
  app.add_option("--require_projection_inside", options.require_projection_inside,
                 "keep only configurations whose projection lies inside the segment");
  app.add_option("--xy_limit", f.xy_limit, "|x|, |y| of C, D, S below this")->check(cli::kPositive);
  app.add_option("--z_limit", f.z_limit, "|z| of C, S below this")->check(cli::kPositive);
  app.add_option("--ad_not_longer_than_ab", f.ad_not_longer_than_ab, "|AD| <= |AB|");
  app.add_option("--nearest_node_a", f.nearest_node_a, "A is the master node nearest S");
  app.add_option("--segment_test_a", f.segment_test_a, "S passes the segment test (Eqs 3-6) at A");
  app.add_option("--convex", f.convex, "the segment is strictly convex");
  app.add_option("--min_angle_degrees", f.min_angle_degrees, "smallest interior angle")
      ->check(CLI::Range(0.0, 180.0));
  app.add_option("--max_angle_degrees", f.max_angle_degrees, "largest interior angle")
      ->check(CLI::Range(0.0, 180.0));
  app.add_option("--max_normal_tilt_tangent", f.max_normal_tilt_tangent,
                 "Gregory: tangent of the largest normal tilt")
      ->check(cli::kPositive);
  app.add_option("--max_iterations", options.projection.max_iterations, "Newton iterations per start")
      ->transform(cli::integer_in(1, 10000));
  app.add_option("--tol_param", options.projection.tol_param, "Newton step tolerance (parameter units)")
      ->check(cli::kPositive);
  app.add_option("--starts_per_axis", options.projection.starts_per_axis, "Newton starts per parameter axis")
      ->transform(cli::integer_in(1, 10));
  app.add_option("--domain_margin", options.projection.domain_margin, "parameter slack counted as inside")
      ->check(cli::real_in(0.0, search::kMaxDomainMargin));
}

/// Threads, surface, and what must hold before any work: settings that contradict each other, an output that
/// is an input.
void check_settings(const CLI::App& app, Settings& s) {
  if (s.threads > 0) omp_set_num_threads(s.threads);
  s.options.surface = surface_from_string(s.surface_name);
  const auto& f = s.options.filters;
  CONTACTNN_REQUIRE_AS(InvalidArgument, f.min_angle_degrees <= f.max_angle_degrees,
                       "min_angle_degrees " << f.min_angle_degrees << " is above max_angle_degrees "
                                            << f.max_angle_degrees << ": no segment could pass");
  // Every output checked before any work (io::require_outputs: exit 2 for an output that is an input, 4 for
  // one that cannot be written); the effective config goes beside a dataset written to a regular file.
  const bool writes_config = s.input.empty() && (s.scene.empty() || s.sampling == "random");
  const std::filesystem::path effective_config =
      writes_config && !io::written_in_place(s.output) ? cli::effective_config_path(s.output) : "";
  io::require_outputs({{"--output", s.output}, {"the effective config", effective_config}}, {},
                      {{"--input", s.input},
                       {"--scene", s.scene},
                       {"--config", cli::config_path(app)},
                       {"--results", s.history.results},
                       {"--plan", s.plan_file}});
}

/// Scene mode's search settings: the surface, the projection, the narrow phase, the global search, the
/// history's increment and the plan (whose surface becomes the run's).
void configure_scene_search(const CLI::App& app, Settings& s) {
  contact::SearchOptions& search = s.search;
  SceneHistory& history = s.history;
  search.surface = s.options.surface;
  search.projection = s.options.projection;
  search.narrow =
      s.narrow_name == "reference" ? contact::NarrowPhase::kReference : contact::NarrowPhase::kCertified;
  search.search = s.search_name == "nearest_node" ? contact::GlobalSearchKind::kNearestNode
                                                  : contact::GlobalSearchKind::kSurface;
  // --increment '' is no increment (it was taken as `last`): refused like any other bad value.
  CONTACTNN_REQUIRE_AS(InvalidArgument, app.count("--increment") == 0 || !history.increment.empty(),
                       "--increment: expected a number from 1, 'last' or 'all', got ''");
  if (!history.results.empty() && history.increment.empty()) history.increment = "last";
  CONTACTNN_REQUIRE_AS(InvalidArgument, history.results.empty() || s.sampling != "random",
                       "--results: a scene's domain (--sampling random) is sampled from the deck alone");
  if (!s.plan_file.empty()) {
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, search.search == contact::GlobalSearchKind::kSurface && s.sampling != "random",
        "--plan: the surface search's pairs only (not --search nearest_node or --sampling random)");
    s.plan.emplace(history::load_plan_search(s.plan_file));
    CONTACTNN_REQUIRE_AS(InvalidArgument,
                         app.count("--surface") == 0 || s.plan->plan.surface == s.options.surface,
                         "--surface " << s.surface_name << ": the plan '" << s.plan_file << "' is for "
                                      << to_string(s.plan->plan.surface) << " surfaces");
    s.options.surface = search.surface = s.plan->plan.surface;
    search.interior = s.plan->locator.get();
  }
}

/// Enumeration or random sampling (of the paper's domain or a scene's): label, write the dataset and the
/// effective config, summarise.
int dataset_mode(const CLI::App& app, Settings& s) {
  CONTACTNN_REQUIRE(s.sampling == "grid" || s.count > 0, "--sampling random needs --count N");
  cli::Progress progress("gen-configs: labelling", s.quiet);
  const auto report = [&](std::int64_t done, std::int64_t total) { progress.update(done, total); };
  dataset::EnumerationSummary summary;
  dataset::LabelledSet set =
      !s.scene.empty() ? scene_domain(s.scene, s.pair, s.scene_options, s.options, s.count, summary, report)
      : s.sampling == "random" ? dataset::sample_configurations(s.options, s.count, summary, report)
                               : dataset::enumerate_configurations(s.options, summary, report);
  progress.finish();
  // Without the keys that do not change the data, so the file is byte-identical for any output path,
  // thread count or verbosity.
  set.config_toml = cli::effective_config(app, "gen-configs", {"output", "input", "threads", "quiet"});
  const auto dataset_file = io::write_dataset_uncommitted(s.output, set);
  const auto config_file = cli::write_effective_config(app, "gen-configs", s.output);
  io::commit_together({dataset_file.get(), config_file.get()});
  print_summary(summary, s.output);
  return 0;
}

/// The parsed command line run: the checks, then the mode (label, scene, or a dataset).
int run_gen_configs(const CLI::App& app, Settings& s) {
  check_settings(app, s);
  // Label mode: a user's CSV in, the same rows with labels out.
  if (!s.input.empty()) return label_mode(s.options.surface, s.input, s.output, s.options.projection);
  // Scene mode: a deck in, its contact pair's node-segment pairs with labels out (with --sampling random: the
  // scene's domain as a dataset).
  configure_scene_search(app, s);
  if (!s.scene.empty() && s.sampling != "random")
    return scene_mode(s.scene, s.pair, s.search, s.output, s.history);
  return dataset_mode(app, s);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace contactnn;
  CLI::App app{"gen-configs: enumerate node-segment configurations and label them by Newton projection"};
  cli::add_exit_code_footer(app);
  cli::add_config_option(app, "gen-configs");
  Settings settings;
  add_mode_options(app, settings);
  add_data_options(app, settings);
  return cli::run(app, argc, argv, [&]() -> int { return run_gen_configs(app, settings); });
}
