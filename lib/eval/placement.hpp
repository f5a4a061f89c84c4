// World coordinates for the evaluation: a dataset stores configurations in the normalised frame
// (SPEC 4); every method of the study starts from world coordinates, as an FE code hands them over.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "core/conventions.hpp"
#include "geometry/configuration.hpp"

namespace contactnn::eval {

/// The configuration whose normalised features are `features` (feature_count(kind) values, kFeatureNames
/// order): A = (0,0,0), B = (1,0,0), C = (xc,yc,zc), D = (xd,yd,0), S = (xs,ys,zs); for Gregory the unit
/// node normal with n_x/n_z = p, n_y/n_z = q, i.e. (p, q, 1) / |(p, q, 1)|. normalise() of the result gives
/// back `features` up to rounding. Bilinear normals are zero.
[[nodiscard]] geometry::Configuration configuration_from_features(SurfaceKind kind, const double* features);

/// A similarity map x -> scale * rotation * x + translation (a proper rotation, scale > 0).
struct Placement {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  geometry::Vec3 translation = geometry::Vec3::Zero();
  double scale = 1.0;
};

/// A random placement, a pure function of (seed, index) so that row i gets the same placement on any
/// thread count: rotation uniform on SO(3) (Shoemake's unit quaternion), scale log-uniform in [1e-2, 1e2],
/// translation uniform in [-10, 10]^3 times the scale (a mesh's size and position, without the
/// cancellation of a translation many orders above the segment size).
[[nodiscard]] Placement random_placement(std::uint64_t seed, std::uint64_t index);

/// Nodes and slave mapped by `p`; normals rotated only (their length is kept).
[[nodiscard]] geometry::Configuration place(const geometry::Configuration& config, const Placement& p);

}  // namespace contactnn::eval
