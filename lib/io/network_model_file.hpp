// A network file as lib/search's run-time model: what an FE code (and the C interface) loads before it
// searches. Here rather than in lib/search, which knows no file formats.
#pragma once

#include <filesystem>
#include <memory>

#include "search/network_model.hpp"

namespace contactnn::io {

/// The network in `path`, in the precision it was trained in (read_network_real_type), with its training
/// domain. The errors of read_network. Not safe to call from two threads at once (HDF5 as Debian builds it).
[[nodiscard]] std::unique_ptr<search::NetworkModel> read_network_model(const std::filesystem::path& path);

}  // namespace contactnn::io
