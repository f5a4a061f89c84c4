#include "contact/nearest_node.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <nanoflann.hpp>

#include "contact/point_cloud.hpp"

namespace contactnn::contact {

double squared_distance(const Vec3& a, const Vec3& b) {
  const double dx = a.x() - b.x();
  const double dy = a.y() - b.y();
  const double dz = a.z() - b.z();
  return (dx * dx + dy * dy) + dz * dz;
}

int nearest_point_brute_force(std::span<const Vec3> points, const Vec3& query) {
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double d2 = squared_distance(points[i], query);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

namespace {

// Points within this relative margin of the best squared distance seen are kept as candidates: far above
// the rounding by which nanoflann's distances may differ from squared_distance, far below any real gap.
constexpr double kTieMargin = 1e-9;

/// A nanoflann result set that keeps every point near the best distance seen so far (not only one), so
/// that exact ties and rounding-level near-ties all reach the final ranking.
struct NearCandidates {
  using DistanceType = double;
  using IndexType = std::uint32_t;
  double best = std::numeric_limits<double>::infinity();
  std::vector<std::uint32_t> indices;

  [[nodiscard]] std::size_t size() const { return indices.size(); }
  [[nodiscard]] bool full() const { return true; }
  // nanoflann adds a point only if its distance is strictly below worstDist(): the smallest normal double
  // on top keeps points at distance exactly 0 when the best is 0.
  [[nodiscard]] double worstDist() const {
    return best * (1.0 + kTieMargin) + std::numeric_limits<double>::min();
  }
  bool addPoint(double d2, std::uint32_t index) {
    if (d2 < worstDist()) {
      indices.push_back(index);
      if (d2 < best) best = d2;
    }
    return true;
  }
};

}  // namespace

struct NearestPointTree::Index {
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                   PointCloud, 3, std::uint32_t>;
  PointCloud cloud;
  Tree tree;
  explicit Index(const std::vector<Vec3>* points)
      : cloud{points}, tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
};

NearestPointTree::NearestPointTree(std::span<const Vec3> points)
    : points_(points.begin(), points.end()), index_(std::make_unique<Index>(&points_)) {}

NearestPointTree::~NearestPointTree() = default;

int NearestPointTree::nearest(const Vec3& query) const {
  if (points_.empty() || !query.allFinite()) return -1;
  NearCandidates candidates;
  const double q[3] = {query.x(), query.y(), query.z()};
  index_->tree.radiusSearchCustomCallback(q, candidates);
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::uint32_t i : candidates.indices) {
    const double d2 = squared_distance(points_[i], query);
    if (d2 < best_d2 || (d2 == best_d2 && static_cast<int>(i) < best)) {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace contactnn::contact
