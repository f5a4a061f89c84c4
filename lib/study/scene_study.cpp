#include "study/scene_study.hpp"

#include <omp.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <limits>
#include <mutex>
#include <sstream>
#include <thread>

#include "core/error.hpp"
#include "core/input_features.hpp"
#include "dataset/labeller.hpp"
#include "eval/report.hpp"
#include "geometry/bilinear_patch.hpp"
#include "io/csv.hpp"
#include "mlp/pattern_selection.hpp"
#include "mlp/random.hpp"
#include "mlp/trainer.hpp"
#include "search/local_search.hpp"
#include "search/method.hpp"
#include "study/json_text.hpp"

namespace contactnn::study {

using detail::json_number;
using detail::json_string;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<std::string> split_methods(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto first = item.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    out.push_back(item.substr(first, item.find_last_not_of(" \t") - first + 1));
  }
  return out;
}

std::string join(const std::vector<int>& sizes) {
  std::string out;
  for (const int s : sizes) out += (out.empty() ? "" : ",") + std::to_string(s);
  return out;
}

int feature_count_of(SurfaceKind surface) { return surface == SurfaceKind::kBilinear ? 8 : 16; }

std::string network_name(SurfaceKind surface, int hidden, int second_layer) {
  return std::to_string(feature_count_of(surface)) + "-" + std::to_string(hidden) +
         (second_layer > 0 ? "-" + std::to_string(second_layer) : std::string()) + "-2";
}

int team_size(const SceneStudyOptions& options) {
  return options.threads > 0 ? options.threads : omp_get_max_threads();
}

/// Appends a configuration's SPEC 6 raw values (as lib/eval's sets hold them).
void append_raw(std::vector<double>& raw, const geometry::Configuration& c, SurfaceKind kind) {
  for (const auto& node : c.nodes) raw.insert(raw.end(), {node.x(), node.y(), node.z()});
  raw.insert(raw.end(), {c.slave.x(), c.slave.y(), c.slave.z()});
  if (kind == SurfaceKind::kGregory) {
    for (const auto& n : c.normals) raw.insert(raw.end(), {n.x(), n.y(), n.z()});
  }
}

/// An evaluation set of pairs (the reference's labels in the caller's order, as gen-configs --scene writes
/// them).
struct SetBuilder {
  eval::EvaluationSet set;
  std::vector<double> labels;
  SetBuilder(std::string name, std::string source, SurfaceKind kind) {
    set.name = std::move(name);
    set.source = std::move(source);
    set.surface = kind;
  }
  void add(const contact::NodeSegmentPair& p) {
    append_raw(set.raw, p.config, set.surface);
    set.label_status.push_back(p.label.status);
    set.label_gap.push_back(p.label.gap);
    set.size.push_back(geometry::max_node_distance(p.config.nodes));
    set.label_iterations.push_back(p.label.iterations);
    labels.insert(labels.end(), {p.label.param[0], p.label.param[1]});
  }
  eval::EvaluationSet finish() {
    set.labels = Eigen::Map<const dataset::MatrixRM<double>>(labels.data(), set.rows(), 2);
    return std::move(set);
  }
};

/// The training data every size shares: the pattern draw, the scaling (from the training inputs alone, so
/// the same for every size), the scaled patterns and the training domain. train-net's steps 3 and 4.
struct TrainingData {
  mlp::Scaling scaling;
  geometry::TrainingDomain domain;
  mlp::MatrixRM<float> train_x, train_t, validation_x, validation_t;
};

TrainingData prepare_training(const dataset::LabelledSet& set, const SceneStudyOptions& o) {
  TrainingData d;
  std::vector<std::uint32_t> ok_rows;
  for (Eigen::Index r = 0; r < set.size(); ++r) {
    if (set.status[static_cast<std::size_t>(r)] == Status::kOk)
      ok_rows.push_back(static_cast<std::uint32_t>(r));
  }
  const auto train_count = static_cast<std::size_t>(static_cast<double>(o.count) * o.train_fraction);
  const auto validation_count =
      static_cast<std::size_t>(std::llround(o.validation_fraction * static_cast<double>(train_count)));
  CONTACTNN_REQUIRE_AS(InvalidArgument, train_count >= 1 && train_count + validation_count <= ok_rows.size(),
                       "train_fraction "
                           << o.train_fraction << " and validation_fraction " << o.validation_fraction
                           << " need " << train_count + validation_count
                           << " configurations with status ok; the scene's sample has " << ok_rows.size());
  const mlp::PatternSelection selection =
      mlp::select_patterns(ok_rows, train_count, validation_count, mlp::Rng::derive_seed(o.seed, 1));
  const int n_features = feature_count_of(set.surface);
  const InputFeatures input_map = input_features_from_string(o.input_features);
  mlp::MatrixRM<double> inputs(set.size(), n_features);
  for (Eigen::Index r = 0; r < set.size(); ++r) {
    map_input_features(input_map, set.surface, set.features.row(r).data(), inputs.row(r).data());
  }
  mlp::MatrixRM<double> train_raw(static_cast<Eigen::Index>(selection.training.size()), n_features);
  for (Eigen::Index r = 0; r < train_raw.rows(); ++r)
    train_raw.row(r) = inputs.row(selection.training[static_cast<std::size_t>(r)]);
  const ParamDomain range = param_domain(set.surface);
  d.scaling = mlp::Scaling::from_inputs(train_raw, 2, range.lo, range.hi, o.input_quantile);
  d.scaling.input_features = input_map;
  d.scaling.target_low = o.target_low;
  d.scaling.target_high = o.target_high;
  d.scaling.validate(n_features, 2);
  const auto scaled = [&](const std::vector<std::uint32_t>& rows, mlp::MatrixRM<float>& x,
                          mlp::MatrixRM<float>& t) {
    x.resize(static_cast<Eigen::Index>(rows.size()), n_features);
    t.resize(static_cast<Eigen::Index>(rows.size()), 2);
    for (Eigen::Index r = 0; r < x.rows(); ++r) {
      const auto row = static_cast<Eigen::Index>(rows[static_cast<std::size_t>(r)]);
      for (int i = 0; i < n_features; ++i)
        x(r, i) = static_cast<float>(d.scaling.scale_input(i, inputs(row, i)));
      for (int k = 0; k < 2; ++k) t(r, k) = static_cast<float>(d.scaling.scale_target(k, set.labels(row, k)));
    }
  };
  scaled(selection.training, d.train_x, d.train_t);
  scaled(selection.validation, d.validation_x, d.validation_t);
  d.domain = geometry::TrainingDomain::from_features(set.surface, set.features.data(),
                                                     static_cast<long>(set.size()), set.status, set.filters);
  return d;
}

mlp::Network<float> fresh_network(SurfaceKind surface, int hidden, const TrainingData& data,
                                  const SceneStudyOptions& o) {
  std::vector<int> sizes{feature_count_of(surface), hidden};
  if (o.second_layer > 0) sizes.push_back(o.second_layer);
  sizes.push_back(2);
  mlp::Network<float> network(sizes, o.u0, data.scaling);
  network.initialize(mlp::Rng::derive_seed(o.seed, 0));
  return network;
}

/// The network alone on `set`: mean |error| of each coordinate (1 thread: called from a training thread).
std::array<double, 2> heldout_errors(const search::NetworkModel& model, const eval::EvaluationSet& set,
                                     const SceneStudyOptions& o) {
  const search::LocalSearch search(set.surface, search::Method::parse("network"), {}, &model);
  const eval::Estimates e = eval::run_on_set(search, set, 1);
  const eval::MethodErrors m = eval::compare_with_labels("network", e, set, o.failure_box_margin, false);
  return {m.stats[0].mean_abs, m.stats[1].mean_abs};
}

