// The normalised frame of paper Section 4 (SPEC 4) and its inverse.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "core/conventions.hpp"
#include "geometry/configuration.hpp"

namespace contactnn::geometry {

/// y = scale * R (x - origin): A to the origin, B onto +x at distance 1, D into the xy-plane with
/// y_D > 0. R is a proper rotation (det +1), so orientation, the normal side and the gap sign are kept;
/// local coordinates are invariant under the map.
class AffineFrame {
 public:
  /// The frame of a segment from its nodes A, B and D. std::nullopt when it does not exist:
  /// |AB| is zero (relative to |AD|) or D lies on the line AB (the segment is degenerate).
  /// Non-finite inputs also give std::nullopt.
  [[nodiscard]] static std::optional<AffineFrame> from_nodes(const Vec3& a, const Vec3& b, const Vec3& d);

  /// World point -> normalised point.
  [[nodiscard]] Vec3 to_normalised(const Vec3& x) const { return scale_ * (rotation_ * (x - origin_)); }
  /// Normalised point -> world point.
  [[nodiscard]] Vec3 to_world(const Vec3& y) const { return origin_ + rotation_.transpose() * (y / scale_); }
  /// Rotates a direction (a normal) into the frame; lengths are kept (no scaling).
  [[nodiscard]] Vec3 rotate(const Vec3& direction) const { return rotation_ * direction; }

  /// Normalised length per world length: 1 / |AB|.
  [[nodiscard]] double scale() const { return scale_; }
  [[nodiscard]] const Eigen::Matrix3d& rotation() const { return rotation_; }
  [[nodiscard]] const Vec3& origin() const { return origin_; }

 private:
  AffineFrame(const Vec3& origin, const Eigen::Matrix3d& rotation, double scale)
      : origin_(origin), rotation_(rotation), scale_(scale) {}
  Vec3 origin_;
  Eigen::Matrix3d rotation_;  ///< rows: unit AB, in-plane normal to AB towards D, segment normal
  double scale_;
};

/// A configuration mapped into the normalised frame, with the network inputs of SPEC 4.
struct NormalisedConfiguration {
  Configuration config;              ///< nodes, slave and (rotated, unit) normals in the normalised frame
  std::array<double, 16> features;   ///< xc yc zc xd yd xs ys zs, then (Gregory) n_x/n_z, n_y/n_z for A..D
  AffineFrame frame;
};

/// Why a configuration could not be normalised.
enum class NormaliseFailure { kNonFinite, kDegenerate };

/// Maps a world configuration into the normalised frame. For Gregory the normals are normalised to unit
/// length and rotated; a normal with zero length, or with n_z <= 0 in the frame (pointing away from or
/// parallel to the segment), makes the configuration degenerate. So does a segment that is collapsed up
/// to the rounding of its world coordinates (is_degenerate_segment with noise eps * max|x| * scale): e.g.
/// collinear nodes 1e5 element sizes from the origin, whose rounding leaves an area of ~1e-11 in the frame.
/// @return the normalised configuration, or the reason it does not exist.
struct NormaliseOutcome {
  std::optional<NormalisedConfiguration> value;
  NormaliseFailure failure = NormaliseFailure::kDegenerate;
};
[[nodiscard]] NormaliseOutcome normalise(const Configuration& world, SurfaceKind kind);

}  // namespace contactnn::geometry
