#include <gtest/gtest.h>

#include <type_traits>

#include "core/error.hpp"
#include "io/dataset_file.hpp"
#include "io/domain_io.hpp"
#include "io/hdf5_file.hpp"
#include "io/network_file.hpp"
#include "mlp/random.hpp"
#include "mlp/trainer.hpp"
#include "network_fixtures.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

std::filesystem::path temp_dir() { return testing::test_output_dir("test-mlp"); }

using testing::bilinear_domain;

template <class Real>
mlp::Network<Real> bilinear_network(std::vector<int> sizes, std::uint64_t seed) {
  return testing::bilinear_network<Real>(std::move(sizes), 1.5, seed);
}

NetworkProvenance provenance() {
  NetworkProvenance p;
  p.config_toml = "[train-net]\nhidden = \"8\"\n";
  p.seed = 12345678901234ULL;
  p.dataset_path = "data/x.h5";
  p.dataset_checksum = "fnv1a64:0123456789abcdef";
  p.training_mode = "online";
  p.training_patterns = 1000;
  p.validation_patterns = 200;
  p.epochs_run = 17;
  p.best_epoch = 12;
  p.training_loss = 1.5e-3;
  p.validation_loss = 2.5e-3;
  return p;
}

std::string error_of(const std::filesystem::path& path) {
  try {
    (void)read_network<float>(path);
  } catch (const FormatError& e) {
    return e.what();
  } catch (const Error& e) {
    return std::string("wrong exception type: ") + e.what();
  }
  return "(no error)";
}

template <class Real>
void check_round_trip() {
  // One file per real type: ctest -j runs the float and the double case at once, in one directory.
  const auto path = temp_dir() / (std::is_same_v<Real, float> ? "round-float.h5" : "round-double.h5");
  const auto net = bilinear_network<Real>({8, 5, 3, 2}, 4);
  write_network(path, net, bilinear_domain(), provenance());
  const TrainedNetwork<Real> back = read_network<Real>(path);
  EXPECT_EQ(back.network.layer_sizes(), net.layer_sizes());
  EXPECT_EQ(back.network.parameters(), net.parameters());  // bit-exact
  EXPECT_EQ(back.network.u0(), net.u0());
  EXPECT_EQ(back.network.scaling().input_min, net.scaling().input_min);
  EXPECT_EQ(back.network.scaling().output_max, net.scaling().output_max);
  EXPECT_EQ(back.network.scaling().target_low, net.scaling().target_low);
  EXPECT_EQ(back.domain.feature_max, bilinear_domain().feature_max);
  EXPECT_EQ(back.domain.surface, SurfaceKind::kBilinear);
  EXPECT_EQ(back.provenance.seed, provenance().seed);
  EXPECT_EQ(back.provenance.config_toml, provenance().config_toml);
  EXPECT_EQ(back.provenance.dataset_checksum, provenance().dataset_checksum);
  EXPECT_EQ(back.provenance.best_epoch, 12);
  EXPECT_EQ(back.provenance.validation_loss, 2.5e-3);
}

TEST(NetworkFile, RoundTripIsBitExactFloat) { check_round_trip<float>(); }
TEST(NetworkFile, RoundTripIsBitExactDouble) { check_round_trip<double>(); }

TEST(NetworkFile, InputFeaturesRoundTrip) {
  const auto path = temp_dir() / "affine.h5";
  auto net = bilinear_network<float>({8, 4, 2}, 5);
  mlp::Scaling s = net.scaling();
  s.input_features = InputFeatures::kAffine;
  const mlp::Network<float> affine({8, 4, 2}, 1.5, s);
  write_network(path, affine, bilinear_domain(), provenance());
  EXPECT_EQ(read_network<float>(path).network.scaling().input_features, InputFeatures::kAffine);
  write_network(path, net, bilinear_domain(), provenance());
  EXPECT_EQ(read_network<float>(path).network.scaling().input_features, InputFeatures::kPaper);
}

TEST(NetworkFile, DatasetFileIsRejectedNamingBothKindsAndTheFile) {
  const auto path = temp_dir() / "a-dataset.h5";
  dataset::LabelledSet set;
  set.resize(2, SurfaceKind::kBilinear);
  set.features.setZero();
  set.labels.setZero();
  set.gap.setZero();
  set.iterations.setZero();
  set.scale.setOnes();
  set.status.assign(2, Status::kOk);
  write_dataset(path, set);
  const std::string e = error_of(path);
  EXPECT_NE(e.find("is a contactnn-dataset file, expected a contactnn-network file"), std::string::npos) << e;
  EXPECT_NE(e.find("a-dataset.h5"), std::string::npos) << e;
}

TEST(NetworkFile, OtherSchemaVersionIsRejectedWithBothVersions) {
  const auto path = temp_dir() / "future.h5";
  {
    Hdf5File f(path, Hdf5File::Mode::kCreate);
    f.write_attribute("/", "kind", std::string(kNetworkFileKind));
    f.write_attribute("/", "schema_version", std::int64_t{kNetworkSchemaVersion + 1});
  }
  const std::string e = error_of(path);
  EXPECT_NE(e.find("schema version " + std::to_string(kNetworkSchemaVersion + 1) + ", expected " +
                   std::to_string(kNetworkSchemaVersion)),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("future.h5"), std::string::npos) << e;
}