/// A snapshot of a training: the parameters of its best validation epoch (restore_best), made ready for
/// lib/search.
SceneNetwork snapshot(const mlp::Network<float>& network, const mlp::TrainingState<float>& state,
                      std::string name, int hidden, const TrainingData& data,
                      const eval::EvaluationSet& heldout, const SceneStudyOptions& o) {
  auto kept = std::make_shared<mlp::Network<float>>(network);
  if (state.best_epoch > 0) kept->parameters() = state.best_parameters;
  SceneNetwork n;
  n.name = std::move(name);
  n.hidden = hidden;
  n.epochs = state.epoch;
  n.best_epoch = state.best_epoch;
  n.validation_loss = state.best_validation_loss;
  n.domain = data.domain;
  n.model = std::make_shared<search::NetworkModel>(*kept, data.domain);
  n.network = std::move(kept);
  const std::array<double, 2> e = heldout_errors(*n.model, heldout, o);
  n.heldout_mean_abs[0] = e[0];
  n.heldout_mean_abs[1] = e[1];
  return n;
}

}  // namespace

std::string_view to_string(TrainNetworks mode) {
  switch (mode) {
    case TrainNetworks::kAuto: return "auto";
    case TrainNetworks::kAlways: return "always";
    case TrainNetworks::kNever: return "never";
  }
  return "unknown";
}

std::string_view to_string(DomainStates states) {
  switch (states) {
    case DomainStates::kAuto: return "auto";
    case DomainStates::kRest: return "rest";
    case DomainStates::kHistory: return "history";
  }
  return "unknown";
}

DomainStates domain_states_from_string(std::string_view name) {
  if (name == "auto") return DomainStates::kAuto;
  if (name == "rest") return DomainStates::kRest;
  if (name == "history") return DomainStates::kHistory;
  throw InvalidArgument("domain: expected auto, rest or history, got '" + std::string(name) + "'");
}

TrainNetworks train_networks_from_string(std::string_view name) {
  if (name == "auto") return TrainNetworks::kAuto;
  if (name == "always") return TrainNetworks::kAlways;
  if (name == "never") return TrainNetworks::kNever;
  throw InvalidArgument("train_networks: expected auto, always or never, got '" + std::string(name) + "'");
}

std::string default_methods(SurfaceKind surface) {
  std::string list =
      "closed_form,closed_form+newton:1,closed_form+newton:2,closed_form+newton:3,newton:1,newton:2,"
      "newton:3,newton:4,newton:5,newton";
  if (surface == SurfaceKind::kBilinear) {
    // The methods of lib/search that other work adds, where this build has them.
    for (const char* extra : {"four_triangles"}) {
      try {
        (void)search::Method::parse(extra);
        list += std::string(",") + extra;
      } catch (const InvalidArgument&) {
      }
    }
  }
  return list;
}

SceneStudyOptions resolved(SceneStudyOptions o, SurfaceKind surface) {
  const bool gregory = surface == SurfaceKind::kGregory;
  if (o.sizes.empty()) o.sizes = gregory ? std::vector<int>{16, 32, 48} : std::vector<int>{8, 16, 32};
  if (!(o.target > 0.0)) o.target = gregory ? 0.0025 : 0.005;
  if (!(o.learning_rate > 0.0)) o.learning_rate = gregory ? 0.01 : 0.02;
  if (o.methods.empty()) o.methods = default_methods(surface);
  CONTACTNN_REQUIRE_AS(InvalidArgument, o.count >= 100, "count = " << o.count << ", expected at least 100");
  CONTACTNN_REQUIRE_AS(InvalidArgument, o.heldout_divisor >= 1,
                       "heldout_divisor = " << o.heldout_divisor << ", expected >= 1");
  for (const int h : o.sizes) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, h >= 1 && h <= search::NetworkModel::kMaxWidth,
                         "sizes: " << h << " hidden units, expected 1.." << search::NetworkModel::kMaxWidth);
  }
  CONTACTNN_REQUIRE_AS(InvalidArgument, std::is_sorted(o.sizes.begin(), o.sizes.end()),
                       "sizes " << join(o.sizes) << ": expected the smallest first");
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, o.epochs >= 1 && o.long_epochs >= 0,
      "epochs " << o.epochs << " and long_epochs " << o.long_epochs << ": expected >= 1 and >= 0");
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, std::isfinite(o.target) && std::isfinite(o.margin) && o.margin > 0.0,
      "target " << o.target << " and margin " << o.margin << ": expected finite numbers > 0");
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       o.train_fraction > 0.0 && o.train_fraction <= 1.0 && o.validation_fraction >= 0.0,
                       "train_fraction " << o.train_fraction << " must be in (0, 1], validation_fraction "
                                         << o.validation_fraction << " >= 0");
  CONTACTNN_REQUIRE_AS(InvalidArgument, o.timing_queries >= 1, "timing_queries = " << o.timing_queries);
  (void)input_features_from_string(o.input_features);
  CONTACTNN_REQUIRE_AS(InvalidArgument, o.capture_pairs == "nearest_node" || o.capture_pairs == "surface",
                       "capture_pairs: expected nearest_node or surface, got '" << o.capture_pairs << "'");
  for (const std::string& m : split_methods(o.methods)) {
    const search::Method method = search::Method::parse(m);
    CONTACTNN_REQUIRE_AS(InvalidArgument, !method.needs_network() && !method.needs_start(),
                         "methods: '"
                             << m
                             << "' needs a network or a caller's start; scene networks' methods go in "
                                "network_methods");
    (void)search::LocalSearch(surface, method);  // a method the surface has (four_triangles: bilinear only)
  }
  for (const std::string& m : split_methods(o.network_methods)) {
    CONTACTNN_REQUIRE_AS(InvalidArgument, search::Method::parse(m).needs_network(),
                         "network_methods: '" << m << "' uses no network; it belongs in methods");
  }
  return o;
}

// ---------------------------------------------------------------------------------------------- 1. pairs

ScenePairs search_pairs(const contact::Scene& scene, SurfaceKind surface) {
  contact::SearchOptions options;
  options.surface = surface;
  options.search = contact::GlobalSearchKind::kSurface;
  ScenePairs out;
  out.result = contact::search_scene(scene, options);
  SetBuilder face("face-pairs", "the deck's pairs inside a face", surface);
  SetBuilder quad4("quad4-pairs", "the deck's pairs on quadrilaterals", surface);
  for (const contact::NodeSegmentPair& p : out.result.pairs) {
    if (p.status != contact::PairStatus::kFound) continue;
    ++out.locations[static_cast<std::size_t>(p.location)];
    if (scene.master.face_nodes(p.segment).type != mesh::FaceType::kQuad4) continue;
    ++out.quad4;
    quad4.add(p);
    if (p.location == Location::kFace) face.add(p);
  }
  out.face = face.finish();
  out.quad4_pairs = quad4.finish();
  return out;
}

