// The normalised frame of paper Section 4 (SPEC 4) and its inverse.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "core/conventions.hpp"
#include "core/symmetry.hpp"
#include "geometry/configuration.hpp"

namespace contactnn::geometry {

/// y = scale * R (x - origin): A to the origin, B onto +x at distance 1, D into the xy-plane with
/// y_D > 0. R is orthogonal: from_nodes gives a proper rotation (det +1, the normal (B-A) x (D-A) along +z);
/// reflected_z() the same with z reversed (det -1), which the canonical orientation of normalise() uses.
/// Local coordinates are invariant under either.
class AffineFrame {
 public:
  /// The identity map (A at the origin, unit scale); from_nodes gives a segment's frame.
  AffineFrame() : origin_(Vec3::Zero()), rotation_(Eigen::Matrix3d::Identity()), scale_(1.0) {}
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

  /// The same frame with its z axis reversed (a reflection of space: z -> -z in the frame).
  [[nodiscard]] AffineFrame reflected_z() const {
    Eigen::Matrix3d r = rotation_;
    r.row(2) = -r.row(2);
    return AffineFrame(origin_, r, scale_);
  }

  /// Normalised length per world length: 1 / |AB|.
  [[nodiscard]] double scale() const { return scale_; }
  [[nodiscard]] const Eigen::Matrix3d& rotation() const { return rotation_; }
  [[nodiscard]] const Vec3& origin() const { return origin_; }

 private:
  AffineFrame(const Vec3& origin, const Eigen::Matrix3d& rotation, double scale)
      : origin_(origin), rotation_(rotation), scale_(scale) {}
  Vec3 origin_;
  Eigen::Matrix3d rotation_;  ///< rows: unit AB, in-plane normal to AB towards D, +-segment normal
  double scale_;
};

/// The symmetry of the square that brings `nodes` to the paper's canonical configuration for slave `slave`
/// (SPEC 4): canonical A is the node nearest S (the first in the caller's order on a tie); then the mirror
/// when |AD| > |AB|. Where SPEC 4 is silent, |AD| = |AB|, the mirror is taken when S lies nearer the line AD
/// than the line AB (so that S ends nearer the canonical AB), which makes the choice the same for every node
/// order of the segment. Lengths within a relative 1e-12 plus the rounding of the world coordinates
/// (16 eps max|x|) are a tie, so that the choice does not depend on where the segment is placed; the lengths
/// are those of the configuration scaled by a power of two (exact), so that the choice does not depend on the
/// scale either (no square under- or overflows, from 1e-300 up to 1e308).
[[nodiscard]] SquareSymmetry canonical_symmetry(const std::array<Vec3, 4>& nodes, const Vec3& slave);

/// Every symmetry that canonical_symmetry could have chosen if its ties went another way: one per node tied
/// for nearest (in the caller's order, so symmetries[0] is canonical_symmetry's), two for a node with
/// |AB| = |AD| and S on the diagonal. count >= 1.
struct CanonicalSymmetries {
  std::array<SquareSymmetry, 8> symmetries{};
  int count = 0;
};
[[nodiscard]] CanonicalSymmetries canonical_symmetries(const std::array<Vec3, 4>& nodes, const Vec3& slave);

/// A configuration mapped into the canonical normalised frame, with the network inputs of SPEC 4.
///
/// Canonical means: the nodes relabelled by `symmetry` (A nearest S, |AD| <= |AB|), then the frame of SPEC 4
/// built on them, and then one choice SPEC 4 leaves open, the orientation of the frame's z axis: z_S >= 0
/// (with z_S = 0, up to 1e-12 plus the inputs' rounding: z_C >= 0; both 0: a tie, see canonical_forms).
/// Reflecting a whole configuration through the plane of A, B, D changes no local coordinate (an isometry;
/// for Gregory the reflected node normals are then all reversed, which leaves the patch unchanged, SPEC 3),
/// so this is a symmetry of the problem like the 8 of the square. It makes the network input the same for a
/// segment given in either orientation (node order A, B, C, D or A, D, C, B, with or without a reflection of
/// space) and halves the domain a network must learn. The caller's gap sign (its own orientation, SPEC 2) is
/// restored by `orientation`.
struct NormalisedConfiguration {
  Configuration config{};             ///< canonical nodes, slave and (rotated, unit) normals in the frame
  std::array<double, 16> features{};  ///< xc yc zc xd yd xs ys zs, then (Gregory) n_x/n_z, n_y/n_z for A..D
  AffineFrame frame;                  ///< world -> canonical normalised frame (a rotation or a reflection)
  SquareSymmetry symmetry;            ///< canonical node i is the caller's node symmetry.caller_node(i)
  /// +1 or -1: the caller's gap (along its own P_xi x P_eta) is orientation * (canonical gap) /
  /// frame.scale().
  double orientation = 1.0;
  /// False when the canonical corner A has no frame (B, A, D collinear: a straight angle) and another
  /// corner's frame was taken: the projection is still right, but the features are not those a network was
  /// trained on.
  bool canonical = true;
  /// z_S = z_C = 0 (to the tolerance above): the other orientation of z is canonical too (for Gregory the
  /// features differ: slopes).
  bool z_tie = false;

