// Steps 3 and 4 of the scene study (scene_study.hpp): the scene networks, untrained (to time them before any
// training) and trained in memory by train_networks' schedule (training_schedule.cpp): the sizes in
// increasing order on a team of threads, the first within margin x target kept, the best carried on to
// long_epochs when none is. Every network is bit for bit the one train-net makes from the same sample and
// settings.
#pragma once

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "geometry/domain.hpp"
#include "mlp/network.hpp"
#include "search/network_model.hpp"
#include "study/scene_domain.hpp"
#include "study/scene_study.hpp"

namespace contactnn::study {

/// A scene network: trained, or (weights untrained) for timing only.
struct SceneNetwork {
  std::string name;  ///< "16-32-2", "16-32-2-long" (trained on to long_epochs)
  int hidden = 0;
  int epochs = 0;      ///< epochs run (the kept parameters may be an earlier epoch's)
  int best_epoch = 0;  ///< epoch of the kept parameters (best validation loss)
  std::shared_ptr<const mlp::Network<float>> network;
  geometry::TrainingDomain domain;
  std::shared_ptr<const search::NetworkModel> model;
  double heldout_mean_abs[2] = {0.0, 0.0};  ///< the network alone on the held-out sample
  double seconds = 0.0;                     ///< training time (wall, on its own thread)
  double validation_loss = 0.0;
  [[nodiscard]] double heldout_error() const { return std::max(heldout_mean_abs[0], heldout_mean_abs[1]); }
};

/// The networks of every size with untrained weights (initialised from the seed): their cost is a trained
/// network's, so step 3 can time them before any training.
[[nodiscard]] std::vector<SceneNetwork> untrained_networks(const SceneDomain& domain, SurfaceKind surface,
                                                           const SceneStudyOptions& options);

struct NetworkTraining {
  std::vector<SceneNetwork> tried;  ///< in the order they finished: each size, then the long round's
  int scene = -1;                   ///< index in `tried` of the scene network (-1: none trained)
  bool reached = false;             ///< the scene network is within margin x target on the held-out sample
  double seconds = 0.0;             ///< wall time of the whole step
};

/// Step 4 for `sizes` (a subset of options.sizes, in increasing order; empty: nothing is trained).
[[nodiscard]] NetworkTraining train_networks(const SceneDomain& domain, SurfaceKind surface,
                                             const SceneStudyOptions& options, const std::vector<int>& sizes,
                                             const StudyLog& log = {});

}  // namespace contactnn::study