std::string pairs_csv(const contact::Scene& scene, const ScenePairs& pairs, SurfaceKind surface) {
  const bool gregory = surface == SurfaceKind::kGregory;
  std::vector<std::string> header;
  for (const char* name : {"slave", "a", "b", "c", "d"}) header.emplace_back(name);
  for (auto name : kRawPointColumns) header.emplace_back(name);
  if (gregory) {
    for (auto name : kRawNormalColumns) header.emplace_back(name);
  }
  const auto names = coordinate_names(surface);
  for (const char* name : {names[0].data(), names[1].data(), "status", "gap", "iterations"})
    header.emplace_back(name);
  const std::size_t status_column = header.size() - 3;
  for (const char* name : {"location", "px", "py", "pz", "face_type", "nodes"}) header.emplace_back(name);
  std::string text;
  io::append_csv_row(text, header);
  std::vector<std::string> row;
  for (const contact::NodeSegmentPair& p : pairs.result.pairs) {
    row.assign(header.size(), "");
    std::size_t c = 0;
    row[c++] = std::to_string(p.slave_id);
    if (p.status == contact::PairStatus::kNoSegment) {
      row[status_column] = "no_segment";
      io::append_csv_row(text, row);
      continue;
    }
    const mesh::FaceNodes face = scene.master.face_nodes(p.segment);
    if (face.type == mesh::FaceType::kQuad4) {
      for (int n : p.nodes) row[c++] = std::to_string(scene.master.node_ids[static_cast<std::size_t>(n)]);
      for (const auto& x : p.config.nodes) {
        for (int k = 0; k < 3; ++k) row[c++] = io::format_double(x[k]);
      }
      for (int k = 0; k < 3; ++k) row[c++] = io::format_double(p.config.slave[k]);
      if (gregory) {
        for (const auto& n : p.config.normals) {
          for (int k = 0; k < 3; ++k) row[c++] = io::format_double(n[k]);
        }
      }
    } else {
      c += 4 + kRawPointColumns.size() + (gregory ? kRawNormalColumns.size() : 0);
    }
    const dataset::Label& l = p.label;
    const bool has_value = l.status == Status::kOk || l.status == Status::kOutside;
    const auto value = [&](double x) { return has_value ? io::format_double(x + 0.0) : std::string(); };
    row[c++] = value(l.param[0]);
    row[c++] = value(l.param[1]);
    row[c++] = std::string(to_string(l.status));
    row[c++] = value(l.gap);
    row[c++] = std::to_string(l.iterations);
    row[c++] = std::string(to_string(p.location));
    for (int k = 0; k < 3; ++k) row[c++] = io::format_double(p.point[k] + 0.0);
    row[c++] = std::string(mesh::to_string(face.type));
    std::string face_nodes;
    for (int n : face)
      face_nodes += (face_nodes.empty() ? "" : " ") +
                    std::to_string(scene.master.node_ids[static_cast<std::size_t>(n)]);
    row[c++] = std::move(face_nodes);
    io::append_csv_row(text, row);
  }
  return text;
}

// --------------------------------------------------------------------------------------------- 2. domain

SceneDomain sample_domain(const contact::Scene& scene, SurfaceKind surface, const SceneStudyOptions& options,
                          const StudyLog& log) {
  return sample_domain(std::vector<const contact::Scene*>{&scene}, surface, options, log);
}

SceneDomain sample_domain(const std::vector<const contact::Scene*>& states, SurfaceKind surface,
                          const SceneStudyOptions& options, const StudyLog& log) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, !states.empty(), "sample_domain: no state of the scene");
  dataset::EnumerationOptions generator;
  generator.surface = surface;
  generator.seed = options.seed;
  SceneDomain out;
  std::vector<dataset::SceneSegment> segments;
  for (const contact::Scene* state : states) {
    const contact::Scene& scene = *state;
    CONTACTNN_REQUIRE_AS(
        InvalidArgument, !scene.master.segments.empty(),
        "pair " << scene.pair << ": the master surface has no quadrilateral segment: no domain to sample");
    if (options.capture_pairs == "surface") {
      // The capture covers the pairs the local search serves: the surface search's on quad4 faces.
      out.deck_offset =
          std::max(out.deck_offset, contact::largest_relative_offset(search_pairs(scene, surface).result));
    } else {
      // The capture covers the deck's own slave nodes: the offsets of the paper's nearest-node pairs (SPEC
      // 7's slave nodes, corners only), far ones too.
      contact::Scene corners = scene;
      corners.slaves = mesh::corner_slaves(scene.slaves);
      corners.slave_ids.clear();
      corners.slave_positions.clear();
      for (std::size_t i = 0; i < scene.slave_ids.size(); ++i) {
        if (i < scene.slaves.midside.size() && scene.slaves.midside[i] != 0) continue;
        corners.slave_ids.push_back(scene.slave_ids[i]);
        corners.slave_positions.push_back(scene.slave_positions[i]);
      }
      contact::SearchOptions nearest;
      nearest.search = contact::GlobalSearchKind::kNearestNode;
      nearest.surface = surface;
      nearest.projection = generator.projection;
      out.deck_offset = std::max(out.deck_offset,
                                 contact::largest_relative_offset(contact::search_scene(corners, nearest)));
    }
    for (const auto& s : scene.master.segments) {
      dataset::SceneSegment segment;
      for (std::size_t i = 0; i < 4; ++i) {
        const auto node = static_cast<std::size_t>(s[i]);
        segment.nodes[i] = scene.master.positions[node];
        segment.normals[i] = scene.master_normals[node];
      }
      segments.push_back(segment);
    }
  }
  out.domain = options.domain;
  if (1.25 * out.deck_offset > out.domain.capture) {
    if (log) {
      char line[160];
      std::snprintf(line, sizeof line,
                    "capture %g -> %g of the shortest edge, to cover the deck's own slave nodes",
                    out.domain.capture, 1.25 * out.deck_offset);
      log(line);
    }
    out.domain.capture = 1.25 * out.deck_offset;
  }
  dataset::EnumerationSummary summary;
  out.train = dataset::sample_scene(segments, out.domain, generator, options.count, summary);
  out.heldout_seed = options.seed + options.heldout_seed_offset;
  generator.seed = out.heldout_seed;
  out.heldout =
      dataset::sample_scene(segments, out.domain, generator,
                            std::max<std::int64_t>(100, options.count / options.heldout_divisor), summary);
  out.heldout_set = eval::set_from_dataset(out.heldout, "heldout",
                                           "the scene's domain, seed " + std::to_string(out.heldout_seed),
                                           false, out.heldout_seed);
  return out;
}

// ------------------------------------------------------------------------------------------- 3. networks

std::vector<SceneNetwork> untrained_networks(const SceneDomain& domain, SurfaceKind surface,
                                             const SceneStudyOptions& options) {
  const TrainingData data = prepare_training(domain.train, options);
  std::vector<SceneNetwork> out;
  for (const int h : options.sizes) {
    SceneNetwork n;
    n.name = network_name(surface, h, options.second_layer) + "-untrained";
    n.hidden = h;
    n.domain = data.domain;
    auto network = std::make_shared<mlp::Network<float>>(fresh_network(surface, h, data, options));
    n.model = std::make_shared<search::NetworkModel>(*network, data.domain);
    n.network = std::move(network);
    out.push_back(std::move(n));
  }
  return out;
}

namespace {

/// Thread priorities of the training: a thread training what the study waits for runs at the process's own
/// nice value, one training ahead of time (a size that may turn out unneeded) kSpeculativeNice above it, so
/// that speculation takes only the cores nothing else wants (on a busy 2-core machine, the smallest Gregory
/// size took 14 s beside an unniced speculative one, 6 s alone). A thread must get its priority back when its
/// work becomes the one waited for, which Linux allows only with privilege or RLIMIT_NICE: where a throwaway
/// thread cannot, no thread changes its priority at all.
constexpr int kSpeculativeNice = 10;

class ThreadPriority {
 public:
  ThreadPriority() {
    errno = 0;
    const int nice = getpriority(PRIO_PROCESS, 0);
    if (errno != 0) return;
    base_ = nice;
    std::thread([&] {
      const auto tid = static_cast<id_t>(syscall(SYS_gettid));
      enabled_ = setpriority(PRIO_PROCESS, tid, std::min(base_ + kSpeculativeNice, 19)) == 0 &&
                 setpriority(PRIO_PROCESS, tid, base_) == 0;
    }).join();
  }
  /// Sets the calling thread's priority (once per change; nothing when disabled).
  void set(bool speculative) const {
    thread_local int current = std::numeric_limits<int>::min();
    const int nice = speculative ? std::min(base_ + kSpeculativeNice, 19) : base_;
    if (!enabled_ || nice == current) return;
    if (setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), nice) == 0) current = nice;
  }

 private:
  int base_ = 0;
  bool enabled_ = false;
};

