// Step 6 of the scene study (scene_study.hpp): every quadrilateral pair in each of the 8 node orders of its
// segment (SPEC 4) gives the same reference label (1e-12) and the same answer of the plan's method and of the
// scene network (1e-6).
#pragma once

#include <string>

#include "core/conventions.hpp"
#include "search/local_search.hpp"
#include "study/scene_pairs.hpp"

namespace contactnn::study {

struct NodeOrderCheck {
  long pairs = 0;             ///< quad4 pairs checked (x 8 orders)
  double label = 0.0;         ///< largest difference of the reference's coordinates from the identity order's
  double label_gap = 0.0;     ///< the same for the gap (its sign follows the orientation)
  double plan_method = 0.0;   ///< the plan's method
  double scene_network = -1;  ///< the scene network alone (-1: none)
  bool passed = true;         ///< label <= 1e-12 (relative to 1) and the methods <= 1e-6
  [[nodiscard]] std::string summary() const;
};

/// Step 6 on every quad4 pair of `pairs` (any location): the reference labels and, through lib/search, `plan`
/// and `scene` (nullable) in the 8 node orders.
[[nodiscard]] NodeOrderCheck check_node_orders(const ScenePairs& pairs, SurfaceKind surface,
                                               const search::LocalSearch& plan,
                                               const search::LocalSearch* scene);

}  // namespace contactnn::study
