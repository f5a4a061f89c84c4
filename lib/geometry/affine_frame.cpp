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

CanonicalSymmetries canonical_symmetries(const std::array<Vec3, 4>& world_nodes, const Vec3& world_slave) {
  // The choice must not depend on the scale of the coordinates (SPEC 6: any unit). Near 1e+-300 the
  // differences below overflow (no node would be nearest) and the cross products of the |AB| = |AD| test
  // under- or overflow (the mirror would depend on the scale), so the configuration is first scaled by the
  // power of two that brings its largest coordinate into [0.5, 1): exact, so every comparison below is the
  // one of the unscaled configuration in exact arithmetic, and nothing under- or overflows.
  double largest = world_slave.cwiseAbs().maxCoeff();
  for (const Vec3& node : world_nodes) largest = std::max(largest, node.cwiseAbs().maxCoeff());
  int exponent = 0;
  if (largest > 0.0 && std::isfinite(largest)) (void)std::frexp(largest, &exponent);
  std::array<Vec3, 4> nodes;
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c)
      nodes[static_cast<std::size_t>(i)][c] =
          std::ldexp(world_nodes[static_cast<std::size_t>(i)][c], -exponent);
  }
  Vec3 slave;
  for (int c = 0; c < 3; ++c) slave[c] = std::ldexp(world_slave[c], -exponent);
  largest = std::ldexp(largest, -exponent);

  // Two lengths count as equal when they differ by less than a relative 1e-12 plus the rounding the world
  // coordinates already carry (eps * max|x| each): an exact tie stays a tie wherever the segment is placed,
  // instead of being decided by the rounding of the placement.
  const double noise = 16.0 * std::numeric_limits<double>::epsilon() * largest;
  const auto tie = [&](double x, double y) { return std::abs(x - y) <= 1e-12 * std::max(x, y) + noise; };

  CanonicalSymmetries result;
  std::array<double, 4> distance{};
  for (int i = 0; i < 4; ++i)
    distance[static_cast<std::size_t>(i)] = length_of(slave - nodes[static_cast<std::size_t>(i)]);
  const double nearest = *std::min_element(distance.begin(), distance.end());
  for (int r = 0; r < 4; ++r) {
    if (!tie(distance[r], nearest)) continue;  // the nearest nodes, in the caller's order (SPEC 4: the first)
    const Vec3& a = nodes[static_cast<std::size_t>(r)];
    const Vec3 ab = nodes[static_cast<std::size_t>((r + 1) % 4)] - a;
    const Vec3 ad = nodes[static_cast<std::size_t>((r + 3) % 4)] - a;
    const double length_ab = length_of(ab), length_ad = length_of(ad);
    auto& out = result.symmetries;
    if (!tie(length_ad, length_ab)) {
      out[static_cast<std::size_t>(result.count++)] = SquareSymmetry{r, length_ad > length_ab};
      continue;
    }
    // |AB| = |AD|: mirror when S is nearer the line AD than the line AB. The same numbers in either node
    // order; on the diagonal itself both orders are canonical.
    const Vec3 as = slave - a;
    const double to_ab = length_of(as.cross(ab)) / length_ab, to_ad = length_of(as.cross(ad)) / length_ad;
    if (!tie(to_ad, to_ab)) {
      out[static_cast<std::size_t>(result.count++)] = SquareSymmetry{r, to_ad < to_ab};
    } else {
      out[static_cast<std::size_t>(result.count++)] = SquareSymmetry{r, false};
      out[static_cast<std::size_t>(result.count++)] = SquareSymmetry{r, true};
    }
  }
  return result;
}

SquareSymmetry canonical_symmetry(const std::array<Vec3, 4>& nodes, const Vec3& slave) {
  return canonical_symmetries(nodes, slave).symmetries[0];
}