/// Step 4's schedule (the header comment of train_networks): the sizes on a team of threads, one trainer
/// each.
class TrainingSchedule {
 public:
  TrainingSchedule(const SceneDomain& domain, SurfaceKind surface, const SceneStudyOptions& o,
                   const std::vector<int>& sizes, const StudyLog& log)
      : domain_(domain),
        surface_(surface),
        o_(o),
        log_(log),
        data_(prepare_training(domain.train, o)),
        long_round_(o.long_epochs > o.epochs) {
    mlp::TrainOptions t;
    t.mode = mlp::TrainingMode::kOnline;
    t.learning_rate = o.learning_rate;
    t.momentum = o.momentum;
    // The learning rate is constant, so a trainer set up for long_epochs runs its first `epochs` exactly as
    // one set up for `epochs`: the long round is the same training carried on.
    t.epochs = std::max(o.epochs, o.long_epochs);
    t.patience = 0;
    t.restore_best = true;
    t.seed = o.seed;
    t.threads = 1;
    for (const int h : sizes) {
      auto slot = std::make_unique<Slot>();
      slot->hidden = h;
      slot->network = std::make_unique<mlp::Network<float>>(fresh_network(surface, h, data_, o));
      slot->trainer = std::make_unique<mlp::Trainer<float>>(*slot->network, t, data_.train_x, data_.train_t,
                                                            data_.validation_x, data_.validation_t);
      slots_.push_back(std::move(slot));
    }
  }

  NetworkTraining run() {
    const auto start = Clock::now();
    const int team = std::max(1, std::min(team_size(o_), static_cast<int>(slots_.size())));
    std::vector<std::thread> threads;
    std::exception_ptr failure;
    std::mutex failure_mutex;
    for (int t = 0; t < team; ++t) {
      threads.emplace_back([&] {
        try {
          work();
        } catch (...) {
          const std::lock_guard<std::mutex> lock(failure_mutex);
          if (!failure) failure = std::current_exception();
          const std::lock_guard<std::mutex> state(mutex_);
          finished_ = true;
          changed_.notify_all();
        }
      });
    }
    for (std::thread& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
    return result(seconds_since(start));
  }

 private:
  struct Slot {
    int hidden = 0;
    std::unique_ptr<mlp::Network<float>> network;
    std::unique_ptr<mlp::Trainer<float>> trainer;
    bool taken = false;       // a thread is training it
    bool round_done = false;  // its `epochs` are done and judged
    bool cancelled = false;   // dropped: a smaller size reached the target first
    std::optional<SceneNetwork> round, long_round;
    double seconds = 0.0;
  };

  double target() const { return o_.margin * o_.target; }

  void say(const std::string& line) const {
    if (log_) log_(line);
  }

  bool round_complete() const {
    return std::all_of(slots_.begin(), slots_.end(),
                       [](const auto& s) { return s->round_done || s->cancelled; });
  }

  /// The size the study waits for: the smallest still in the first round (-1: the round is complete).
  int critical() const {
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      if (!slots_[i]->round_done && !slots_[i]->cancelled) return static_cast<int>(i);
    }
    return -1;
  }

  /// The finished size of the lowest held-out error (-1: none).
  int best_finished(bool free_only) const {
    int best = -1;
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      const Slot& s = *slots_[i];
      if (!s.round_done || (free_only && (s.taken || s.long_round))) continue;
      if (best < 0 ||
          s.round->heldout_error() < slots_[static_cast<std::size_t>(best)]->round->heldout_error()) {
        best = static_cast<int>(i);
      }
    }
    return best;
  }

  void work() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!finished_) {
      if (next_ < slots_.size()) {  // a size of the first round
        const std::size_t i = next_++;
        slots_[i]->taken = true;
        lock.unlock();
        first_round(i);
        lock.lock();
        continue;
      }
      if (round_complete()) {
        if (reached_ >= 0 || !long_round_) break;
        const auto b = static_cast<std::size_t>(best_finished(false));
        if (slots_[b]->long_round) break;  // carried on to the end ahead of time
        if (slots_[b]->taken) {            // its thread carries it on
          changed_.wait(lock);
          continue;
        }
        slots_[b]->taken = true;
        lock.unlock();
        carry_on(b);
        lock.lock();
        continue;
      }
      // The other threads are still in the first round: carry the best finished size on ahead of time.
      const int ahead = reached_ < 0 && long_round_ ? best_finished(true) : -1;
      if (ahead >= 0) {
        slots_[static_cast<std::size_t>(ahead)]->taken = true;
        lock.unlock();
        carry_on(static_cast<std::size_t>(ahead));
        lock.lock();
        continue;
      }
      changed_.wait(lock);
    }
    finished_ = true;
    changed_.notify_all();
  }

  /// The first `epochs` of size i, then its held-out error; stops early when a smaller size reaches the
  /// target.
  void first_round(std::size_t i) {
    Slot& s = *slots_[i];
    const auto start = Clock::now();
    while (s.trainer->state().epoch < o_.epochs) {
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (finished_ || (reached_ >= 0 && static_cast<std::size_t>(reached_) < i)) {
          s.cancelled = true;
          s.taken = false;
          changed_.notify_all();
          return;
        }
        priority_.set(critical() != static_cast<int>(i));
      }
      (void)s.trainer->train_epoch();
    }
    s.seconds += seconds_since(start);
    SceneNetwork n =
        snapshot(*s.network, s.trainer->state(), network_name(surface_, s.hidden, o_.second_layer), s.hidden,
                 data_, domain_.heldout_set, o_);
    n.seconds = s.seconds;
    const std::lock_guard<std::mutex> lock(mutex_);
    char line[200];
    std::snprintf(line, sizeof line,
                  "%s, %d epochs: held-out mean |error| %.5f / %.5f (target %g, margin %g), %.1f s",
                  n.name.c_str(), n.epochs, n.heldout_mean_abs[0], n.heldout_mean_abs[1], o_.target,
                  o_.margin, n.seconds);
    say(line);
    if (n.heldout_error() <= target() && (reached_ < 0 || static_cast<int>(i) < reached_))
      reached_ = static_cast<int>(i);
    s.round = std::move(n);
    s.round_done = true;
    s.taken = false;
    changed_.notify_all();
  }

  /// Size i trained on towards long_epochs; stops when it is no longer the best (or a size reached the
  /// target).
  void carry_on(std::size_t i) {
    Slot& s = *slots_[i];
    const auto start = Clock::now();
    while (s.trainer->state().epoch < o_.long_epochs) {
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        const bool overtaken = round_complete() && best_finished(false) != static_cast<int>(i);
        if (finished_ || reached_ >= 0 || overtaken) {
          s.seconds += seconds_since(start);
          s.taken = false;
          changed_.notify_all();
          return;
        }
        priority_.set(!round_complete());
      }
      (void)s.trainer->train_epoch();
    }
    s.seconds += seconds_since(start);
    SceneNetwork n =
        snapshot(*s.network, s.trainer->state(), network_name(surface_, s.hidden, o_.second_layer) + "-long",
                 s.hidden, data_, domain_.heldout_set, o_);
    n.seconds = s.seconds;
    const std::lock_guard<std::mutex> lock(mutex_);
    char line[200];
    std::snprintf(line, sizeof line, "%s, %d epochs: held-out mean |error| %.5f / %.5f, %.1f s in all",
                  n.name.c_str(), n.epochs, n.heldout_mean_abs[0], n.heldout_mean_abs[1], n.seconds);
    say(line);
    s.long_round = std::move(n);
    s.taken = false;
    changed_.notify_all();
  }

  NetworkTraining result(double seconds) {
    NetworkTraining out;
    out.seconds = seconds;
    int reached_index = -1, long_index = -1;
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      if (!slots_[i]->round) continue;
      if (static_cast<int>(i) == reached_) reached_index = static_cast<int>(out.tried.size());
      out.tried.push_back(*slots_[i]->round);
    }
    const int best = reached_ < 0 ? best_finished(false) : -1;
    if (best >= 0 && slots_[static_cast<std::size_t>(best)]->long_round) {
      long_index = static_cast<int>(out.tried.size());
      out.tried.push_back(*slots_[static_cast<std::size_t>(best)]->long_round);
    }
    if (out.tried.empty()) return out;
    if (reached_index >= 0) {
      out.scene = reached_index;
      out.reached = true;
    } else if (long_index >= 0 &&
               out.tried[static_cast<std::size_t>(long_index)].heldout_error() <= target()) {
      out.scene = long_index;
      out.reached = true;
    } else {
      out.scene = 0;
      for (std::size_t i = 1; i < out.tried.size(); ++i) {
        if (out.tried[i].heldout_error() < out.tried[static_cast<std::size_t>(out.scene)].heldout_error()) {
          out.scene = static_cast<int>(i);
        }
      }
    }
    return out;
  }

  const SceneDomain& domain_;
  SurfaceKind surface_;
  const SceneStudyOptions& o_;
  const StudyLog& log_;
  TrainingData data_;
  bool long_round_;
  std::vector<std::unique_ptr<Slot>> slots_;
  ThreadPriority priority_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::size_t next_ = 0;
  int reached_ = -1;  // the smallest size (slot index) that reached the target in the first round
  bool finished_ = false;
};

}  // namespace

