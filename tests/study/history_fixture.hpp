// A small history written by hand for the tests of scene-study --results (lib/study/scene_history.hpp): two
// C3D8 blocks, the upper one's bottom (4 slave nodes at 0.3 and 0.7, 0.01 above) on the lower one's top (one
// master face, the unit square at z = 1), and a CalculiX .frd (ccx's long layout) whose increments hold the
// DISP given here.
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace contactnn::study::fixture {

inline const char* kTwoBlocksDeck =
    "*NODE\n"
    "1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n"
    "5, 0, 0, 1\n6, 1, 0, 1\n7, 1, 1, 1\n8, 0, 1, 1\n"
    "11, 0.3, 0.3, 1.01\n12, 0.7, 0.3, 1.01\n13, 0.7, 0.7, 1.01\n14, 0.3, 0.7, 1.01\n"
    "15, 0.3, 0.3, 1.41\n16, 0.7, 0.3, 1.41\n17, 0.7, 0.7, 1.41\n18, 0.3, 0.7, 1.41\n"
    "*ELEMENT, TYPE=C3D8, ELSET=EMASTER\n1, 1, 2, 3, 4, 5, 6, 7, 8\n"
    "*ELEMENT, TYPE=C3D8, ELSET=ESLAVE\n2, 11, 12, 13, 14, 15, 16, 17, 18\n"
    "*SURFACE, NAME=SMASTER\nEMASTER, S2\n"
    "*SURFACE, NAME=SSLAVE\nESLAVE, S1\n"
    "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\nSSLAVE, SMASTER\n";

inline const std::vector<long> kTwoBlocksNodes = {1, 2, 3, 4, 5, 6, 7, 8, 11, 12, 13, 14, 15, 16, 17, 18};

/// The deck's node coordinates, in kTwoBlocksNodes' order.
inline std::vector<std::array<double, 3>> two_blocks_coordinates() {
  return {{0, 0, 0},        {1, 0, 0},        {1, 1, 0},        {0, 1, 0},
          {0, 0, 1},        {1, 0, 1},        {1, 1, 1},        {0, 1, 1},
          {0.3, 0.3, 1.01}, {0.7, 0.3, 1.01}, {0.7, 0.7, 1.01}, {0.3, 0.7, 1.01},
          {0.3, 0.3, 1.41}, {0.7, 0.3, 1.41}, {0.7, 0.7, 1.41}, {0.3, 0.7, 1.41}};
}

/// One increment's DISP of every node of `nodes` (same order).
using Displacements = std::vector<std::array<double, 3>>;

/// A .frd in ccx's long layout: the node block (`nodes`, `coordinates`) and one static DISP block per entry
/// of `increments` (times 1, 2, ...). `orders[k]` (where given and not empty): the indices into `nodes` whose
/// records increment k's DISP block lists, in that order (another order, or some nodes only); else every node
/// in `nodes` order.
inline std::string frd_text(const std::vector<long>& nodes,
                            const std::vector<std::array<double, 3>>& coordinates,
                            const std::vector<Displacements>& increments,
                            const std::vector<std::vector<std::size_t>>& orders = {}) {
  char b[256];
  std::string text = "    1C\n    1UPGM               CalculiX                                        \n";
  std::snprintf(b, sizeof b, "    2C                  %12zu                                     1\n",
                nodes.size());
  text += b;
  const auto record = [&](long id, const std::array<double, 3>& v) {
    std::snprintf(b, sizeof b, " -1%10ld%12.5E%12.5E%12.5E\n", id, v[0], v[1], v[2]);
    text += b;
  };
  for (std::size_t i = 0; i < nodes.size(); ++i) record(nodes[i], coordinates[i]);
  text += " -3\n";
  for (std::size_t k = 0; k < increments.size(); ++k) {
    text += "    1PSTEP                         1           1           1          \n";
    std::vector<std::size_t> order = k < orders.size() ? orders[k] : std::vector<std::size_t>();
    if (order.empty()) {
      for (std::size_t i = 0; i < nodes.size(); ++i) order.push_back(i);
    }
    std::snprintf(b, sizeof b, "  100CL  101%12.5E%12zu                     0%5zu           1\n",
                  static_cast<double>(k + 1), order.size(), k + 1);
    text += b;
    text +=
        " -4  DISP        4    1\n -5  D1          1    2    1    0\n -5  D2          1    2    2    0\n"
        " -5  D3          1    2    3    0\n -5  ALL         1    2    0    0    1ALL\n";
    for (const std::size_t i : order) record(nodes[i], increments[k][i]);
    text += " -3\n";
  }
  return text + " 9999\n";
}

/// The two blocks' history: increment 1 at rest (zero DISP); increment 2 with the master face stretched to
/// 1 x 5 (nodes at y = 1 moved by +4 in y), so that its pairs lie far outside a domain drawn from the rest
/// state (the face's aspect ratio 5 against 1 +- the deformation).
inline std::string two_blocks_frd() {
  const std::size_t n = kTwoBlocksNodes.size();
  Displacements rest(n, {0.0, 0.0, 0.0});
  Displacements stretched = rest;
  for (std::size_t i = 0; i < n; ++i) {
    if (two_blocks_coordinates()[i][1] == 1.0) stretched[i] = {0.0, 4.0, 0.0};
  }
  return frd_text(kTwoBlocksNodes, two_blocks_coordinates(), {rest, stretched});
}

}  // namespace contactnn::study::fixture
