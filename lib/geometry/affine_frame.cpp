#include "geometry/affine_frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/segment_checks.hpp"

namespace contactnn::geometry {

namespace {
// Relative size below which a length or a sine counts as zero: well above double rounding of O(1)
// normalised coordinates, far below any segment a mesh generator would produce.
constexpr double kRelativeZero = 1e-12;

/// |v| for any finite v: the plain norm squares the components, which under- or overflows for lengths
/// beyond about 1e+-154 (world coordinates in any unit, SPEC 6); there Eigen's scaled norm is used.
double length_of(const Vec3& v) {
  const double plain = v.norm();
  return plain > 1e-150 && plain < 1e150 ? plain : v.stableNorm();
}
}  // namespace

std::optional<AffineFrame> AffineFrame::from_nodes(const Vec3& a, const Vec3& b, const Vec3& d) {
  if (!a.allFinite() || !b.allFinite() || !d.allFinite()) return std::nullopt;
  const Vec3 ab = b - a;
  const Vec3 ad = d - a;
  const double length_ab = length_of(ab);
  const double length_ad = length_of(ad);
  if (!(length_ab > 0.0) || !std::isfinite(length_ab)) return std::nullopt;
  if (length_ab <= kRelativeZero * length_ad) return std::nullopt;
  const Vec3 e1 = ab / length_ab;
  const Vec3 normal = e1.cross(ad);  // |normal| = |AD| sin(angle at A)
  const double normal_length = length_of(normal);
  if (!(normal_length > kRelativeZero * std::max(length_ad, length_ab))) return std::nullopt;
  // Near-collinear A, B, D: the cross product's rounding (eps |AD|) is large against |normal|, and e3 comes
  // out up to eps / sin(angle at A) off perpendicular to e1; one Gram-Schmidt step keeps the map a rotation.
  Vec3 e3 = normal / normal_length;
  e3 = (e3 - e3.dot(e1) * e1).normalized();
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
  // A and B are exact by construction (not mapped: that would only add the map's rounding), and so is z_D.
  local.nodes[0] = Vec3::Zero();
  local.nodes[1] = Vec3(1.0, 0.0, 0.0);
  local.nodes[2] = frame->to_normalised(world.nodes[2]);
  local.nodes[3] = frame->to_normalised(world.nodes[3]);
  local.nodes[3].z() = 0.0;
  local.slave = frame->to_normalised(world.slave);
  // Each world coordinate carries rounding eps |x|: in the frame, eps * max|x| * scale. Far from the origin
  // that exceeds is_degenerate_segment's relative thresholds, and a segment collapsed in exact arithmetic
  // (collinear nodes) keeps an area at that level; it is degenerate whatever its position.
  double largest = 0.0;
  for (const Vec3& node : world.nodes) largest = std::max(largest, node.cwiseAbs().maxCoeff());
  const double noise = std::numeric_limits<double>::epsilon() * largest * frame->scale();
  if (is_degenerate_segment(local.nodes, noise)) return {std::nullopt, NormaliseFailure::kDegenerate};
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
      // Any positive length (SPEC 6), 1e-300 and 1e300 included.
      const double length = length_of(world.normals[i]);
      if (!(length > 0.0)) return {std::nullopt, NormaliseFailure::kDegenerate};
      const Vec3 n = frame->rotate(world.normals[i] / length);
      // A node normal parallel to the segment plane (or flipped) has no n_x/n_z feature. The frame's own
      // normal is known to the rounding of the coordinates only (noise above): an n_z below it is zero.
      if (!(n.z() > std::max(kRelativeZero, 16.0 * noise))) return {std::nullopt, NormaliseFailure::kDegenerate};
      local.normals[i] = n;
      features[8 + 2 * i] = n.x() / n.z();
      features[9 + 2 * i] = n.y() / n.z();
    }
  }
  return {NormalisedConfiguration{local, features, *frame}, NormaliseFailure::kDegenerate};
}

}  // namespace contactnn::geometry
