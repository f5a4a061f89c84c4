// The frozen network file of train-net (docs/files.md, "Network file"): architecture, U0, weights, scaling,
// the training domain and provenance; a checkpoint is the same file plus the trainer's state.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include "geometry/domain.hpp"
#include "io/atomic_output.hpp"
#include "mlp/network.hpp"
#include "mlp/training_state.hpp"

namespace contactnn::io {

class Hdf5File;

/// The network itself in an open file (u0, activation, /architecture, /layers, /scaling, input_features): the
/// part of the network file above shared with other files of networks (face_network_file.hpp). Reading
/// refuses (FormatError naming `name`) another activation, inconsistent sizes and non-finite parameters.
template <class Real>
void write_network_layers(Hdf5File& file, const mlp::Network<Real>& network);
template <class Real>
[[nodiscard]] mlp::Network<Real> read_network_layers(const Hdf5File& file, const std::string& name);

/// Where a network came from. Stored as root attributes.
struct NetworkProvenance {
  std::string config_toml;       ///< effective train-net configuration
  std::uint64_t seed = 0;        ///< the run's --seed
  std::string dataset_path;      ///< dataset file as given on the command line
  std::string dataset_checksum;  ///< file_checksum() of the dataset file
  std::string training_mode;     ///< "online" or "batch"
  std::int64_t training_patterns = 0;
  std::int64_t validation_patterns = 0;
  std::int64_t epochs_run = 0;
  std::int64_t best_epoch = 0;  ///< epoch whose parameters were kept (0: the last one)
  double training_loss = std::numeric_limits<double>::quiet_NaN();    ///< mean E_p, last epoch
  double validation_loss = std::numeric_limits<double>::quiet_NaN();  ///< mean E_p of the kept parameters
};

template <class Real>
struct TrainedNetwork {
  mlp::Network<Real> network;
  geometry::TrainingDomain domain;
  NetworkProvenance provenance;
};

/// Writes `path` atomically (temporary file, then rename). Schema version kNetworkSchemaVersion:
///   root attributes  kind = "contactnn-network", schema_version, surface, real_type ("float32" or
///                    "float64": the precision it was trained in), u0, activation (Eq 12 in words), and
///                    the provenance fields (config, seed, dataset, dataset_checksum, training_mode,
///                    training_patterns, validation_patterns, epochs_run, best_epoch, training_loss,
///                    validation_loss)
///   /architecture/layer_sizes     int32 [L+1]        n_0 (inputs) ... n_L (outputs)
///   /layers/<l>/weights           float64 [n_{l+1} x n_l]  W_ji of Eq 13 (row j: unit j's inputs)
///   /layers/<l>/thresholds        float64 [n_{l+1}]        theta_j of Eq 13
///   /scaling/input_min, input_max, output_min, output_max  float64; attributes target_low, target_high
///                                 on /scaling/output_min (mlp::Scaling)
///   /domain/...                   the training domain (io::write_domain)
///   /checkpoint/...               only with `checkpoint`: velocity, best_parameters (float64 [P]),
///                                 rng_state (int64 [4]); attributes epoch, best_epoch,
///                                 best_validation_loss, training_loss, validation_loss on
///                                 /checkpoint/velocity
/// Parameters of a float network are stored exactly (float -> double is exact), so a round trip is
/// bit-exact. Throws IoError if the file cannot be written, NumericalError for a non-finite parameter.
template <class Real>
void write_network(const std::filesystem::path& path, const mlp::Network<Real>& network,
                   const geometry::TrainingDomain& domain, const NetworkProvenance& provenance,
                   const mlp::TrainingState<Real>* checkpoint = nullptr);

/// The same, leaving the commit to the caller (io::commit_together with the effective config).
template <class Real>
[[nodiscard]] std::unique_ptr<AtomicOutput> write_network_uncommitted(
    const std::filesystem::path& path, const mlp::Network<Real>& network,
    const geometry::TrainingDomain& domain, const NetworkProvenance& provenance,
    const mlp::TrainingState<Real>* checkpoint = nullptr);

/// The root attribute real_type of a network file: "float32" or "float64". FormatError for any other value
/// (and the errors of opening a network file).
[[nodiscard]] std::string read_network_real_type(const std::filesystem::path& path);

/// Reads a network file (or a checkpoint, ignoring its state). FormatError, naming the file and stating
/// expected and actual, for a file of another kind (e.g. a dataset), another schema version, a real_type
/// other than float32/float64 or an activation other than Eq 12's sigmoid (the only ones evaluated), a
/// missing member, a member of the wrong shape, a non-finite parameter or an inconsistent scaling.
template <class Real>
[[nodiscard]] TrainedNetwork<Real> read_network(const std::filesystem::path& path);

/// The trainer state of a checkpoint written with write_network(..., checkpoint) for `network`'s
/// architecture. FormatError if the file holds no checkpoint, its sizes differ, or its state is damaged (a
/// non-finite momentum term or kept parameter, impossible epochs): "the checkpoint is corrupt".
template <class Real>
[[nodiscard]] mlp::TrainingState<Real> read_training_state(const std::filesystem::path& path,
                                                           const mlp::Network<Real>& network);

/// FNV-1a 64-bit hash of a file's bytes as 16 hex digits, "fnv1a64:<hex>". IoError if it cannot be read.
[[nodiscard]] std::string file_checksum(const std::filesystem::path& path);

}  // namespace contactnn::io