NetworkTraining train_networks(const SceneDomain& domain, SurfaceKind surface,
                               const SceneStudyOptions& options, const std::vector<int>& sizes,
                               const StudyLog& log) {
  if (sizes.empty()) return {};
  TrainingSchedule schedule(domain, surface, options, sizes, log);
  return schedule.run();
}

// ---------------------------------------------------------------------------------------- 5. measurements

namespace {

struct ExpandedMethod {
  std::string name;
  search::Method method;
  int network = -1;
};

std::vector<ExpandedMethod> expand(const std::string& methods, const std::string& network_methods,
                                   const std::vector<const SceneNetwork*>& networks) {
  std::vector<ExpandedMethod> out;
  for (const std::string& m : split_methods(methods)) {
    const search::Method method = search::Method::parse(m);
    out.push_back({method.name(), method, -1});
  }
  for (std::size_t k = 0; k < networks.size(); ++k) {
    for (const std::string& m : split_methods(network_methods)) {
      const search::Method method = search::Method::parse(m);
      out.push_back({method.name() + "[" + networks[k]->name + "]", method, static_cast<int>(k)});
    }
  }
  return out;
}

search::LocalSearch search_of(SurfaceKind surface, const ExpandedMethod& m,
                              const std::vector<const SceneNetwork*>& networks) {
  return search::LocalSearch(
      surface, m.method, {},
      m.network >= 0 ? networks[static_cast<std::size_t>(m.network)]->model.get() : nullptr);
}

}  // namespace

std::vector<MethodMeasurement> measure_methods(const eval::EvaluationSet& set, SurfaceKind surface,
                                               const std::string& methods, const std::string& network_methods,
                                               const std::vector<const SceneNetwork*>& networks,
                                               const SceneStudyOptions& options) {
  const std::vector<ExpandedMethod> expanded = expand(methods, network_methods, networks);
  std::vector<search::LocalSearch> searches;
  std::vector<MethodMeasurement> out;
  const int threads = options.threads;
  for (const ExpandedMethod& m : expanded) {
    searches.push_back(search_of(surface, m, networks));
    MethodMeasurement r;
    r.name = m.name;
    r.method = m.method.name();
    r.network = m.network;
    const eval::Estimates e = eval::run_on_set(searches.back(), set, threads);
    r.errors = eval::compare_with_labels(m.name, e, set, options.failure_box_margin, false);
    std::vector<std::int32_t>().swap(r.errors.converged_iterations);
    r.effective_mean = eval::effective_mean_error(r.errors, surface);
    r.reaches = r.effective_mean <= options.margin * options.target;
    out.push_back(std::move(r));
  }
  // Speed: every method on the same queries (the set's rows with a reference point, cycled up to at least
  // 4096 per pass), batched, 1 thread, round-robin (eval::time_methods).
  std::vector<std::size_t> rows;
  for (std::size_t r = 0;
       r < set.label_status.size() && static_cast<std::int64_t>(rows.size()) < options.timing_queries; ++r) {
    if (set.label_status[r] == Status::kOk || set.label_status[r] == Status::kOutside) rows.push_back(r);
  }
  CONTACTNN_REQUIRE_AS(FormatError, !rows.empty(),
                       "'" << set.source << "' has no row with a reference point to time on");
  const std::size_t distinct = rows.size();
  for (std::size_t i = 0; rows.size() < 4096; ++i) rows.push_back(rows[i % distinct]);
  const auto cols = static_cast<std::size_t>(eval::EvaluationSet::raw_columns(surface));
  std::vector<double> raw;
  raw.reserve(rows.size() * cols);
  for (const std::size_t r : rows) {
    raw.insert(raw.end(), set.raw.begin() + static_cast<std::ptrdiff_t>(r * cols),
               set.raw.begin() + static_cast<std::ptrdiff_t>((r + 1) * cols));
  }
  const std::size_t n = rows.size();
  std::vector<std::vector<double>> param(searches.size(), std::vector<double>(2 * n));
  std::vector<std::vector<Status>> status(searches.size(), std::vector<Status>(n));
  std::vector<eval::TimedMethod> timed;
  for (std::size_t m = 0; m < searches.size(); ++m) {
    timed.push_back({out[m].name, "", static_cast<std::int64_t>(n), [&, m] {
                       searches[m].run(
                           n, raw.data(),
                           search::Results<double>{param[m].data(), nullptr, status[m].data(), nullptr}, 1);
                       double sum = 0.0;
                       for (std::size_t i = 0; i < n; ++i) sum += param[m][2 * i] + 0.5 * param[m][2 * i + 1];
                       return sum;
                     }});
  }
  const std::vector<eval::Timing> timings = eval::time_methods(timed, options.timing);
  // The fastest pass: another process can only slow a pass down (on a busy machine a preempted pass of a fast
  // method read 6 times its time, and the median of 7 passes did not hide it).
  for (std::size_t m = 0; m < out.size(); ++m) out[m].batched_ns = timings[m].min_ns;
  return out;
}

