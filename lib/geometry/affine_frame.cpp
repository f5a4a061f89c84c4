#include "geometry/affine_frame.hpp"

#include <cmath>

namespace contactnn::geometry {

namespace {
// Relative size below which a length or a sine counts as zero: well above double rounding of O(1)
// normalised coordinates, far below any segment a mesh generator would produce.
constexpr double kRelativeZero = 1e-12;
}  // namespace

std::optional<AffineFrame> AffineFrame::from_nodes(const Vec3& a, const Vec3& b, const Vec3& d) {
  if (!a.allFinite() || !b.allFinite() || !d.allFinite()) return std::nullopt;
  const Vec3 ab = b - a;
  const Vec3 ad = d - a;
  const double length_ab = ab.norm();
  const double length_ad = ad.norm();
  if (!(length_ab > 0.0) || !std::isfinite(length_ab)) return std::nullopt;
  if (length_ab <= kRelativeZero * length_ad) return std::nullopt;
  const Vec3 e1 = ab / length_ab;
  const Vec3 normal = e1.cross(ad);  // |normal| = |AD| sin(angle at A)
  const double normal_length = normal.norm();
  if (!(normal_length > kRelativeZero * std::max(length_ad, length_ab))) return std::nullopt;
  const Vec3 e3 = normal / normal_length;
  const Vec3 e2 = e3.cross(e1);
  Eigen::Matrix3d rotation;
  rotation.row(0) = e1.transpose();
  rotation.row(1) = e2.transpose();
  rotation.row(2) = e3.transpose();
  return AffineFrame(a, rotation, 1.0 / length_ab);
}

NormaliseOutcome normalise(const Configuration& world, SurfaceKind kind) {
  const bool gregory = kind == SurfaceKind::kGregory;
  if (!world.is_finite(gregory)) return {std::nullopt, NormaliseFailure::kNonFinite};
  const auto frame = AffineFrame::from_nodes(world.nodes[0], world.nodes[1], world.nodes[3]);
  if (!frame) return {std::nullopt, NormaliseFailure::kDegenerate};

  Configuration local;
  for (int i = 0; i < 4; ++i) local.nodes[i] = frame->to_normalised(world.nodes[i]);
  // Exact by construction; writing them removes the rounding of the map from the fixed coordinates.
  local.nodes[0] = Vec3::Zero();
  local.nodes[1] = Vec3(1.0, 0.0, 0.0);
  local.nodes[3].z() = 0.0;
  local.slave = frame->to_normalised(world.slave);
  for (int i = 0; i < 4; ++i) local.normals[i] = Vec3::Zero();

  std::array<double, 16> features{};
  features[0] = local.nodes[2].x();
  features[1] = local.nodes[2].y();
  features[2] = local.nodes[2].z();
  features[3] = local.nodes[3].x();
  features[4] = local.nodes[3].y();
  features[5] = local.slave.x();
  features[6] = local.slave.y();
  features[7] = local.slave.z();
  if (gregory) {
    for (int i = 0; i < 4; ++i) {
      const double length = world.normals[i].norm();
      if (!(length > 0.0)) return {std::nullopt, NormaliseFailure::kDegenerate};
      const Vec3 n = frame->rotate(world.normals[i] / length);
      // A node normal parallel to the segment plane (or flipped) has no n_x/n_z feature.
      if (!(n.z() > kRelativeZero)) return {std::nullopt, NormaliseFailure::kDegenerate};
      local.normals[i] = n;
      features[8 + 2 * i] = n.x() / n.z();
      features[9 + 2 * i] = n.y() / n.z();
    }
  }
  return {NormalisedConfiguration{local, features, *frame}, NormaliseFailure::kDegenerate};
}

}  // namespace contactnn::geometry
