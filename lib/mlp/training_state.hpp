// A training run's state (mlp::Trainer's checkpoint): a plain struct, apart from the trainer so that the
// network file code (io/network_file.hpp), which reads and writes checkpoints, needs no trainer code.
#pragma once

#include <limits>

#include "mlp/network.hpp"
#include "mlp/random.hpp"

namespace contactnn::mlp {

/// Everything that determines the rest of a run besides the network's parameters and the data: a run
/// restored from it continues bit-identically to one that was never interrupted.
template <class Real>
struct TrainingState {
  int epoch = 0;                 ///< completed epochs
  Rng::State rng{};              ///< shuffle generator
  AlignedVector<Real> velocity;  ///< last update dw per parameter (the momentum term)
  double best_validation_loss = std::numeric_limits<double>::infinity();
  int best_epoch = 0;                   ///< epoch of best_validation_loss (0: none yet)
  AlignedVector<Real> best_parameters;  ///< parameters after best_epoch
  double training_loss = std::numeric_limits<double>::quiet_NaN();    ///< last epoch's mean E_p
  double validation_loss = std::numeric_limits<double>::quiet_NaN();  ///< after the last epoch
};

}  // namespace contactnn::mlp