std::vector<int> sizes_that_may_pay(const std::vector<MethodMeasurement>& measured,
                                    const std::vector<SceneNetwork>& untrained,
                                    const SceneStudyOptions& options, std::vector<std::string>* why) {
  if (options.train_networks == TrainNetworks::kNever) {
    if (why) why->push_back("no scene network trained (train_networks = never)");
    return {};
  }
  if (options.train_networks == TrainNetworks::kAlways) return options.sizes;
  const MethodMeasurement* fastest = nullptr;
  for (const MethodMeasurement& m : measured) {
    if (m.network < 0 && m.reaches && (fastest == nullptr || m.batched_ns < fastest->batched_ns))
      fastest = &m;
  }
  std::vector<int> sizes;
  for (const SceneNetwork& n : untrained) {
    const auto it = std::find_if(measured.begin(), measured.end(), [&](const MethodMeasurement& m) {
      return m.name == "network[" + n.name + "]";
    });
    CONTACTNN_REQUIRE(it != measured.end(), "no timing of the untrained network " << n.name);
    if (fastest == nullptr || it->batched_ns < fastest->batched_ns) {
      sizes.push_back(n.hidden);
    } else if (why) {
      char line[240];
      std::snprintf(line, sizeof line,
                    "%s not trained: the network alone takes %.1f ns/query, %s reaches the target in %.1f ns",
                    n.name.substr(0, n.name.size() - std::string("-untrained").size()).c_str(),
                    it->batched_ns, fastest->name.c_str(), fastest->batched_ns);
      why->push_back(line);
    }
  }
  return sizes;
}

std::size_t choose_plan(const std::vector<MethodMeasurement>& measured) {
  CONTACTNN_REQUIRE(!measured.empty(), "no method measured: nothing to choose from");
  std::size_t best = 0;
  bool any = false;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    if (!measured[i].reaches) continue;
    if (!any || measured[i].batched_ns < measured[best].batched_ns) best = i;
    any = true;
  }
  if (any) return best;
  for (std::size_t i = 1; i < measured.size(); ++i) {
    const MethodMeasurement &a = measured[i], &b = measured[best];
    if (a.effective_mean < b.effective_mean ||
        (a.effective_mean == b.effective_mean && a.batched_ns < b.batched_ns))
      best = i;
  }
  return best;
}

// ---------------------------------------------------------------------------------------- 6. node orders

namespace {

/// Where node i of the identity order goes in the order (rotation, mirror) (scripts/node-orders' convention).
int caller_node(int rotation, bool mirror, int i) { return ((mirror ? (4 - i) % 4 : i) + rotation) % 4; }

/// The identity order's local coordinates as the order (rotation, mirror) reports them (SPEC 4).
std::array<double, 2> to_caller(int rotation, bool mirror, std::array<double, 2> p, double centre) {
  double x = p[0] - centre, y = p[1] - centre;
  if (mirror) std::swap(x, y);
  for (int r = 0; r < rotation; ++r) {
    const double t = x;
    x = -y;
    y = t;
  }
  return {x + centre, y + centre};
}

bool has_point(Status s) { return s == Status::kOk || s == Status::kOutside || s == Status::kOutOfDomain; }

}  // namespace

std::string NodeOrderCheck::summary() const {
  char line[300];
  if (scene_network >= 0.0) {
    std::snprintf(
        line, sizeof line,
        "node orders: %ld pairs x 8 orders; largest difference: labels %.3g (gap %.3g), plan's method %.3g, "
        "scene network %.3g: %s",
        pairs, label, label_gap, plan_method, scene_network, passed ? "passed" : "FAILED");
  } else {
    std::snprintf(line, sizeof line,
                  "node orders: %ld pairs x 8 orders; largest difference: labels %.3g (gap %.3g), plan's "
                  "method %.3g: %s",
                  pairs, label, label_gap, plan_method, passed ? "passed" : "FAILED");
  }
  return line;
}

NodeOrderCheck check_node_orders(const ScenePairs& pairs, SurfaceKind surface,
                                 const search::LocalSearch& plan, const search::LocalSearch* scene) {
  constexpr double kLabelTolerance = 1e-12;  // SPEC 4: the same canonical configuration in every order
  constexpr double kMethodTolerance =
      1e-6;  // float networks: the same canonical input, rounding of the map back
  NodeOrderCheck check;
  const eval::EvaluationSet& set = pairs.quad4_pairs;
  const auto n = static_cast<std::size_t>(set.rows());
  check.pairs = static_cast<long>(n);
  if (scene != nullptr) check.scene_network = 0.0;
  if (n == 0) return check;
  const auto cols = static_cast<std::size_t>(eval::EvaluationSet::raw_columns(surface));
  const double centre = surface == SurfaceKind::kGregory ? 0.5 : 0.0;
  const bool gregory = surface == SurfaceKind::kGregory;
  struct Answers {
    std::vector<dataset::Label> labels;
    std::vector<double> plan_param, scene_param;
    std::vector<Status> plan_status, scene_status;
  };
  const auto answers_in = [&](int rotation, bool mirror) {
    Answers a;
    std::vector<double> raw(n * cols);
    for (std::size_t r = 0; r < n; ++r) {
      const double* in = set.raw.data() + r * cols;
      double* out = raw.data() + r * cols;
      for (int i = 0; i < 4; ++i) {
        const int k = caller_node(rotation, mirror, i);
        for (int x = 0; x < 3; ++x) {
          out[3 * k + x] = in[3 * i + x];
          if (gregory) out[15 + 3 * k + x] = in[15 + 3 * i + x];
        }
      }
      for (int x = 12; x < 15; ++x) out[x] = in[x];
      geometry::Configuration c{};
      for (int i = 0; i < 4; ++i) {
        c.nodes[static_cast<std::size_t>(i)] = geometry::Vec3(out[3 * i], out[3 * i + 1], out[3 * i + 2]);
        if (gregory)
          c.normals[static_cast<std::size_t>(i)] =
              geometry::Vec3(out[15 + 3 * i], out[16 + 3 * i], out[17 + 3 * i]);
      }
      c.slave = geometry::Vec3(out[12], out[13], out[14]);
      a.labels.push_back(dataset::label_configuration(c, surface));
    }
    const auto run = [&](const search::LocalSearch& s, std::vector<double>& param,
                         std::vector<Status>& status) {
      param.assign(2 * n, 0.0);
      status.assign(n, Status::kInvalid);
      s.run(n, raw.data(), search::Results<double>{param.data(), nullptr, status.data(), nullptr});
    };
    run(plan, a.plan_param, a.plan_status);
    if (scene != nullptr) run(*scene, a.scene_param, a.scene_status);
    return a;
  };
  const Answers identity = answers_in(0, false);
  for (const bool mirror : {false, true}) {
    for (int rotation = 0; rotation < 4; ++rotation) {
      const Answers a = rotation == 0 && !mirror ? identity : answers_in(rotation, mirror);
      const double sign = mirror ? -1.0 : 1.0;
      for (std::size_t r = 0; r < n; ++r) {
        const dataset::Label &base = identity.labels[r], &l = a.labels[r];
        if (base.status != l.status) {
          check.passed = false;
          continue;
        }
        if (base.status == Status::kOk || base.status == Status::kOutside) {
          const auto want = to_caller(rotation, mirror, base.param, centre);
          check.label =
              std::max({check.label, std::abs(l.param[0] - want[0]), std::abs(l.param[1] - want[1])});
          check.label_gap = std::max(check.label_gap, std::abs(l.gap - sign * base.gap));
        }
        const auto compare = [&](const std::vector<double>& p0, const std::vector<Status>& s0,
                                 const std::vector<double>& p, const std::vector<Status>& s, double& worst) {
          if (s0[r] != s[r]) {
            check.passed = false;
            return;
          }
          if (!has_point(s0[r])) return;
          const auto want = to_caller(rotation, mirror, {p0[2 * r], p0[2 * r + 1]}, centre);
          worst = std::max({worst, std::abs(p[2 * r] - want[0]), std::abs(p[2 * r + 1] - want[1])});
        };
        compare(identity.plan_param, identity.plan_status, a.plan_param, a.plan_status, check.plan_method);
        if (scene != nullptr) {
          compare(identity.scene_param, identity.scene_status, a.scene_param, a.scene_status,
                  check.scene_network);
        }
      }
    }
  }
  check.passed = check.passed && check.label <= kLabelTolerance && check.plan_method <= kMethodTolerance &&
                 check.scene_network <= kMethodTolerance;
  return check;
}

