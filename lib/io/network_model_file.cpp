#include "io/network_model_file.hpp"

#include "io/network_file.hpp"

namespace contactnn::io {

std::unique_ptr<search::NetworkModel> read_network_model(const std::filesystem::path& path) {
  if (read_network_real_type(path) == "float32") {
    const TrainedNetwork<float> trained = read_network<float>(path);
    return std::make_unique<search::NetworkModel>(trained.network, trained.domain);
  }
  const TrainedNetwork<double> trained = read_network<double>(path);
  return std::make_unique<search::NetworkModel>(trained.network, trained.domain);
}

}  // namespace contactnn::io
