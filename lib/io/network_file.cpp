#include "io/network_file.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "core/conventions.hpp"
#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "io/atomic_output.hpp"
#include "io/domain_io.hpp"
#include "io/hdf5_file.hpp"

namespace contactnn::io {

namespace {

template <class Real>
std::vector<double> to_double(const Real* values, std::size_t n) {
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<double>(values[i]);
  return out;
}

template <class Real>
void from_double(const std::vector<double>& values, Real* out) {
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = static_cast<Real>(values[i]);
}

std::string layers_text(const std::vector<int>& sizes) {
  std::string s;
  for (std::size_t l = 0; l < sizes.size(); ++l) s += (l ? "-" : "") + std::to_string(sizes[l]);
  return s;
}

// Reads a float64 vector and checks its length.
std::vector<double> read_sized(const Hdf5File& file, const std::string& name, std::size_t expected,
                               const std::string& why) {
  const std::vector<double> v = file.read_vector<double>(name);
  CONTACTNN_REQUIRE_AS(FormatError, v.size() == expected,
                       "'" << file.path().string() << "': dataset " << name << " has " << v.size()
                           << " values, expected " << expected << " (" << why << ")");
  return v;
}

constexpr const char* kActivationText = "O = 1 / (1 + exp(-2 U / U0)), U = sum_i W_ji I_i - theta_j";

}  // namespace

template <class Real>
void write_network_layers(Hdf5File& file, const mlp::Network<Real>& network) {
  const auto& sizes = network.layer_sizes();
  file.write_attribute("/", "u0", network.u0());
  file.write_attribute("/", "activation", std::string(kActivationText));
  file.write_vector("architecture/layer_sizes", std::vector<std::int32_t>(sizes.begin(), sizes.end()));
  for (int l = 0; l < network.layer_count(); ++l) {
    const std::string group = "layers/" + std::to_string(l);
    MatrixRM<double> w(sizes[l + 1], sizes[l]);
    for (Eigen::Index k = 0; k < w.size(); ++k) w.data()[k] = static_cast<double>(network.weights(l)[k]);
    file.write_matrix(group + "/weights", w);
    file.write_vector(group + "/thresholds",
                      to_double(network.thresholds(l), static_cast<std::size_t>(sizes[l + 1])));
  }
  const mlp::Scaling& s = network.scaling();
  file.write_attribute("/", "input_features", std::string(to_string(s.input_features)));
  file.write_vector("scaling/input_min", s.input_min);
  file.write_vector("scaling/input_max", s.input_max);
  file.write_vector("scaling/output_min", s.output_min);
  file.write_vector("scaling/output_max", s.output_max);
  file.write_attribute("scaling/output_min", "target_low", s.target_low);
  file.write_attribute("scaling/output_min", "target_high", s.target_high);
}

template <class Real>
mlp::Network<Real> read_network_layers(const Hdf5File& file, const std::string& name) {
  const std::string activation = file.read_string_attribute("/", "activation");
  CONTACTNN_REQUIRE_AS(FormatError, activation == kActivationText,
                       "'" << name << "': activation is " << quote_text(activation)
                           << ", expected the sigmoid of Eq 12, '" << kActivationText << "'");

  const std::vector<std::int32_t> raw_sizes = file.read_vector<std::int32_t>("architecture/layer_sizes");
  CONTACTNN_REQUIRE_AS(FormatError, raw_sizes.size() >= 2,
                       "'" << name << "': architecture/layer_sizes has " << raw_sizes.size()
                           << " entries, expected at least 2 (inputs and outputs)");
  std::vector<int> sizes(raw_sizes.begin(), raw_sizes.end());
  for (int n : sizes) {
    CONTACTNN_REQUIRE_AS(FormatError, n >= 1, "'" << name << "': layer size " << n << ", expected >= 1");
  }
  const std::string arch = layers_text(sizes);

  mlp::Scaling s;
  const auto n_in = static_cast<std::size_t>(sizes.front());
  const auto n_out = static_cast<std::size_t>(sizes.back());
  s.input_min = read_sized(file, "scaling/input_min", n_in, "one per input of " + arch);
  s.input_max = read_sized(file, "scaling/input_max", n_in, "one per input of " + arch);
  s.output_min = read_sized(file, "scaling/output_min", n_out, "one per output of " + arch);
  s.output_max = read_sized(file, "scaling/output_max", n_out, "one per output of " + arch);
  s.target_low = file.read_double_attribute("scaling/output_min", "target_low");
  s.target_high = file.read_double_attribute("scaling/output_min", "target_high");
  // Files written before input maps existed see the paper's features.
  if (file.has_attribute("/", "input_features")) {
    const std::string features = file.read_string_attribute("/", "input_features");
    try {
      s.input_features = input_features_from_string(features);
    } catch (const InvalidArgument&) {
      throw FormatError("'" + name + "': input_features is '" + features + "', expected 'paper' or 'affine'");
    }
  }
  const double u0 = file.read_double_attribute("/", "u0");

  auto network = [&] {
    try {
      return mlp::Network<Real>(sizes, u0, s);
    } catch (const InvalidArgument& e) {
      throw FormatError("'" + name + "': inconsistent network: " + e.what());
    }
  }();
  for (int l = 0; l < network.layer_count(); ++l) {
    const std::string group = "layers/" + std::to_string(l);
    const MatrixRM<double> w = file.read_matrix<double>(group + "/weights");
    CONTACTNN_REQUIRE_AS(FormatError, w.rows() == sizes[l + 1] && w.cols() == sizes[l],
                         "'" << name << "': dataset " << group << "/weights is " << w.rows() << " x "
                             << w.cols() << ", expected " << sizes[l + 1] << " x " << sizes[l]
                             << " (layer sizes " << arch << ")");
    for (Eigen::Index k = 0; k < w.size(); ++k) network.weights(l)[k] = static_cast<Real>(w.data()[k]);
    const std::vector<double> theta = read_sized(
        file, group + "/thresholds", static_cast<std::size_t>(sizes[l + 1]), "layer sizes " + arch);
    from_double(theta, network.thresholds(l));
  }
  for (Real p : network.parameters()) {
    CONTACTNN_REQUIRE_AS(FormatError, std::isfinite(static_cast<double>(p)),
                         "'" << name << "': a network parameter is not finite");
  }
  return network;
}

template <class Real>
std::unique_ptr<AtomicOutput> write_network_uncommitted(const std::filesystem::path& path,
                                                        const mlp::Network<Real>& network,
                                                        const geometry::TrainingDomain& domain,
                                                        const NetworkProvenance& provenance,
                                                        const mlp::TrainingState<Real>* checkpoint) {
  for (Real p : network.parameters()) {
    CONTACTNN_REQUIRE_AS(
        NumericalError, std::isfinite(static_cast<double>(p)),
        "refusing to write a network with a non-finite parameter to '" << path.string() << "'");
  }
  auto out = std::make_unique<AtomicOutput>(path);
  {
    Hdf5File file(out->write_path(), Hdf5File::Mode::kCreate, path);
    file.write_attribute("/", "kind", std::string(kNetworkFileKind));
    file.write_attribute("/", "schema_version", std::int64_t{kNetworkSchemaVersion});
    file.write_attribute("/", "surface", std::string(to_string(domain.surface)));
    file.write_attribute("/", "real_type", std::string(std::is_same_v<Real, float> ? "float32" : "float64"));
    file.write_attribute("/", "config", provenance.config_toml);
    file.write_attribute("/", "seed", static_cast<std::int64_t>(provenance.seed));
    file.write_attribute("/", "dataset", provenance.dataset_path);
    file.write_attribute("/", "dataset_checksum", provenance.dataset_checksum);
    file.write_attribute("/", "training_mode", provenance.training_mode);
    file.write_attribute("/", "training_patterns", provenance.training_patterns);
    file.write_attribute("/", "validation_patterns", provenance.validation_patterns);
    file.write_attribute("/", "epochs_run", provenance.epochs_run);
    file.write_attribute("/", "best_epoch", provenance.best_epoch);
    file.write_attribute("/", "training_loss", provenance.training_loss);
    file.write_attribute("/", "validation_loss", provenance.validation_loss);

    write_network_layers(file, network);
    write_domain(file, "domain", domain);

    if (checkpoint != nullptr) {
      const std::size_t n = network.parameter_count();
      CONTACTNN_REQUIRE(checkpoint->velocity.size() == n && checkpoint->best_parameters.size() == n,
                        "checkpoint state does not match the network's " << n << " parameters");
      file.write_vector("checkpoint/velocity", to_double(checkpoint->velocity.data(), n));
      file.write_vector("checkpoint/best_parameters", to_double(checkpoint->best_parameters.data(), n));
      std::vector<std::int64_t> rng(4);
      for (int k = 0; k < 4; ++k) rng[k] = std::bit_cast<std::int64_t>(checkpoint->rng[k]);
      file.write_vector("checkpoint/rng_state", rng);
      const std::string obj = "checkpoint/velocity";
      file.write_attribute(obj, "epoch", std::int64_t{checkpoint->epoch});
      file.write_attribute(obj, "best_epoch", std::int64_t{checkpoint->best_epoch});
      file.write_attribute(obj, "best_validation_loss", checkpoint->best_validation_loss);
      file.write_attribute(obj, "training_loss", checkpoint->training_loss);
      file.write_attribute(obj, "validation_loss", checkpoint->validation_loss);
    }
    file.close();
  }
  return out;
}

template <class Real>
void write_network(const std::filesystem::path& path, const mlp::Network<Real>& network,
                   const geometry::TrainingDomain& domain, const NetworkProvenance& provenance,
                   const mlp::TrainingState<Real>* checkpoint) {
  write_network_uncommitted(path, network, domain, provenance, checkpoint)->commit();
}

namespace {
std::string read_network_real_type(const Hdf5File& file) {
  const std::string real_type = file.read_string_attribute("/", "real_type");
  CONTACTNN_REQUIRE_AS(FormatError, real_type == "float32" || real_type == "float64",
                       "'" << file.path().string() << "': real_type is " << quote_text(real_type)
                           << ", expected 'float32' or 'float64'");
  return real_type;
}
}  // namespace

namespace {

/// require_file_kind for a network file; a face network (scene-study --face's, for tri6 or quad8 faces) is a
/// valid file given to the wrong search: InvalidArgument, as a network of the other surface is, not
/// FormatError.
void require_network_file(const Hdf5File& file) {
  CONTACTNN_REQUIRE_AS(
      InvalidArgument,
      !file.has_attribute("/", "kind") || file.read_string_attribute("/", "kind") != "contactnn-face-network",
      "'" << file.path().string()
          << "' is a face network (scene-study --face's, for tri6 or quad8 faces), not a network of "
             "4-node segments: bilinear and Gregory surfaces take train-net's network file");
  require_file_kind(file, kNetworkFileKind, kNetworkSchemaVersion);
}

}  // namespace

std::string read_network_real_type(const std::filesystem::path& path) {
  const Hdf5File file(path, Hdf5File::Mode::kRead);
  require_network_file(file);
  return read_network_real_type(file);
}

template <class Real>
TrainedNetwork<Real> read_network(const std::filesystem::path& path) {
  const Hdf5File file(path, Hdf5File::Mode::kRead);
  const std::string name = path.string();
  require_network_file(file);
  // What the evaluation code computes: the sigmoid of Eq 12 in float or double. A file that says it is
  // something else is refused rather than evaluated as if it were this.
  (void)read_network_real_type(file);
  mlp::Network<Real> network = read_network_layers<Real>(file, name);
  const auto n_in = static_cast<std::size_t>(network.input_count());
  const std::string arch = layers_text(network.layer_sizes());

  geometry::TrainingDomain domain = read_domain(file, "domain");
  const std::string surface = file.read_string_attribute("/", "surface");
  CONTACTNN_REQUIRE_AS(FormatError, surface == to_string(domain.surface),
                       "'" << name << "': root surface '" << surface << "' but domain surface '"
                           << to_string(domain.surface) << "'");
  CONTACTNN_REQUIRE_AS(FormatError, static_cast<int>(n_in) == feature_count(domain.surface),
                       "'" << name << "': a " << surface << " network needs " << feature_count(domain.surface)
                           << " inputs, layer sizes are " << arch);

  NetworkProvenance p;
  p.config_toml = file.read_string_attribute("/", "config");
  p.seed = static_cast<std::uint64_t>(file.read_int_attribute("/", "seed"));
  p.dataset_path = file.read_string_attribute("/", "dataset");
  p.dataset_checksum = file.read_string_attribute("/", "dataset_checksum");
  p.training_mode = file.read_string_attribute("/", "training_mode");
  p.training_patterns = file.read_int_attribute("/", "training_patterns");
  p.validation_patterns = file.read_int_attribute("/", "validation_patterns");
  p.epochs_run = file.read_int_attribute("/", "epochs_run");
  p.best_epoch = file.read_int_attribute("/", "best_epoch");
  p.training_loss = file.read_double_attribute("/", "training_loss");
  p.validation_loss = file.read_double_attribute("/", "validation_loss");
  return TrainedNetwork<Real>{std::move(network), std::move(domain), std::move(p)};
}

template <class Real>
mlp::TrainingState<Real> read_training_state(const std::filesystem::path& path,
                                             const mlp::Network<Real>& network) {
  const Hdf5File file(path, Hdf5File::Mode::kRead);
  const std::string name = path.string();
  require_file_kind(file, kNetworkFileKind, kNetworkSchemaVersion);
  CONTACTNN_REQUIRE_AS(FormatError, file.has_dataset("checkpoint/velocity"),
                       "'" << name
                           << "' is a network file without a checkpoint (no /checkpoint group): "
                              "it cannot be resumed");
  const std::size_t n = network.parameter_count();
  const std::string why = "one per parameter of the network";
  mlp::TrainingState<Real> state;
  state.velocity.resize(n);
  state.best_parameters.resize(n);
  from_double(read_sized(file, "checkpoint/velocity", n, why), state.velocity.data());
  from_double(read_sized(file, "checkpoint/best_parameters", n, why), state.best_parameters.data());
  const std::vector<std::int64_t> rng = file.read_vector<std::int64_t>("checkpoint/rng_state");
  CONTACTNN_REQUIRE_AS(FormatError, rng.size() == 4,
                       "'" << name << "': checkpoint/rng_state has " << rng.size() << " words, expected 4");
  for (int k = 0; k < 4; ++k) state.rng[k] = std::bit_cast<std::uint64_t>(rng[k]);
  const std::string obj = "checkpoint/velocity";
  state.epoch = static_cast<int>(file.read_int_attribute(obj, "epoch"));
  state.best_epoch = static_cast<int>(file.read_int_attribute(obj, "best_epoch"));
  state.best_validation_loss = file.read_double_attribute(obj, "best_validation_loss");
  state.training_loss = file.read_double_attribute(obj, "training_loss");
  state.validation_loss = file.read_double_attribute(obj, "validation_loss");
  // A checkpoint is only ever written from finite state (losses excepted: NaN without a validation set), so
  // a non-finite value is a damaged file, not a diverging run.
  const auto require_finite = [&](const auto& values, const char* what) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      CONTACTNN_REQUIRE_AS(FormatError, std::isfinite(static_cast<double>(values[i])),
                           "'" << name << "': checkpoint/" << what << " element " << i << " is "
                               << static_cast<double>(values[i]) << ": the checkpoint is corrupt");
    }
  };
  require_finite(state.velocity, "velocity");
  require_finite(state.best_parameters, "best_parameters");
  CONTACTNN_REQUIRE_AS(FormatError,
                       state.epoch >= 0 && state.best_epoch >= 0 && state.best_epoch <= state.epoch,
                       "'" << name << "': checkpoint epoch " << state.epoch << ", best epoch "
                           << state.best_epoch << ": the checkpoint is corrupt");
  return state;
}