// A complete network file written member by member, with layer 0's weights given `cols` columns.
void write_by_hand(const std::filesystem::path& path, int cols, std::size_t thresholds) {
  Hdf5File f(path, Hdf5File::Mode::kCreate);
  f.write_attribute("/", "kind", std::string(kNetworkFileKind));
  f.write_attribute("/", "schema_version", std::int64_t{kNetworkSchemaVersion});
  f.write_attribute("/", "surface", std::string("bilinear"));
  f.write_attribute("/", "u0", 2.0);
  f.write_attribute("/", "real_type", std::string("float32"));
  f.write_attribute("/", "activation",
                    std::string("O = 1 / (1 + exp(-2 U / U0)), U = sum_i W_ji I_i - theta_j"));
  f.write_vector("architecture/layer_sizes", std::vector<std::int32_t>{8, 4, 2});
  f.write_matrix("layers/0/weights", MatrixRM<double>(MatrixRM<double>::Zero(4, cols)));
  f.write_vector("layers/0/thresholds", std::vector<double>(thresholds, 0.0));
  f.write_matrix("layers/1/weights", MatrixRM<double>(MatrixRM<double>::Zero(2, 4)));
  f.write_vector("layers/1/thresholds", std::vector<double>(2, 0.0));
  const auto d = bilinear_domain();
  f.write_vector("scaling/input_min", d.feature_min);
  f.write_vector("scaling/input_max", d.feature_max);
  f.write_vector("scaling/output_min", std::vector<double>{-1, -1});
  f.write_vector("scaling/output_max", std::vector<double>{1, 1});
  f.write_attribute("scaling/output_min", "target_low", 0.1);
  f.write_attribute("scaling/output_min", "target_high", 0.9);
  write_domain(f, "domain", d);
  const NetworkProvenance p = provenance();
  f.write_attribute("/", "config", p.config_toml);
  f.write_attribute("/", "seed", std::int64_t{1});
  f.write_attribute("/", "dataset", p.dataset_path);
  f.write_attribute("/", "dataset_checksum", p.dataset_checksum);
  f.write_attribute("/", "training_mode", p.training_mode);
  for (const char* k : {"training_patterns", "validation_patterns", "epochs_run", "best_epoch"}) {
    f.write_attribute("/", k, std::int64_t{1});
  }
  f.write_attribute("/", "training_loss", 0.1);
  f.write_attribute("/", "validation_loss", 0.1);
}

TEST(NetworkFile, WrongShapesAreRejectedWithExpectedAndActual) {
  const auto good = temp_dir() / "by-hand.h5";
  write_by_hand(good, 8, 4);
  EXPECT_NO_THROW((void)read_network<float>(good));  // the hand-written file is otherwise valid

  const auto path = temp_dir() / "wrong-shape.h5";
  write_by_hand(path, 7, 4);
  std::string e = error_of(path);
  EXPECT_NE(e.find("layers/0/weights is 4 x 7, expected 4 x 8 (layer sizes 8-4-2)"), std::string::npos) << e;
  EXPECT_NE(e.find("wrong-shape.h5"), std::string::npos) << e;

  write_by_hand(path, 8, 3);
  e = error_of(path);
  EXPECT_NE(e.find("layers/0/thresholds has 3 values, expected 4"), std::string::npos) << e;
}

TEST(NetworkFile, NetworkWithoutCheckpointCannotBeResumed) {
  const auto path = temp_dir() / "no-checkpoint.h5";
  const auto net = bilinear_network<float>({8, 4, 2}, 1);
  write_network(path, net, bilinear_domain(), provenance());
  try {
    (void)read_training_state<float>(path, net);
    FAIL() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("without a checkpoint"), std::string::npos) << e.what();
  }
}

TEST(NetworkFile, ResumingFromCheckpointFileEqualsUninterruptedRunBitForBit) {
  mlp::Rng rng(3);
  mlp::MatrixRM<float> x(400, 8), t(400, 2), vx(80, 8), vt(80, 2);
  for (auto* m : {&x, &t, &vx, &vt}) {
    for (Eigen::Index k = 0; k < m->size(); ++k) m->data()[k] = static_cast<float>(rng.uniform(0.1, 0.9));
  }
  for (const auto mode : {mlp::TrainingMode::kOnline, mlp::TrainingMode::kBatch}) {
    mlp::TrainOptions o;
    o.mode = mode;
    o.batch_size = 50;
    o.epochs = 9;
    o.learning_rate = 0.05;
    auto straight = bilinear_network<float>({8, 6, 2}, 2);
    mlp::Trainer<float> a(straight, o, x, t, vx, vt);
    a.train();

    const auto path = temp_dir() / "checkpoint.h5";
    {
      auto first = bilinear_network<float>({8, 6, 2}, 2);
      mlp::Trainer<float> b(first, o, x, t, vx, vt);
      for (int e = 0; e < 4; ++e) b.train_epoch();
      write_network(path, first, bilinear_domain(), provenance(), &b.state());
    }
    TrainedNetwork<float> saved = read_network<float>(path);
    mlp::Trainer<float> c(saved.network, o, x, t, vx, vt);
    c.restore(read_training_state<float>(path, saved.network));
    EXPECT_EQ(c.state().epoch, 4);
    c.train();
    EXPECT_EQ(straight.parameters(), saved.network.parameters()) << mlp::to_string(mode);
    EXPECT_EQ(a.state().best_validation_loss, c.state().best_validation_loss);
  }
}

}  // namespace
}  // namespace contactnn::io
