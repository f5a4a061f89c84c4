#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "core/error.hpp"
#include "mlp/smooth_problem.hpp"
#include "mlp/trainer.hpp"

namespace contactnn::mlp {
namespace {

using testing::make_network;
using testing::smooth_problem;

// Stated level for the smooth 3-8-2 problem: the initial mean E_p is ~1e-2; 300 online epochs bring it
// below 2e-4 (an rms error of 0.014 in sigmoid units), measured ~1e-4 with these seeds.
constexpr double kSmoothProblemLossLevel = 2e-4;
// Batch size 1 and online mode do the same arithmetic in another association order (double): after a few
// hundred updates the parameters differ by rounding only.
constexpr double kSameAlgorithmTolerance = 1e-12;

template <class Real>
MatrixRM<Real> empty_rows(int cols) {
  return MatrixRM<Real>(0, cols);
}

TEST(Trainer, OnlineLossFallsToStatedLevelOnSmoothProblem) {
  auto net = make_network<float>({3, 8, 2}, 1);
  const auto train = smooth_problem<float>(200, 2);
  const auto val = smooth_problem<float>(100, 3);
  TrainOptions o;
  o.learning_rate = 0.1;
  o.momentum = 0.9;
  o.epochs = 300;
  Trainer<float> trainer(net, o, train.inputs, train.targets, val.inputs, val.targets);
  const double first = trainer.train_epoch().training_loss;
  trainer.train();
  EXPECT_LT(trainer.state().training_loss, kSmoothProblemLossLevel) << "first epoch " << first;
  EXPECT_LT(trainer.state().best_validation_loss, 2 * kSmoothProblemLossLevel);
  EXPECT_LT(trainer.state().training_loss, first / 10);
  std::printf("smooth problem: first epoch %.3e, last %.3e\n", first, trainer.state().training_loss);
}

TEST(Trainer, FullBatchLossFallsOnSmoothProblem) {
  auto net = make_network<float>({3, 8, 2}, 1);
  const auto train = smooth_problem<float>(200, 2);
  TrainOptions o;
  o.mode = TrainingMode::kBatch;
  o.learning_rate = 2.0;
  o.momentum = 0.9;
  o.epochs = 2000;
  Trainer<float> trainer(net, o, train.inputs, train.targets, empty_rows<float>(3), empty_rows<float>(2));
  const double first = trainer.train_epoch().training_loss;
  trainer.train();
  EXPECT_LT(trainer.state().training_loss, 5 * kSmoothProblemLossLevel) << "first epoch " << first;
  std::printf("smooth problem, full batch: first epoch %.3e, last %.3e\n", first,
              trainer.state().training_loss);
}

TEST(Trainer, BatchSizeOneEqualsOnlineMode) {
  const auto train = smooth_problem<double>(150, 4);
  auto run = [&](TrainingMode mode) {
    auto net = make_network<double>({3, 6, 2}, 8);
    TrainOptions o;
    o.mode = mode;
    o.batch_size = 1;
    o.learning_rate = 0.05;
    o.epochs = 3;
    o.seed = 77;
    Trainer<double> trainer(net, o, train.inputs, train.targets, empty_rows<double>(3),
                            empty_rows<double>(2));
    trainer.train();
    return net.parameters();
  };
  const auto online = run(TrainingMode::kOnline);
  const auto batch = run(TrainingMode::kBatch);
  ASSERT_EQ(online.size(), batch.size());
  for (std::size_t k = 0; k < online.size(); ++k)
    EXPECT_NEAR(online[k], batch[k], kSameAlgorithmTolerance) << k;
}

TEST(Trainer, ResumingFromStateEqualsUninterruptedRunBitForBit) {
  const auto train = smooth_problem<float>(300, 5);
  const auto val = smooth_problem<float>(60, 6);
  for (const auto mode : {TrainingMode::kOnline, TrainingMode::kBatch}) {
    TrainOptions o;
    o.mode = mode;
    o.batch_size = 64;
    o.learning_rate = mode == TrainingMode::kOnline ? 0.1 : 0.5;
    o.epochs = 12;
    o.seed = 3;
    auto straight = make_network<float>({3, 7, 5, 2}, 21);
    Trainer<float> a(straight, o, train.inputs, train.targets, val.inputs, val.targets);
    a.train();

    auto first = make_network<float>({3, 7, 5, 2}, 21);
    TrainingState<float> saved;
    AlignedVector<float> saved_parameters;
    {
      Trainer<float> b(first, o, train.inputs, train.targets, val.inputs, val.targets);
      for (int e = 0; e < 5; ++e) b.train_epoch();
      saved = b.state();
      saved_parameters = first.parameters();
    }
    auto resumed =
        make_network<float>({3, 7, 5, 2}, 99);  // other initial weights: all must come from the state
    resumed.parameters() = saved_parameters;
    Trainer<float> c(resumed, o, train.inputs, train.targets, val.inputs, val.targets);
    c.restore(saved);
    c.train();
    EXPECT_EQ(straight.parameters(), resumed.parameters()) << to_string(mode);
    EXPECT_EQ(a.state().epoch, c.state().epoch);
    EXPECT_EQ(a.state().best_epoch, c.state().best_epoch);
    EXPECT_EQ(a.state().velocity, c.state().velocity);
  }
}

TEST(Trainer, SameSeedSameNetworkForAnyThreadCount) {
  const auto train = smooth_problem<float>(3000, 7);
  auto run = [&](int threads) {
    auto net = make_network<float>({3, 16, 2}, 5);
    TrainOptions o;
    o.mode = TrainingMode::kBatch;
    o.batch_size = 700;
    o.learning_rate = 0.5;
    o.epochs = 4;
    o.threads = threads;
    Trainer<float> trainer(net, o, train.inputs, train.targets, empty_rows<float>(3), empty_rows<float>(2));
    trainer.train();
    return net.parameters();
  };
  EXPECT_EQ(run(1), run(2));
  EXPECT_EQ(run(1), run(3));
}

TEST(Trainer, NonFiniteLossThrowsNumericalErrorNamingTheEpoch) {
  auto net = make_network<float>({3, 8, 2}, 1);
  const auto train = smooth_problem<float>(50, 2);
  TrainOptions o;
  o.epochs = 50;
  Trainer<float> trainer(net, o, train.inputs, train.targets, empty_rows<float>(3), empty_rows<float>(2));
  trainer.train_epoch();
  trainer.train_epoch();
  // A sigmoid network's error is bounded, so no learning rate makes it overflow reliably; a corrupted
  // parameter does, and must stop training at the next epoch.
  net.parameters()[0] = std::numeric_limits<float>::quiet_NaN();
  try {
    trainer.train();
    FAIL() << "a NaN parameter did not stop training";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("at epoch 3"), std::string::npos) << e.what();
    EXPECT_EQ(e.exit_code(), 5);
  }
}

TEST(Trainer, EarlyStoppingAfterPatienceAndBestParametersRestored) {
  auto net = make_network<float>({3, 8, 2}, 1);
  const auto train = smooth_problem<float>(100, 2);
  auto val = smooth_problem<float>(100, 3);
  val.targets.setConstant(0.5f);  // unrelated targets: fitting the training set makes validation worse
  TrainOptions o;
  o.learning_rate = 0.1;
  o.epochs = 1000;
  o.patience = 5;
  Trainer<float> trainer(net, o, train.inputs, train.targets, val.inputs, val.targets);
  trainer.train();
  const auto& s = trainer.state();
  EXPECT_LT(s.epoch, o.epochs);
  EXPECT_EQ(s.epoch, s.best_epoch + o.patience);
  EXPECT_EQ(net.parameters(), s.best_parameters);
}

TEST(Trainer, LearningRateDecaysGeometricallyToTheFinalOne) {
  auto net = make_network<double>({3, 4, 2}, 1);
  const auto train = smooth_problem<double>(20, 2);
  TrainOptions o;
  o.learning_rate = 0.1;
  o.learning_rate_final = 0.001;
  o.epochs = 5;
  const Trainer<double> decaying(net, o, train.inputs, train.targets, empty_rows<double>(3),
                                 empty_rows<double>(2));
  // 0.1 * 0.01^(e / 4): 0.1, 0.0316..., 0.01, 0.00316..., 0.001, written out.
  EXPECT_DOUBLE_EQ(decaying.learning_rate_at(0), 0.1);
  EXPECT_NEAR(decaying.learning_rate_at(1), 0.031622776601683794, 1e-15);
  EXPECT_NEAR(decaying.learning_rate_at(2), 0.01, 1e-15);
  EXPECT_NEAR(decaying.learning_rate_at(4), 0.001, 1e-16);
  o.learning_rate_final = 0.0;
  const Trainer<double> constant(net, o, train.inputs, train.targets, empty_rows<double>(3),
                                 empty_rows<double>(2));
  EXPECT_DOUBLE_EQ(constant.learning_rate_at(3), 0.1);
}

TEST(Trainer, DecayingRateChangesTheRunAndAFinalRateEqualToTheFirstDoesNot) {
  const auto train = smooth_problem<double>(50, 2);
  const auto run = [&](double final_rate) {
    auto net = make_network<double>({3, 4, 2}, 1);
    TrainOptions o;
    o.learning_rate = 0.1;
    o.learning_rate_final = final_rate;
    o.epochs = 20;
    Trainer<double> t(net, o, train.inputs, train.targets, empty_rows<double>(3), empty_rows<double>(2));
    t.train();
    return net.parameters();
  };
  EXPECT_EQ(run(0.0), run(0.1));
  EXPECT_NE(run(0.0), run(0.01));
}

TEST(Trainer, RejectsBadOptions) {
  auto net = make_network<float>({3, 8, 2}, 1);
  const auto train = smooth_problem<float>(10, 2);
  TrainOptions o;
  o.momentum = 1.0;
  EXPECT_THROW(
      Trainer<float>(net, o, train.inputs, train.targets, empty_rows<float>(3), empty_rows<float>(2)),
      InvalidArgument);
  o = TrainOptions{};
  o.learning_rate = -1;
  EXPECT_THROW(
      Trainer<float>(net, o, train.inputs, train.targets, empty_rows<float>(3), empty_rows<float>(2)),
      InvalidArgument);
}

}  // namespace
}  // namespace contactnn::mlp
