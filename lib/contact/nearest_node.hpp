// The master node nearest a slave node: a k-d tree (nanoflann) and the brute-force scan it must agree with.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "geometry/surface_point.hpp"

namespace contactnn::contact {

using geometry::Vec3;

/// |a - b|^2 as (dx dx + dy dy) + dz dz: the one formula both searches compare, so they rank ties alike.
[[nodiscard]] double squared_distance(const Vec3& a, const Vec3& b);

/// Index of the point nearest `query` by squared_distance, the lowest index among exact ties; -1 if
/// `points` is empty. O(n): the oracle of the tree below.
[[nodiscard]] int nearest_point_brute_force(std::span<const Vec3> points, const Vec3& query);

/// A k-d tree over a fixed set of points (copied), answering exactly what nearest_point_brute_force answers.
/// nanoflann finds every point within a relative 1e-9 of the smallest squared distance it sees; those are
/// then ranked by squared_distance with the lowest index winning ties, so the answer does not depend on
/// nanoflann's own rounding or visiting order. (A mesh's nodes in increasing id make "lowest index" the
/// lowest node id.) Queries are const and may run concurrently.
class NearestPointTree {
 public:
  explicit NearestPointTree(std::span<const Vec3> points);
  ~NearestPointTree();
  NearestPointTree(const NearestPointTree&) = delete;
  NearestPointTree& operator=(const NearestPointTree&) = delete;

  /// Same contract as nearest_point_brute_force. A non-finite query gives -1.
  [[nodiscard]] int nearest(const Vec3& query) const;

 private:
  struct Index;
  std::vector<Vec3> points_;
  std::unique_ptr<Index> index_;
};

}  // namespace contactnn::contact
