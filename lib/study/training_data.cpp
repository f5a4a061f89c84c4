#include "study/training_data.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/input_features.hpp"
#include "eval/accuracy.hpp"
#include "mlp/pattern_selection.hpp"
#include "mlp/random.hpp"
#include "search/local_search.hpp"
#include "search/method.hpp"
#include "study/study_detail.hpp"

namespace contactnn::study {

namespace detail {

namespace {

/// The network alone on `set`: mean |error| of each coordinate (1 thread: called from a training thread).
std::array<double, 2> heldout_errors(const search::NetworkModel& model, const eval::EvaluationSet& set,
                                     const SceneStudyOptions& o) {
  const search::LocalSearch search(set.surface, search::Method::parse("network"), {}, &model);
  const eval::Estimates e = eval::run_on_set(search, set, 1);
  const eval::MethodErrors m = eval::compare_with_labels("network", e, set, o.failure_box_margin, false);
  return {m.stats[0].mean_abs, m.stats[1].mean_abs};
}

}  // namespace

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

}  // namespace detail

using detail::fresh_network;
using detail::network_name;
using detail::prepare_training;
using detail::TrainingData;

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

}  // namespace contactnn::study
