// Back-propagation with momentum (paper Section 3): the online mode of the paper and a batch mode built on
// the fused batch kernel, with validation-based early stopping and a state that checkpoints exactly.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string_view>
#include <vector>

#include "mlp/batch_gradient.hpp"
#include "mlp/network.hpp"
#include "mlp/online_backprop.hpp"
#include "mlp/random.hpp"
#include "mlp/training_state.hpp"

namespace contactnn::mlp {

/// online: one update per pattern, patterns shuffled every epoch (the paper's ordinary BP).
/// batch:  one update per mini-batch of batch_size patterns (shuffled every epoch), or per epoch when
///         batch_size is 0 or >= the training set (full batch, no shuffle).
enum class TrainingMode { kOnline, kBatch };
[[nodiscard]] std::string_view to_string(TrainingMode mode);
/// "online" or "batch"; InvalidArgument naming both otherwise.
[[nodiscard]] TrainingMode training_mode_from_string(std::string_view name);

/// Every update is  dw = momentum * dw - learning_rate * g;  w += dw,  with g the gradient of E_p (Eq 14)
/// in online mode and the mean of the batch's dE_p/dw in batch mode, so one learning rate means the same
/// step size per pattern in both modes and batch_size 1 is online mode.
struct TrainOptions {
  TrainingMode mode = TrainingMode::kOnline;
  std::size_t batch_size = 0;  ///< batch mode: patterns per update; 0 = all (full batch)
  double learning_rate = 0.1;  ///< eta, > 0 (of the first epoch)
  /// eta of the last epoch; eta decays geometrically from learning_rate to this over the epochs (a constant
  /// step leaves SGD at the noise floor its step sets; decaying it lets the last epochs settle). 0 =
  /// constant.
  double learning_rate_final = 0.0;
  double momentum = 0.9;     ///< alpha, in [0, 1)
  int epochs = 10000;        ///< maximum epochs (passes over the training set), >= 1
  int patience = 0;          ///< stop after this many epochs without a new best validation error; 0 = never
  bool restore_best = true;  ///< with a validation set, end on the parameters of the best validation error
  std::uint64_t seed = 1;    ///< seeds the per-epoch shuffles
  int threads = 0;           ///< OpenMP threads for batch mode and validation; 0 = OpenMP's default
};

/// One epoch's outcome. Losses are mean E_p (Eq 14) per pattern in the scaled (sigmoid) units: the training
/// loss accumulated during the epoch (before each update), the validation loss after it (NaN without a
/// validation set).
struct EpochReport {
  int epoch = 0;
  double training_loss = 0.0;
  double validation_loss = 0.0;
  bool improved = false;  ///< a new best validation loss
};

template <class Real>
class Trainer {
 public:
  /// Inputs and targets are already scaled (Network::scaling()): N x n_0 and N x n_L, N >= 1; the
  /// validation set may have 0 rows. The trainer keeps references: they must outlive it. Throws
  /// InvalidArgument for bad options or shapes. Allocates every buffer here.
  Trainer(Network<Real>& network, const TrainOptions& options, const MatrixRM<Real>& train_inputs,
          const MatrixRM<Real>& train_targets, const MatrixRM<Real>& validation_inputs,
          const MatrixRM<Real>& validation_targets);

  /// Replaces the fresh state (zero momentum, generator from options.seed) by a checkpointed one whose
  /// sizes must match the network.
  void restore(TrainingState<Real> state);
  [[nodiscard]] const TrainingState<Real>& state() const { return state_; }

  /// One epoch; throws NumericalError naming the epoch when a loss is not finite.
  EpochReport train_epoch();
  /// eta of (0-based) epoch `epoch`: learning_rate * (learning_rate_final / learning_rate)^(epoch / (epochs -
  /// 1)).
  [[nodiscard]] double learning_rate_at(int epoch) const;
  /// True once options.epochs epochs are done or early stopping fired.
  [[nodiscard]] bool finished() const;
  /// Runs epochs until finished() or `on_epoch` returns false, then (restore_best, validation set) puts the
  /// best-validation parameters into the network. Returns the number of epochs run in total.
  int train(const std::function<bool(const EpochReport&)>& on_epoch = {});
  /// The restore_best step of train(), for callers that drive train_epoch() themselves.
  void finish();

 private:
  void online_epoch(double& loss_sum);
  void batch_epoch(double& loss_sum);
  void update(Real scale);

  Network<Real>& network_;
  TrainOptions options_;
  const MatrixRM<Real>& train_inputs_;
  const MatrixRM<Real>& train_targets_;
  std::size_t train_count_;
  std::size_t validation_count_;
  TrainingState<Real> state_;
  std::vector<std::uint32_t> order_;
  OnlineBackprop<Real> online_;
  std::unique_ptr<BatchGradient<Real>> batch_;
  PanelPatterns<Real> train_panels_;
  PanelPatterns<Real> validation_panels_;
  AlignedVector<Real> gradient_;
};

}  // namespace contactnn::mlp
