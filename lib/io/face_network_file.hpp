// The file of a face network (search::FaceNetwork: tri6 or quad8 faces; docs/files.md "Face network file"):
// the network as in the network file (write_network_layers), the face type, the training domain's feature
// box, and where it came from.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "mlp/network.hpp"
#include "search/face_network.hpp"

namespace contactnn::io {

inline constexpr std::string_view kFaceNetworkFileKind = "contactnn-face-network";
inline constexpr std::int64_t kFaceNetworkSchemaVersion = 1;

/// A face network as stored.
struct FaceNetworkFile {
  search::FaceKind face = search::FaceKind::kTri6;
  mlp::Network<float> network;
  std::vector<double> feature_min, feature_max;  ///< the training domain (search::FaceNetwork)
  std::string provenance;                        ///< free text: the study, its scene, sample and settings
};

/// Writes `path` atomically:
///   root attributes  kind = "contactnn-face-network", schema_version = 1, face ("tri6" or "quad8"),
///                    real_type "float32", provenance, and those of write_network_layers
///   /architecture, /layers, /scaling   as in the network file
///   /domain/feature_min, /domain/feature_max   float64 [face_feature_count]
/// Throws IoError if it cannot be written, NumericalError for a non-finite parameter.
void write_face_network(const std::filesystem::path& path, search::FaceKind face,
                        const mlp::Network<float>& network, const std::vector<double>& feature_min,
                        const std::vector<double>& feature_max, const std::string& provenance);

/// Reads a file write_face_network wrote; FormatError naming the file for another kind or version, a face
/// type other than tri6 or quad8, or inputs or bounds that do not match the face type.
[[nodiscard]] FaceNetworkFile read_face_network(const std::filesystem::path& path);

/// The file as FaceSearch's network.
[[nodiscard]] std::unique_ptr<search::FaceNetwork> load_face_network(const std::filesystem::path& path);

}  // namespace contactnn::io
