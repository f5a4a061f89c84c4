// The shipped networks (data/weights) for lib/search's tests, each read once per test program.
// CONTACTNN_SOURCE_DIR is the source tree (a compile definition of the tests).
#pragma once

#include <map>
#include <string>

#include "io/network_file.hpp"

namespace contactnn::testing {

/// data/weights/<name> (a float network file), read on first use.
inline const io::TrainedNetwork<float>& shipped(const std::string& name) {
  static std::map<std::string, io::TrainedNetwork<float>> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    it = cache.emplace(name, io::read_network<float>(std::string(CONTACTNN_SOURCE_DIR) + "/data/weights/" + name)).first;
  }
  return it->second;
}

}  // namespace contactnn::testing