std::string file_checksum(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  CONTACTNN_REQUIRE_AS(IoError, in.good(), "cannot open '" << path.string() << "' to checksum it");
  std::uint64_t h = 0xcbf29ce484222325ULL;
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const std::streamsize got = in.gcount();
    for (std::streamsize i = 0; i < got; ++i) {
      h ^= static_cast<unsigned char>(buffer[static_cast<std::size_t>(i)]);
      h *= 0x100000001b3ULL;
    }
  }
  CONTACTNN_REQUIRE_AS(IoError, in.eof(), "error reading '" << path.string() << "' to checksum it");
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return std::string("fnv1a64:") + hex;
}

template std::unique_ptr<AtomicOutput> write_network_uncommitted(const std::filesystem::path&,
                                                                 const mlp::Network<float>&,
                                                                 const geometry::TrainingDomain&,
                                                                 const NetworkProvenance&,
                                                                 const mlp::TrainingState<float>*);
template std::unique_ptr<AtomicOutput> write_network_uncommitted(const std::filesystem::path&,
                                                                 const mlp::Network<double>&,
                                                                 const geometry::TrainingDomain&,
                                                                 const NetworkProvenance&,
                                                                 const mlp::TrainingState<double>*);
template void write_network(const std::filesystem::path&, const mlp::Network<float>&,
                            const geometry::TrainingDomain&, const NetworkProvenance&,
                            const mlp::TrainingState<float>*);
template void write_network(const std::filesystem::path&, const mlp::Network<double>&,
                            const geometry::TrainingDomain&, const NetworkProvenance&,
                            const mlp::TrainingState<double>*);
template TrainedNetwork<float> read_network(const std::filesystem::path&);
template TrainedNetwork<double> read_network(const std::filesystem::path&);
template mlp::TrainingState<float> read_training_state(const std::filesystem::path&,
                                                       const mlp::Network<float>&);
template mlp::TrainingState<double> read_training_state(const std::filesystem::path&,
                                                        const mlp::Network<double>&);

}  // namespace contactnn::io

namespace contactnn::io {
template void write_network_layers(Hdf5File&, const mlp::Network<float>&);
template void write_network_layers(Hdf5File&, const mlp::Network<double>&);
template mlp::Network<float> read_network_layers(const Hdf5File&, const std::string&);
template mlp::Network<double> read_network_layers(const Hdf5File&, const std::string&);
}  // namespace contactnn::io
