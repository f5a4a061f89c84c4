#include "mlp/trainer.hpp"

#include <cmath>
#include <numeric>

#include "core/error.hpp"
#include "mlp/flush_denormals.hpp"

namespace contactnn::mlp {

std::string_view to_string(TrainingMode mode) { return mode == TrainingMode::kOnline ? "online" : "batch"; }

TrainingMode training_mode_from_string(std::string_view name) {
  if (name == "online") return TrainingMode::kOnline;
  if (name == "batch") return TrainingMode::kBatch;
  throw InvalidArgument("unknown training mode '" + std::string(name) + "': expected 'online' or 'batch'");
}

template <class Real>
Trainer<Real>::Trainer(Network<Real>& network, const TrainOptions& options,
                       const MatrixRM<Real>& train_inputs, const MatrixRM<Real>& train_targets,
                       const MatrixRM<Real>& validation_inputs, const MatrixRM<Real>& validation_targets)
    : network_(network),
      options_(options),
      train_inputs_(train_inputs),
      train_targets_(train_targets),
      train_count_(static_cast<std::size_t>(train_inputs.rows())),
      validation_count_(static_cast<std::size_t>(validation_inputs.rows())),
      online_(network),
      train_panels_(network.input_count(), network.output_count()),
      validation_panels_(network.input_count(), network.output_count()) {
  CONTACTNN_REQUIRE(options.learning_rate > 0.0 && std::isfinite(options.learning_rate),
                    "learning rate must be positive, got " << options.learning_rate);
  CONTACTNN_REQUIRE(
      options.learning_rate_final >= 0.0 && options.learning_rate_final <= options.learning_rate,
      "final learning rate must be in [0, learning rate " << options.learning_rate << "], got "
                                                          << options.learning_rate_final);
  CONTACTNN_REQUIRE(options.momentum >= 0.0 && options.momentum < 1.0,
                    "momentum must be in [0, 1), got " << options.momentum);
  CONTACTNN_REQUIRE(options.epochs >= 1, "epochs must be at least 1, got " << options.epochs);
  CONTACTNN_REQUIRE(options.patience >= 0, "patience must be >= 0, got " << options.patience);
  CONTACTNN_REQUIRE(train_count_ >= 1, "the training set is empty");
  CONTACTNN_REQUIRE(train_count_ < (std::size_t{1} << 32),
                    "at most 2^32 - 1 training patterns, got " << train_count_);
  CONTACTNN_REQUIRE(
      train_inputs.cols() == network.input_count() && train_targets.cols() == network.output_count() &&
          train_targets.rows() == train_inputs.rows(),
      "training set: expected N x " << network.input_count() << " inputs and N x " << network.output_count()
                                    << " targets, got " << train_inputs.rows() << " x " << train_inputs.cols()
                                    << " and " << train_targets.rows() << " x " << train_targets.cols());
  CONTACTNN_REQUIRE(validation_inputs.rows() == validation_targets.rows() &&
                        (validation_count_ == 0 || (validation_inputs.cols() == network.input_count() &&
                                                    validation_targets.cols() == network.output_count())),
                    "validation set: expected N x "
                        << network.input_count() << " inputs and N x " << network.output_count()
                        << " targets, got " << validation_inputs.rows() << " x " << validation_inputs.cols()
                        << " and " << validation_targets.rows() << " x " << validation_targets.cols());
  CONTACTNN_REQUIRE(train_inputs.allFinite() && train_targets.allFinite(),
                    "the training set contains a non-finite value");
  state_.rng = Rng(options.seed).state();
  state_.velocity.assign(network.parameter_count(), Real(0));
  state_.best_parameters = network.parameters();
  order_.resize(train_count_);
  std::iota(order_.begin(), order_.end(), 0u);
  gradient_.assign(network.parameter_count(), Real(0));
  const bool need_batch = options.mode == TrainingMode::kBatch || validation_count_ > 0;
  if (need_batch) batch_ = std::make_unique<BatchGradient<Real>>(network, options.threads);
  if (options.mode == TrainingMode::kBatch) {
    // Full batch: laid out once. Mini-batches: re-laid out in shuffled order every epoch, same buffers.
    const std::size_t batch = options.batch_size == 0 ? train_count_ : options.batch_size;
    train_panels_.assign(train_inputs, train_targets, order_.data(), train_count_, batch, options.threads);
  }
  if (validation_count_ > 0) {
    std::vector<std::uint32_t> identity(validation_count_);
    std::iota(identity.begin(), identity.end(), 0u);
    validation_panels_.assign(validation_inputs, validation_targets, identity.data(), validation_count_,
                              validation_count_, options.threads);
  }
}

template <class Real>
void Trainer<Real>::restore(TrainingState<Real> state) {
  CONTACTNN_REQUIRE(state.velocity.size() == network_.parameter_count() &&
                        state.best_parameters.size() == network_.parameter_count(),
                    "training state holds "
                        << state.velocity.size() << " momentum and " << state.best_parameters.size()
                        << " best values, the network has " << network_.parameter_count() << " parameters");
  CONTACTNN_REQUIRE(state.epoch >= 0, "training state epoch " << state.epoch);
  state_ = std::move(state);
}

template <class Real>
bool Trainer<Real>::finished() const {
  if (state_.epoch >= options_.epochs) return true;
  return options_.patience > 0 && validation_count_ > 0 && state_.best_epoch > 0 &&
         state_.epoch - state_.best_epoch >= options_.patience;
}

template <class Real>
void Trainer<Real>::online_epoch(double& loss_sum) {
  Rng rng = Rng::from_state(state_.rng);
  std::iota(order_.begin(), order_.end(), 0u);  // the permutation depends on the generator state only
  rng.shuffle(order_.data(), order_.size());
  state_.rng = rng.state();
  const Real lr = static_cast<Real>(learning_rate_at(state_.epoch));
  const Real alpha = static_cast<Real>(options_.momentum);
  Real* velocity = state_.velocity.data();
  online_.load(network_, velocity);
  const std::size_t n = order_.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t row = order_[k];
    // Shuffled rows are scattered over a set larger than L2: fetch the next one while this one trains.
    if (k + 1 < n) {
      __builtin_prefetch(train_inputs_.row(order_[k + 1]).data());
      __builtin_prefetch(train_targets_.row(order_[k + 1]).data());
    }
    loss_sum += static_cast<double>(online_.train_pattern(network_, velocity, train_inputs_.row(row).data(),
                                                          train_targets_.row(row).data(), lr, alpha));
  }
  online_.store(network_, velocity);
}

