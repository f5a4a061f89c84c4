#include "io/face_network_file.hpp"

#include <cmath>

#include "core/conventions.hpp"
#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "io/atomic_output.hpp"
#include "io/hdf5_file.hpp"
#include "io/network_file.hpp"

namespace contactnn::io {

void write_face_network(const std::filesystem::path& path, search::FaceKind face,
                        const mlp::Network<float>& network, const std::vector<double>& feature_min,
                        const std::vector<double>& feature_max, const std::string& provenance) {
  for (float p : network.parameters()) {
    CONTACTNN_REQUIRE_AS(
        NumericalError, std::isfinite(p),
        "refusing to write a network with a non-finite parameter to '" << path.string() << "'");
  }
  // The same checks as a FaceNetwork's (face type, inputs, bounds) before anything is written.
  (void)search::FaceNetwork(face, network, feature_min, feature_max);
  AtomicOutput out(path);
  {
    Hdf5File file(out.write_path(), Hdf5File::Mode::kCreate, path);
    file.write_attribute("/", "kind", std::string(kFaceNetworkFileKind));
    file.write_attribute("/", "schema_version", kFaceNetworkSchemaVersion);
    file.write_attribute("/", "face", std::string(search::to_string(face)));
    file.write_attribute("/", "real_type", std::string("float32"));
    file.write_attribute("/", "provenance", provenance);
    write_network_layers(file, network);
    file.write_vector("domain/feature_min", feature_min);
    file.write_vector("domain/feature_max", feature_max);
    file.close();
  }
  out.commit();
}

FaceNetworkFile read_face_network(const std::filesystem::path& path) {
  const Hdf5File file(path, Hdf5File::Mode::kRead);
  const std::string name = path.string();
  // A network, but of the 4-node segments: a valid file given to the wrong search (InvalidArgument, as a face
  // network of the other face type is), not a damaged one.
  CONTACTNN_REQUIRE_AS(
      InvalidArgument,
      !file.has_attribute("/", "kind") || file.read_string_attribute("/", "kind") != kNetworkFileKind,
      "'" << name
          << "' is a network of 4-node segments (train-net's network file), not a face "
             "network: tri6 and quad8 faces take a face network file (scene-study --face)");
  require_file_kind(file, kFaceNetworkFileKind, kFaceNetworkSchemaVersion);
  const std::string face = file.read_string_attribute("/", "face");
  CONTACTNN_REQUIRE_AS(FormatError, face == "tri6" || face == "quad8",
                       "'" << name << "': face is " << quote_text(face) << ", expected 'tri6' or 'quad8'");
  const std::string real_type = file.read_string_attribute("/", "real_type");
  CONTACTNN_REQUIRE_AS(FormatError, real_type == "float32",
                       "'" << name << "': real_type is " << quote_text(real_type) << ", expected 'float32'");
  FaceNetworkFile out{search::face_kind_from_string(face), read_network_layers<float>(file, name),
                      file.read_vector<double>("domain/feature_min"),
                      file.read_vector<double>("domain/feature_max"),
                      file.read_string_attribute("/", "provenance")};
  try {
    (void)search::FaceNetwork(out.face, out.network, out.feature_min, out.feature_max);
  } catch (const InvalidArgument& e) {
    throw FormatError("'" + name + "': " + e.what());
  }
  return out;
}

std::unique_ptr<search::FaceNetwork> load_face_network(const std::filesystem::path& path) {
  const FaceNetworkFile f = read_face_network(path);
  return std::make_unique<search::FaceNetwork>(f.face, f.network, f.feature_min, f.feature_max);
}

}  // namespace contactnn::io
