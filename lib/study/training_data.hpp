// The scene networks' training data and the making of one network (internal to lib/study: the untrained
// networks of step 3 and the training schedule of step 4 share them). train-net's steps 3 and 4.
#pragma once

#include <array>
#include <string>

#include "dataset/labelled_set.hpp"
#include "eval/evaluation_set.hpp"
#include "mlp/network.hpp"
#include "mlp/scaling.hpp"
#include "mlp/trainer.hpp"
#include "search/network_model.hpp"
#include "study/scene_networks.hpp"

namespace contactnn::study::detail {

/// The training data every size shares: the pattern draw, the scaling (from the training inputs alone, so
/// the same for every size), the scaled patterns and the training domain. train-net's steps 3 and 4.
struct TrainingData {
  mlp::Scaling scaling;
  geometry::TrainingDomain domain;
  mlp::MatrixRM<float> train_x, train_t, validation_x, validation_t;
};

/// The pattern draw, the scaling and the scaled patterns of `set` (options' fractions, seed and input map).
[[nodiscard]] TrainingData prepare_training(const dataset::LabelledSet& set, const SceneStudyOptions& o);

/// A network of `hidden` units (and options' second layer) with fresh weights from the seed.
[[nodiscard]] mlp::Network<float> fresh_network(SurfaceKind surface, int hidden, const TrainingData& data,
                                                const SceneStudyOptions& o);

/// A snapshot of a training: the parameters of its best validation epoch (restore_best), made ready for
/// lib/search, with its held-out error.
[[nodiscard]] SceneNetwork snapshot(const mlp::Network<float>& network,
                                    const mlp::TrainingState<float>& state, std::string name, int hidden,
                                    const TrainingData& data, const eval::EvaluationSet& heldout,
                                    const SceneStudyOptions& o);

}  // namespace contactnn::study::detail
