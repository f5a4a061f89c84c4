// nanoflann's dataset adaptor over a vector of points (the k-d trees of the nearest-node search over master
// nodes and of the reference surface search over face centres). Private to lib/contact.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/surface_point.hpp"

namespace contactnn::contact {

struct PointCloud {
  const std::vector<geometry::Vec3>* points = nullptr;
  [[nodiscard]] std::size_t kdtree_get_point_count() const { return points->size(); }
  [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return (*points)[i][static_cast<Eigen::Index>(dim)];
  }
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox&) const {
    return false;
  }
};

}  // namespace contactnn::contact