// --------------------------------------------------------------------------------------------- 7. report

void judge_on_pairs(const ScenePairs& pairs, SurfaceKind surface,
                    const std::vector<const SceneNetwork*>& networks, SceneStudyResult& result) {
  result.face_errors.clear();
  result.quad4_errors.clear();
  for (const MethodMeasurement& m : result.measured) {
    const ExpandedMethod e{m.name, search::Method::parse(m.method), m.network};
    const search::LocalSearch search = search_of(surface, e, networks);
    for (const auto& [set, errors] :
         {std::pair{&pairs.face, &result.face_errors}, std::pair{&pairs.quad4_pairs, &result.quad4_errors}}) {
      eval::MethodErrors me =
          eval::compare_with_labels(m.name, eval::run_on_set(search, *set, result.options.threads), *set,
                                    result.options.failure_box_margin, false);
      std::vector<std::int32_t>().swap(me.converged_iterations);
      errors->push_back(std::move(me));
    }
  }
}

bool SceneStudyResult::plan_meets_target_on_pairs() const {
  if (face_errors.empty() || face_errors[chosen].rows == 0) return true;
  const eval::MethodErrors& e = face_errors[chosen];
  return e.failures_method == 0 && std::max(e.stats[0].mean_abs, e.stats[1].mean_abs) <= options.target;
}

ScenePlan make_plan(const SceneStudyResult& r, const std::string& network_file) {
  ScenePlan plan;
  plan.surface = r.surface;
  plan.method = r.plan().method;
  plan.network = network_file;
  plan.target = r.options.target;
  plan.margin = r.options.margin;
  plan.reached = r.plan().reaches;
  plan.domain.deck = r.deck;
  plan.domain.pair = r.pair;
  plan.domain.deformation = r.domain.deformation;
  plan.domain.capture = r.domain.capture;
  plan.domain.normal_tilt_tangent = r.domain.normal_tilt_tangent;
  plan.domain.boundary_fraction = r.domain.boundary_fraction;
  plan.domain.heldout_count = r.heldout_rows;
  plan.domain.heldout_seed = static_cast<std::int64_t>(r.heldout_seed);
  plan.domain.segment_test = r.domain.segment_test;
  plan.domain.states = r.options.domain_states == DomainStates::kHistory ? "history" : "rest";
  plan.domain.results = r.results;
  for (const MethodMeasurement& m : r.measured) {
    PlanMeasurement p;
    p.method = m.name;
    p.mean_abs[0] = m.errors.stats[0].mean_abs;
    p.mean_abs[1] = m.errors.stats[1].mean_abs;
    p.effective_mean = m.effective_mean;
    p.max_abs = std::max(m.errors.stats[0].max_abs, m.errors.stats[1].max_abs);
    p.failures = m.errors.failures_method;
    p.batched_ns = m.batched_ns;
    p.reaches_target = m.reaches;
    plan.measurements.push_back(std::move(p));
  }
  return plan;
}

namespace {

std::string g4(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

double worse_mean(const eval::MethodErrors& e) { return std::max(e.stats[0].mean_abs, e.stats[1].mean_abs); }

}  // namespace

std::string report_markdown(const SceneStudyResult& r) {
  const auto names = coordinate_names(r.surface);
  const SceneStudyOptions& o = r.options;
  const MethodMeasurement& plan = r.plan();
  const bool any_face = !r.face_errors.empty() && r.face_errors.front().rows > 0;
  std::ostringstream md;
  md << "# scene-study: `" << std::filesystem::path(r.deck).filename().string() << "` pair " << r.pair << ", "
     << to_string(r.surface) << "\n\n";
  md << "- command: `" << r.command_line << "`\n";
  md << "- **plan: `" << plan.method << "`";
  if (plan.network >= 0) {
    md << " with the network " << r.training.tried[static_cast<std::size_t>(plan.network)].name
       << "** (`network.h5`)";
  } else {
    md << "** (no network)";
  }
  md << ": " << (plan.reaches ? "the fastest" : "none reached the target; the most accurate") << " of the "
     << r.measured.size() << " methods measured on a held-out sample of the scene's domain ("
     << r.heldout_rows << " configurations), "
     << (plan.reaches ? "among those whose effective mean |error| is at most " + g4(o.margin) +
                            " x the target " + g4(o.target)
                      : std::string("target ") + g4(o.target))
     << ": held-out " << g4(plan.effective_mean) << ", " << g4(plan.batched_ns)
     << " ns/query batched on 1 thread. Written to `plan.toml`.\n";
  md << "- the deck's pairs: " << r.slave_nodes << " slave nodes; the closest point lies inside a face for "
     << r.locations[0] << ", on an edge for " << r.locations[1] << ", at a vertex for " << r.locations[2]
     << "; " << r.no_segment << " without a face (no_segment). " << r.quad4
     << " lie on 4-node quadrilaterals (the "
     << "local search's segments, SPEC 7), " << (any_face ? r.face_errors.front().rows : 0)
     << " of them inside the face. Edge and vertex answers are the surface search's own and need no local "
        "search: "
        "the methods are judged on the pairs inside a 4-node quadrilateral.\n";
  if (any_face) {
    const eval::MethodErrors& e = r.face_errors[r.chosen];
    md << "- on those " << e.rows << " pairs the plan's method errs " << g4(e.stats[0].mean_abs) << " / "
       << g4(e.stats[1].mean_abs) << " (mean |error| " << names[0] << " / " << names[1] << ", "
       << e.failures_method << " failures): target " << g4(o.target) << " "
       << (r.plan_meets_target_on_pairs() ? "met" : "**not met**") << "\n";
  } else {
    md << "- no pair of the deck lies inside a 4-node quadrilateral: the plan rests on the scene's domain "
          "alone\n";
  }
  md << "- the scene's domain: its "
     << "master segments deformed by " << g4(r.domain.deformation)
     << " of the shortest edge, the slave within " << g4(r.domain.capture)
     << " of it along the normal (the deck's own offsets reach " << g4(r.deck_offset)
     << (o.capture_pairs == "surface" ? ", on its surface-search pairs on quadrilaterals"
                                      : ", on its nearest-node pairs")
     << ")";
  md << "; drawn from "
     << (o.domain_states == DomainStates::kHistory
             ? "the whole history: the deck and its " + std::to_string(r.history_increments) +
                   " increments of `" + r.results + "`"
             : std::string("the deck's own state"));
  if (r.surface == SurfaceKind::kGregory)
    md << ", node normals tilted by up to " << g4(r.domain.normal_tilt_tangent);
  md << ", " << g4(r.domain.boundary_fraction) << " of the foot points on the boundary; " << o.count
     << " configurations to train from (seed " << o.seed << "), " << r.heldout_rows << " held out (seed "
     << r.heldout_seed << ")\n";
  if (!r.training.tried.empty()) {
    md << "- scene networks (" << o.input_features << " inputs, online back-propagation, learning rate "
       << g4(o.learning_rate) << "): ";
    for (std::size_t i = 0; i < r.training.tried.size(); ++i) {
      const SceneNetwork& n = r.training.tried[i];
      md << (i ? ", " : "") << n.name << " with " << n.epochs << " epochs (held-out " << g4(n.heldout_error())
         << ", " << g4(n.seconds) << " s)";
    }
    const SceneNetwork& scene = r.training.tried[static_cast<std::size_t>(r.training.scene)];
    md << "; the scene network is **" << scene.name << "**, "
       << (r.training.reached ? "the first within " + g4(o.margin) + " x the target"
                              : "the best (none came within " + g4(o.margin) + " x the target)")
       << "; " << g4(r.training.seconds) << " s of training\n";
  }
  for (const std::string& why : r.not_trained) md << "- " << why << "\n";
  md << "- " << r.node_orders.summary() << "\n";
  md << "- time: to the plan " << g4(r.seconds_to_plan) << " s, whole study " << g4(r.seconds) << " s\n\n";
  md << "Every method measured: held-out effective mean |error| (the larger coordinate's mean |error|, each "
        "failure "
        "counting as one domain width; "
     << names[0] << " units, domain width " << (r.surface == SurfaceKind::kGregory ? "1" : "2")
     << ") and time per query (batched, 1 thread, this machine) on the scene's domain, where the plan is "
        "chosen; "
        "then the mean |error| on the deck's pairs inside a face, and on every pair on a quadrilateral "
        "(edges and "
        "vertices included). The plan's row is in bold.\n\n";
  md << "| method | held-out effective mean | reaches " << g4(o.margin) << " x " << g4(o.target)
     << " | ns/query batched | face pairs mean abs " << names[0] << " | mean abs " << names[1]
     << " | max abs | failures | quad4 pairs mean abs |\n|---|---:|:---:|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t i = 0; i < r.measured.size(); ++i) {
    const MethodMeasurement& m = r.measured[i];
    const std::string name = i == r.chosen ? "**" + m.name + "**" : m.name;
    md << "| " << name << " | " << g4(m.effective_mean) << " | " << (m.reaches ? "yes" : "no") << " | "
       << g4(m.batched_ns) << " | ";
    if (any_face) {
      const eval::MethodErrors& e = r.face_errors[i];
      md << g4(e.stats[0].mean_abs) << " | " << g4(e.stats[1].mean_abs) << " | "
         << g4(std::max(e.stats[0].max_abs, e.stats[1].max_abs)) << " | " << e.failures_method << " | ";
    } else {
      md << "- | - | - | - | ";
    }
    md << (r.quad4_errors.empty() || r.quad4_errors[i].rows == 0 ? std::string("-")
                                                                 : g4(worse_mean(r.quad4_errors[i])))
       << " |\n";
  }
  if (!r.history_markdown.empty()) md << "\n" << r.history_markdown;
  return md.str();
}