template <class Real>
double Trainer<Real>::learning_rate_at(int epoch) const {
  if (options_.learning_rate_final <= 0.0 || options_.epochs <= 1) return options_.learning_rate;
  const double progress = std::min(1.0, static_cast<double>(epoch) / (options_.epochs - 1));
  return options_.learning_rate * std::pow(options_.learning_rate_final / options_.learning_rate, progress);
}

template <class Real>
void Trainer<Real>::update(Real scale) {
  // dw = alpha dw - eta g / count;  w += dw
  const Real step = static_cast<Real>(learning_rate_at(state_.epoch)) * scale;
  const Real alpha = static_cast<Real>(options_.momentum);
  Real* w = network_.parameters().data();
  Real* v = state_.velocity.data();
  const Real* g = gradient_.data();
  const std::size_t n = gradient_.size();
  for (std::size_t p = 0; p < n; ++p) {
    v[p] = alpha * v[p] - step * g[p];
    w[p] += v[p];
  }
}

template <class Real>
void Trainer<Real>::batch_epoch(double& loss_sum) {
  const bool full = options_.batch_size == 0 || options_.batch_size >= train_count_;
  if (!full) {
    Rng rng = Rng::from_state(state_.rng);
    std::iota(order_.begin(), order_.end(), 0u);
    rng.shuffle(order_.data(), order_.size());
    state_.rng = rng.state();
    train_panels_.assign(train_inputs_, train_targets_, order_.data(), train_count_, options_.batch_size,
                         options_.threads);
  }
  const auto& segments = train_panels_.segments();
  for (std::size_t s = 0; s < segments.size(); ++s) {
    loss_sum += batch_->compute(network_, train_panels_, s, gradient_.data());
    update(Real(1) / static_cast<Real>(segments[s].pattern_count));
  }
}

template <class Real>
EpochReport Trainer<Real>::train_epoch() {
  const ScopedFlushDenormals flush;
  double loss_sum = 0.0;
  if (options_.mode == TrainingMode::kOnline) {
    online_epoch(loss_sum);
  } else {
    batch_epoch(loss_sum);
  }
  ++state_.epoch;
  EpochReport report;
  report.epoch = state_.epoch;
  report.training_loss = loss_sum / static_cast<double>(train_count_);
  CONTACTNN_REQUIRE_AS(NumericalError, std::isfinite(report.training_loss),
                       "training diverged at epoch " << state_.epoch << ": mean training error is "
                                                     << report.training_loss
                                                     << " (try a smaller learning rate or momentum)");
  report.validation_loss = std::numeric_limits<double>::quiet_NaN();
  if (validation_count_ > 0) {
    report.validation_loss =
        batch_->loss(network_, validation_panels_, 0) / static_cast<double>(validation_count_);
    CONTACTNN_REQUIRE_AS(NumericalError, std::isfinite(report.validation_loss),
                         "training diverged at epoch " << state_.epoch << ": mean validation error is "
                                                       << report.validation_loss);
    if (report.validation_loss < state_.best_validation_loss) {
      report.improved = true;
      state_.best_validation_loss = report.validation_loss;
      state_.best_epoch = state_.epoch;
      state_.best_parameters = network_.parameters();
    }
  }
  state_.training_loss = report.training_loss;
  state_.validation_loss = report.validation_loss;
  return report;
}

template <class Real>
void Trainer<Real>::finish() {
  if (options_.restore_best && validation_count_ > 0 && state_.best_epoch > 0) {
    network_.parameters() = state_.best_parameters;
  }
}

template <class Real>
int Trainer<Real>::train(const std::function<bool(const EpochReport&)>& on_epoch) {
  while (!finished()) {
    const EpochReport report = train_epoch();
    if (on_epoch && !on_epoch(report)) break;
  }
  finish();
  return state_.epoch;
}

template class Trainer<float>;
template class Trainer<double>;

}  // namespace contactnn::mlp
