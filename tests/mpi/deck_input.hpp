// A deck's contact pair as the distributed search's input (tests/mpi): the faces in increasing (element id,
// face number), their connectivity in deck ids, the nodes in increasing deck id; the global face id is the
// index in that order, the serial handle's caller index (tests/contact/test_contact_search.cpp's input).
#pragma once

#include <algorithm>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include "contact/scene.hpp"

namespace contactnn::mpi_test {

struct Input {
  std::vector<long> ids;  ///< node ids, increasing
  std::vector<mesh::FaceType> types;
  std::vector<long> offsets;  ///< face f's nodes: connectivity[offsets[f] .. offsets[f + 1]]
  std::vector<long> connectivity;

  /// The position of node `id` in `ids`.
  [[nodiscard]] std::size_t index(long id) const {
    return static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin());
  }
};

inline Input input_of(const contact::Scene& scene) {
  Input in;
  in.ids = scene.master.node_ids;
  in.ids.insert(in.ids.end(), scene.slave_ids.begin(), scene.slave_ids.end());
  std::sort(in.ids.begin(), in.ids.end());
  in.ids.erase(std::unique(in.ids.begin(), in.ids.end()), in.ids.end());
  for (int f : contact::master_faces_in_deck_order(scene)) {
    const mesh::FaceNodes nodes = scene.master.face_nodes(f);
    in.types.push_back(nodes.type);
    in.offsets.push_back(static_cast<long>(in.connectivity.size()));
    for (int k : nodes) in.connectivity.push_back(scene.master.node_ids[static_cast<std::size_t>(k)]);
  }
  in.offsets.push_back(static_cast<long>(in.connectivity.size()));
  return in;
}

/// Every node's coordinates (3 per node of in.ids; NaN for a node neither side has).
inline std::vector<double> coordinates(const Input& in, const contact::Scene& scene) {
  std::vector<double> x(3 * in.ids.size(), std::numeric_limits<double>::quiet_NaN());
  const auto put = [&](long id, const geometry::Vec3& p) {
    const std::size_t i = in.index(id);
    for (std::size_t k = 0; k < 3; ++k) x[3 * i + k] = p[static_cast<Eigen::Index>(k)];
  };
  for (std::size_t i = 0; i < scene.master.node_ids.size(); ++i)
    put(scene.master.node_ids[i], scene.master.positions[i]);
  for (std::size_t i = 0; i < scene.slave_ids.size(); ++i) put(scene.slave_ids[i], scene.slave_positions[i]);
  return x;
}

}  // namespace contactnn::mpi_test
