// Independent checks of a scene's pairs, shared by the tests and the scene-check tool: the global search
// with the brute-force nearest node against the k-d tree's, and the labels against the dense-grid oracle
// of test_support.hpp (no lib code copied into it).
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "contact/global_search.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "test_support.hpp"

namespace contactnn::testing {

/// How many pairs differ between two searches of the same slaves (status, segment, node order, label
/// bits), and a description of the first difference.
struct SearchComparison {
  long differences = 0;
  std::string first;
};

inline SearchComparison compare_searches(std::span<const contact::NodeSegmentPair> a,
                                         std::span<const contact::NodeSegmentPair> b) {
  SearchComparison c;
  if (a.size() != b.size()) {
    c.differences = static_cast<long>(std::max(a.size(), b.size()));
    c.first = "different pair counts";
    return c;
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto& p = a[i];
    const auto& q = b[i];
    const bool same = p.slave_id == q.slave_id && p.status == q.status && p.nearest_node == q.nearest_node &&
                      p.segment == q.segment && p.nodes == q.nodes && p.label.status == q.label.status &&
                      p.label.param == q.label.param && p.label.gap == q.label.gap;
    if (!same) {
      if (c.differences == 0) {
        c.first = "slave " + std::to_string(p.slave_id) + ": nearest node " + std::to_string(p.nearest_node) +
                  " vs " + std::to_string(q.nearest_node) + ", segment " + std::to_string(p.segment) +
                  " vs " + std::to_string(q.segment);
      }
      ++c.differences;
    }
  }
  return c;
}

/// Labels of found pairs with status ok against oracle_closest_point, in world orientation and scale
/// shifted so that A is the origin. The oracle's finite-difference Newton is unconstrained, so it lands on
/// the stationary point also when that lies on an edge or a corner (slave nodes of matching meshes); pairs
/// whose oracle point lies outside the domain by more than 1e-6 (a minimum on the boundary that is not a
/// stationary point) have nothing to compare and are only counted.
struct OracleComparison {
  long compared = 0;
  long on_boundary = 0;
  double max_difference = 0.0;  ///< max over compared pairs of max(|d param 0|, |d param 1|)
  long nearer_than_label = 0;   ///< oracle points nearer S than the label's by more than rounding
  long worst_slave = 0;
};

inline OracleComparison compare_with_oracle(std::span<const contact::NodeSegmentPair> pairs, SurfaceKind kind,
                                            int grid = 201) {
  OracleComparison c;
  const ParamDomain d = param_domain(kind);
  for (const auto& p : pairs) {
    if (p.status != contact::PairStatus::kFound || p.label.status != Status::kOk) continue;
    std::array<Vec3, 4> shifted = p.config.nodes;
    for (auto& node : shifted) node -= p.config.nodes[0];
    const Vec3 s = p.config.slave - p.config.nodes[0];
    double length = 0.0;
    for (const auto& node : shifted) length = std::max(length, node.norm());
    const auto check = [&](const auto& surface) {
      const auto oracle = oracle_closest_point(surface, s, grid);
      const double margin = 1e-6 * (d.hi - d.lo);
      const double oracle_d2 = (s - surface.position(oracle[0], oracle[1])).squaredNorm();
      const double label_d2 = (s - surface.position(p.label.param[0], p.label.param[1])).squaredNorm();
      if (label_d2 > oracle_d2 + 1e-12 * length * length) ++c.nearer_than_label;
      if (oracle[0] < d.lo - margin || oracle[0] > d.hi + margin || oracle[1] < d.lo - margin ||
          oracle[1] > d.hi + margin) {
        ++c.on_boundary;
        return;
      }
      const double diff =
          std::max(std::abs(oracle[0] - p.label.param[0]), std::abs(oracle[1] - p.label.param[1]));
      if (diff > c.max_difference) {
        c.max_difference = diff;
        c.worst_slave = p.slave_id;
      }
      ++c.compared;
    };
    if (kind == SurfaceKind::kGregory) {
      check(geometry::GregoryPatch(shifted, p.config.normals));
    } else {
      check(geometry::BilinearPatch(shifted));
    }
  }
  return c;
}

}  // namespace contactnn::testing