  /// Canonical local coordinates (of config) -> the caller's, in `kind`'s parameters.
  [[nodiscard]] std::array<double, 2> to_caller(const std::array<double, 2>& param, SurfaceKind kind) const {
    return symmetry.to_caller(param, kind);
  }
  /// A gap in the canonical frame (normalised units, along the canonical P_s x P_t) -> the caller's gap in
  /// world units.
  [[nodiscard]] double gap_to_caller(double canonical_gap) const {
    return orientation * canonical_gap / frame.scale();
  }
};

/// Why a configuration could not be normalised.
enum class NormaliseFailure { kNonFinite, kDegenerate };

/// Maps a world configuration, in any node order, into the canonical normalised frame (see
/// NormalisedConfiguration). For Gregory the normals are normalised to unit length and rotated; a normal with
/// zero length, one (almost) parallel to the segment plane, or normals on both sides of it make the
/// configuration degenerate; normals all on the back side are all reversed (the same patch, SPEC 3). So does
/// a segment that is collapsed up to the rounding of its world coordinates (is_degenerate_segment with noise
/// eps * max|x| * scale): e.g. collinear nodes 1e5 element sizes from the origin, whose rounding leaves an
/// area of ~1e-11 in the frame. When the canonical corner has a straight angle (180 degrees: a triangle), the
/// next corner (counter-clockwise in the canonical order) with a frame is taken and `canonical` is false; a
/// zero angle there (D on the ray AB: the segment folds onto itself) is degenerate.
/// @return the normalised configuration, or the reason it does not exist.
struct NormaliseOutcome {
  std::optional<NormalisedConfiguration> value;
  NormaliseFailure failure = NormaliseFailure::kDegenerate;
};
[[nodiscard]] NormaliseOutcome normalise(const Configuration& world, SurfaceKind kind);

/// normalise() and every other canonical configuration it ties with: another node as near S, |AB| = |AD|
/// with S on the diagonal, and (Gregory) z_S = z_C = 0. A query on a tie has several canonical forms that
/// are the same problem; SPEC 4 takes the first in the caller's order, which makes a network's answer depend
/// on the node order by the network's own error. Averaging a network over all of them does not (matching
/// meshes put slave nodes exactly midway between master nodes). form[0] is normalise()'s; count 0 with
/// `failure` when it fails.
inline constexpr int kMaxCanonicalForms = 16;
struct CanonicalForms {
  std::array<NormalisedConfiguration, kMaxCanonicalForms> form;
  int count = 0;
  NormaliseFailure failure = NormaliseFailure::kDegenerate;
};
[[nodiscard]] CanonicalForms canonical_forms(const Configuration& world, SurfaceKind kind);

}  // namespace contactnn::geometry