namespace {

/// normalise() with the node order given by `symmetry`; `other_z` takes the other orientation of z on a tie
/// (z_S = z_C = 0).
NormaliseOutcome normalise_as(const Configuration& world, SurfaceKind kind, const SquareSymmetry& symmetry,
                              bool other_z = false) {
  const bool gregory = kind == SurfaceKind::kGregory;
  // 1. The caller's nodes relabelled by a symmetry of the square.
  Configuration canonical;
  for (int i = 0; i < 4; ++i) {
    const auto from = static_cast<std::size_t>(symmetry.caller_node(i));
    canonical.nodes[static_cast<std::size_t>(i)] = world.nodes[from];
    canonical.normals[static_cast<std::size_t>(i)] = world.normals[from];
  }
  canonical.slave = world.slave;

  // 2. The frame of SPEC 4 on the canonical nodes.
  auto frame = AffineFrame::from_nodes(canonical.nodes[0], canonical.nodes[1], canonical.nodes[3]);
  if (!frame) return {std::nullopt, NormaliseFailure::kDegenerate};
  Configuration local;
  // A and B are exact by construction (not mapped: that would only add the map's rounding), and so is z_D.
  local.nodes[0] = Vec3::Zero();
  local.nodes[1] = Vec3(1.0, 0.0, 0.0);
  local.nodes[2] = frame->to_normalised(canonical.nodes[2]);
  local.nodes[3] = frame->to_normalised(canonical.nodes[3]);
  local.nodes[3].z() = 0.0;
  local.slave = frame->to_normalised(canonical.slave);

  // 3. The orientation of z: S on the +z side (on the plane: C on it). Negation is exact, so a segment given
  //    in the other orientation reaches bit for bit the same configuration. A height within 1e-12 plus the
  //    rounding of the world coordinates (slave included) counts as 0: a slave on a flat master or on one of
  //    its nodes must not be oriented by the rounding of its placement.
  double largest_all = world.slave.cwiseAbs().maxCoeff();
  for (const Vec3& node : world.nodes) largest_all = std::max(largest_all, node.cwiseAbs().maxCoeff());
  const double z_tolerance =
      1e-12 + 16.0 * std::numeric_limits<double>::epsilon() * largest_all * frame->scale();
  const bool s_on_plane = std::abs(local.slave.z()) <= z_tolerance;
  const bool z_tie = s_on_plane && std::abs(local.nodes[2].z()) <= z_tolerance;
  const bool flip = z_tie ? other_z : (s_on_plane ? local.nodes[2].z() < 0.0 : local.slave.z() < 0.0);
  if (flip) {
    frame = frame->reflected_z();
    local.nodes[2].z() = -local.nodes[2].z();
    local.slave.z() = -local.slave.z();
  }
  // The caller's P_xi x P_eta is the canonical one times the mirror's orientation, seen in a frame whose z
  // axis the flip may have reversed.
  const double orientation = symmetry.orientation() * (flip ? -1.0 : 1.0);

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
    // A node normal (almost) parallel to the segment plane has no n_x/n_z feature. The frame's own normal is
    // known to the rounding of the coordinates only (noise above): an |n_z| below it is zero.
    const double min_nz = std::max(kRelativeZero, 16.0 * noise);
    int front = 0, back = 0;
    for (int i = 0; i < 4; ++i) {
      // Any positive length (SPEC 6), 1e-300 and 1e300 included.
      const double length = length_of(canonical.normals[i]);
      if (!(length > 0.0)) return {std::nullopt, NormaliseFailure::kDegenerate};
      local.normals[i] = frame->rotate(canonical.normals[i] / length);
      front += local.normals[i].z() > min_nz ? 1 : 0;
      back += local.normals[i].z() < -min_nz ? 1 : 0;
    }
    // All on the back side: the same patch as all reversed (SPEC 3 builds it from n n^T and from pairs of
    // cross products with n, each unchanged by n -> -n). On both sides, or in the plane: no patch.
    if (back == 4) {
      for (Vec3& n : local.normals) n = -n;
    } else if (front != 4) {
      return {std::nullopt, NormaliseFailure::kDegenerate};
    }
    for (int i = 0; i < 4; ++i) {
      const Vec3& n = local.normals[i];
      features[8 + 2 * i] = n.x() / n.z();
      features[9 + 2 * i] = n.y() / n.z();
    }
  }
  return {NormalisedConfiguration{local, features, *frame, symmetry, orientation, true, z_tie},
          NormaliseFailure::kDegenerate};
}

}  // namespace

NormaliseOutcome normalise(const Configuration& world, SurfaceKind kind) {
  if (!world.is_finite(kind == SurfaceKind::kGregory)) return {std::nullopt, NormaliseFailure::kNonFinite};
  const SquareSymmetry symmetry = canonical_symmetry(world.nodes, world.slave);
  NormaliseOutcome outcome = normalise_as(world, kind, symmetry);
  if (outcome.value || outcome.failure != NormaliseFailure::kDegenerate) return outcome;
  // A usable segment whose canonical corner A has a straight angle (B, A, D collinear, B and D on opposite
  // sides of A: a triangle) has no frame there; the next corner that has one serves, marked as not canonical.
  const Vec3& a = world.nodes[static_cast<std::size_t>(symmetry.caller_node(0))];
  const Vec3& b = world.nodes[static_cast<std::size_t>(symmetry.caller_node(1))];
  const Vec3& d = world.nodes[static_cast<std::size_t>(symmetry.caller_node(3))];
  if (!((b - a).dot(d - a) < 0.0)) return outcome;
  for (int k = 1; k < 4 && !outcome.value; ++k) {
    SquareSymmetry next = symmetry;
    next.rotation = (symmetry.rotation + (symmetry.mirror ? 4 - k : k)) % 4;
    outcome = normalise_as(world, kind, next);
    if (outcome.value) outcome.value->canonical = false;
  }
  return outcome;
}

CanonicalForms canonical_forms(const Configuration& world, SurfaceKind kind) {
  CanonicalForms forms;
  NormaliseOutcome first = normalise(world, kind);
  forms.failure = first.failure;
  if (!first.value) return forms;
  forms.form[forms.count++] = *first.value;
  if (!first.value->canonical) return forms;  // a fallback corner: no canonical form to tie with
  const CanonicalSymmetries tied = canonical_symmetries(world.nodes, world.slave);
  const bool z_ties = kind == SurfaceKind::kGregory && first.value->z_tie;
  for (int k = 0; k < tied.count; ++k) {
    for (int other_z = 0; other_z <= (z_ties ? 1 : 0); ++other_z) {
      if (k == 0 && other_z == 0) continue;  // the first form
      NormaliseOutcome o =
          normalise_as(world, kind, tied.symmetries[static_cast<std::size_t>(k)], other_z != 0);
      if (o.value) forms.form[static_cast<std::size_t>(forms.count++)] = *o.value;
    }
  }
  return forms;
}

}  // namespace contactnn::geometry