std::string report_json(const SceneStudyResult& r) {
  const SceneStudyOptions& o = r.options;
  const bool any_face = !r.face_errors.empty() && r.face_errors.front().rows > 0;
  const SceneNetwork* scene =
      r.training.scene >= 0 ? &r.training.tried[static_cast<std::size_t>(r.training.scene)] : nullptr;
  const auto find = [&](const std::string& name) -> int {
    for (std::size_t i = 0; i < r.measured.size(); ++i) {
      if (r.measured[i].name == name) return static_cast<int>(i);
    }
    return -1;
  };
  const int scene_row = scene != nullptr ? find("network[" + scene->name + "]") : -1;
  const auto pair_means = [&](int i) {
    if (i < 0 || !any_face) return std::string("null");
    const eval::MethodErrors& e = r.face_errors[static_cast<std::size_t>(i)];
    return "[" + json_number(e.stats[0].mean_abs) + ", " + json_number(e.stats[1].mean_abs) + "]";
  };
  std::ostringstream j;
  j << "{\n  \"deck\": " << json_string(r.deck) << ",\n  \"pair\": " << r.pair
    << ",\n  \"surface\": " << json_string(std::string(to_string(r.surface)))
    << ",\n  \"target\": " << json_number(o.target) << ",\n  \"margin\": " << json_number(o.margin)
    << ",\n  \"count\": " << o.count << ",\n  \"seed\": " << o.seed << ",\n  \"epochs\": " << o.epochs
    << ",\n  \"long_epochs\": " << o.long_epochs << ",\n  \"second_layer\": " << o.second_layer
    << ",\n  \"input_features\": " << json_string(o.input_features)
    << ",\n  \"train_networks\": " << json_string(std::string(to_string(o.train_networks)))
    << ",\n  \"domain\": " << json_string(std::string(to_string(o.domain_states)))
    << ",\n  \"capture_pairs\": " << json_string(o.capture_pairs) << ",\n  \"sizes_tried\": [";
  for (std::size_t i = 0; i < r.training.tried.size(); ++i) {
    const SceneNetwork& n = r.training.tried[i];
    j << (i ? ", " : "") << "{\"hidden\": " << n.hidden << ", \"epochs\": " << n.epochs
      << ", \"name\": " << json_string(n.name) << ", \"heldout_mean_abs\": ["
      << json_number(n.heldout_mean_abs[0]) << ", " << json_number(n.heldout_mean_abs[1])
      << "], \"train_seconds\": " << json_number(n.seconds) << "}";
  }
  j << "],\n  \"network\": "
    << (scene ? json_string(network_name(r.surface, scene->hidden, r.options.second_layer)) : "null")
    << ",\n  \"chosen_hidden\": " << (scene ? std::to_string(scene->hidden) : "null")
    << ",\n  \"chosen_epochs\": " << (scene ? std::to_string(scene->epochs) : "null")
    << ",\n  \"network_reached\": " << (r.training.reached ? "true" : "false")
    << ",\n  \"scene_mean_abs\": " << pair_means(scene_row) << ",\n  \"meets_target\": "
    << (scene_row >= 0 && any_face &&
                worse_mean(r.face_errors[static_cast<std::size_t>(scene_row)]) <= o.target
            ? "true"
            : "false")
    << ",\n  \"pairs\": " << (any_face ? r.face_errors.front().rows : 0)
    << ",\n  \"quad4_pairs\": " << r.quad4 << ",\n  \"locations\": {\"face\": " << r.locations[0]
    << ", \"edge\": " << r.locations[1] << ", \"vertex\": " << r.locations[2] << "}"
    << ",\n  \"node_orders\": " << json_string(r.node_orders.summary())
    << ",\n  \"node_orders_passed\": " << (r.node_orders.passed ? "true" : "false")
    << ",\n  \"seconds_to_plan\": " << json_number(r.seconds_to_plan)
    << ",\n  \"seconds\": " << json_number(r.seconds)
    << ",\n  \"plan\": {\"method\": " << json_string(r.plan().method)
    << ", \"name\": " << json_string(r.plan().name)
    << ", \"reaches\": " << (r.plan().reaches ? "true" : "false")
    << ", \"heldout_effective_mean\": " << json_number(r.plan().effective_mean)
    << ", \"batched_ns\": " << json_number(r.plan().batched_ns)
    << ", \"pairs_mean_abs\": " << pair_means(static_cast<int>(r.chosen))
    << ", \"meets_target_on_pairs\": " << (r.plan_meets_target_on_pairs() ? "true" : "false")
    << "},\n  \"methods\": [";
  for (std::size_t i = 0; i < r.measured.size(); ++i) {
    const MethodMeasurement& m = r.measured[i];
    j << (i ? "," : "") << "\n    {\"method\": " << json_string(m.name)
      << ", \"heldout_effective_mean\": " << json_number(m.effective_mean)
      << ", \"batched_ns\": " << json_number(m.batched_ns)
      << ", \"reaches\": " << (m.reaches ? "true" : "false")
      << ", \"mean_abs\": " << pair_means(static_cast<int>(i)) << ", \"quad4_mean_abs\": "
      << (r.quad4_errors.empty() || r.quad4_errors[i].rows == 0
              ? std::string("null")
              : "[" + json_number(r.quad4_errors[i].stats[0].mean_abs) + ", " +
                    json_number(r.quad4_errors[i].stats[1].mean_abs) + "]")
      << "}";
  }
  j << "\n  ]";
  if (!r.history_json.empty()) j << ",\n  \"history\": " << r.history_json;
  j << "\n}\n";
  return j.str();
}

}  // namespace contactnn::study
