// lib/search/canonical_frame.h against its reference, geometry::normalise and
// geometry::TrainingDomain::contains: random configurations in any node order and placement, the tie rules,
// and the extreme cases of tests/extremes (scales, translations, collapsed and folded segments, straight
// angles, non-finite inputs, Gregory normals of any length, in the plane or on both sides). Also: the kernel
// compiled as C99.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "geometry/affine_frame.hpp"
#include "geometry/domain.hpp"
#include "search/canonical_frame.h"
#include "search/embedded_sources.hpp"
#include "search/network_model.hpp"
#include "search/random_queries.hpp"

extern "C" void contactnn_canonicalise_c99(int n, int gregory, const double* in, double* f, double* nrm,
                                           double* info);
extern "C" int contactnn_forms_c99(const double* x, int gregory, double* f, double* nrm, double* info);

namespace contactnn::search {
namespace {

using geometry::Configuration;
using geometry::Vec3;
using testing::random_order;

const std::array<Vec3, 4> kNoNormals = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};

struct KernelResult {
  int status = 0;
  SquareSymmetry symmetry;
  double orientation = 0.0;
  double scale = 0.0;
  std::array<double, 16> features{};
  std::array<double, 12> normals{};
};

/// The raw block of configs first .. first + n - 1 (SPEC 6 rows of `kind`, lane l of value k at [k n + l], 27
/// rows allocated), the lanes past the end filled with the first config.
std::vector<double> raw_block(const std::vector<Configuration>& configs, std::size_t first, std::size_t n,
                              SurfaceKind kind) {
  std::vector<double> in(27 * n);
  for (std::size_t l = 0; l < n; ++l) {
    std::vector<double> row;
    testing::append_raw(configs[first + l < configs.size() ? first + l : 0], kind, row);
    for (std::size_t k = 0; k < row.size(); ++k) in[k * n + l] = row[k];
  }
  return in;
}

/// Runs the kernel on `configs` as blocks of `lanes` lanes (the last block padded with the first config).
std::vector<KernelResult> run_kernel(const std::vector<Configuration>& configs, SurfaceKind kind, int lanes,
                                     bool c99 = false) {
  const bool gregory = kind == SurfaceKind::kGregory;
  std::vector<KernelResult> results;
  for (std::size_t first = 0; first < configs.size(); first += static_cast<std::size_t>(lanes)) {
    const std::vector<double> in = raw_block(configs, first, static_cast<std::size_t>(lanes), kind);
    std::vector<double> f(16 * static_cast<std::size_t>(lanes)), nrm(12 * static_cast<std::size_t>(lanes)),
        info(CNN_CF_INFO_ROWS * static_cast<std::size_t>(lanes));
    if (c99) {
      contactnn_canonicalise_c99(lanes, gregory ? 1 : 0, in.data(), f.data(), nrm.data(), info.data());
    } else {
      cnn_canonicalise_block(lanes, gregory ? 1 : 0, in.data(), f.data(), nrm.data(), info.data());
    }
    for (int l = 0; l < lanes && first + static_cast<std::size_t>(l) < configs.size(); ++l) {
      const auto at = [&](const std::vector<double>& v, int row) {
        return v[static_cast<std::size_t>(row) * static_cast<std::size_t>(lanes) +
                 static_cast<std::size_t>(l)];
      };
      KernelResult r;
      r.status = static_cast<int>(at(info, 0));
      const int code = static_cast<int>(at(info, 1));
      r.symmetry = SquareSymmetry{code % 4, code >= 4};
      r.orientation = at(info, 2);
      r.scale = at(info, 3);
      for (int k = 0; k < 16; ++k) r.features[static_cast<std::size_t>(k)] = at(f, k);
      for (int k = 0; k < 12 && gregory; ++k) r.normals[static_cast<std::size_t>(k)] = at(nrm, k);
      results.push_back(r);
    }
  }
  return results;
}

/// The reference's status for a network: ok only with a canonical frame.
int reference_status(const geometry::NormaliseOutcome& n) {
  if (!n.value) return n.failure == geometry::NormaliseFailure::kNonFinite ? 4 : 3;
  return n.value->canonical ? 0 : 3;
}

/// How far two implementations of the frame may differ, relative: the world coordinates' rounding seen in the
/// frame (eps max|x| / |AB|), amplified by the angle at the canonical A (the frame's e3 comes from AB x AD),
/// times a few roundings per step.
double frame_tolerance(const Configuration& world, const geometry::NormalisedConfiguration& n) {
  double big = world.slave.cwiseAbs().maxCoeff();
  for (const Vec3& x : world.nodes) big = std::max(big, x.cwiseAbs().maxCoeff());
  const Vec3& d = n.config.nodes[3];
  const double sin_a = std::abs(d.y()) / d.norm();
  return 64.0 * std::numeric_limits<double>::epsilon() * (1.0 + big * n.frame.scale()) / sin_a;
}

/// The kernel's result `k` against the reference's `n` (status ok on both), features to `tol` relative. Where
/// S lies in the plane of A, B, D up to that tolerance, the orientation of z is decided by rounding: either
/// is accepted, with z_C, z_S and the normals' slopes changing sign together.
void expect_same_frame(const KernelResult& k, const geometry::NormalisedConfiguration& n, SurfaceKind kind,
                       double tol, const std::string& what) {
  EXPECT_EQ(k.symmetry, n.symmetry) << what;
  const bool flipped = k.orientation != n.orientation;
  if (flipped) {
    EXPECT_EQ(k.orientation, -n.orientation) << what;
    EXPECT_LE(std::abs(n.features[7]), tol) << what << ": z orientation differs with S off the plane";
  }
  for (int f = 0; f < feature_count(kind); ++f) {
    const bool odd = f == 2 || f == 7 || f >= 8;  // z_C, z_S and the slopes change sign with z
    const double expected = (flipped && odd ? -1.0 : 1.0) * n.features[static_cast<std::size_t>(f)];
    EXPECT_NEAR(k.features[static_cast<std::size_t>(f)], expected, tol * std::max(1.0, std::abs(expected)))
        << what << " feature " << kFeatureNames[static_cast<std::size_t>(f)];
  }
  if (kind == SurfaceKind::kGregory) {
    // The kernel's normals are the reference's unit normals times a positive factor.
    for (int c = 0; c < 4; ++c) {
      const auto at = [&](int j) {
        return k.normals[3 * static_cast<std::size_t>(c) + static_cast<std::size_t>(j)];
      };
      Vec3 expected = n.config.normals[static_cast<std::size_t>(c)];
      if (flipped) expected = Vec3(-expected.x(), -expected.y(), expected.z());
      EXPECT_NEAR((Vec3(at(0), at(1), at(2)).normalized() - expected).norm(), 0.0, tol)
          << what << " normal " << c;
    }
  }
}

/// Checks the kernel against normalise for every configuration (features to frame_tolerance * `slack`).
void expect_matches_reference(const std::vector<Configuration>& configs, SurfaceKind kind, int lanes,
                              double slack = 1.0, bool c99 = false) {
  const std::vector<KernelResult> got = run_kernel(configs, kind, lanes, c99);
  ASSERT_EQ(got.size(), configs.size());
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const geometry::NormaliseOutcome ref = geometry::normalise(configs[i], kind);
    const KernelResult& k = got[i];
    ASSERT_EQ(k.status, reference_status(ref)) << "config " << i;
    if (k.status != 0) continue;
    EXPECT_NEAR(k.scale, ref.value->frame.scale(), 1e-14 * ref.value->frame.scale()) << "config " << i;
    expect_same_frame(k, *ref.value, kind, slack * frame_tolerance(configs[i], *ref.value),
                      "config " + std::to_string(i));
  }
}

/// A segment and slave anywhere: A is not the nearest node in 3 of 4 cases, |AD| > |AB| half the time, the
/// slave on either side; normals tilted by up to ~0.3 and of any length; then placed at random.
Configuration random_world(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Configuration local{
      {Vec3(0, 0, 0), Vec3(1 + 0.5 * u(rng), 0.1 * u(rng), 0.1 * u(rng)),
       Vec3(1 + 0.4 * u(rng), 1 + 0.4 * u(rng), 0.2 * u(rng)), Vec3(0.1 * u(rng), 1 + 0.5 * u(rng), 0)},
      Vec3(0.5 + 0.8 * u(rng), 0.5 + 0.8 * u(rng), 0.4 * u(rng)),
      kNoNormals};
  for (auto& n : local.normals) n = Vec3(0.3 * u(rng), 0.3 * u(rng), 1.0);
  return testing::place(local, rng, random_order(rng));
}

TEST(CanonicalFrameKernel, MatchesNormaliseOnRandomConfigurationsInAnyOrderAndPlacement) {
  std::mt19937_64 rng(101);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    std::vector<Configuration> configs;
    for (int i = 0; i < 2000; ++i) configs.push_back(random_world(rng));
    for (const int lanes : {1, 16}) expect_matches_reference(configs, kind, lanes);
  }
}

TEST(CanonicalFrameKernel, MatchesNormaliseOnThePapersDomains) {
  std::mt19937_64 rng(102);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    std::vector<Configuration> configs;
    for (int i = 0; i < 1000; ++i) {
      configs.push_back(
          testing::place(testing::random_domain_configuration(kind, rng), rng, random_order(rng)));
    }
    expect_matches_reference(configs, kind, 8);
  }
}

/// Exact ties of the reference's rules, each in all 8 node orders and several placements: the slave
/// equidistant from two nodes, |AB| = |AD| (a rhombus and a square), the slave on a diagonal of a square.
TEST(CanonicalFrameKernel, BreaksExactTiesAsTheReferenceDoes) {
  std::mt19937_64 rng(103);
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0.1), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> rhombus = {Vec3(0, 0, 0), Vec3(5, 0, 0), Vec3(8, 4, 0.3), Vec3(3, 4, 0)};
  const std::vector<Configuration> bases = {
      {square, Vec3(0.5, 0.2, 0.3), kNoNormals},   // equidistant from A and B
      {square, Vec3(0.3, 0.3, 0.2), kNoNormals},   // on the diagonal AC: |AB| = |AD| and S equally near both
                                                   // lines
      {square, Vec3(0.2, 0.4, -0.2), kNoNormals},  // nearer the line AB
      {rhombus, Vec3(2, 0.5, 0.4), kNoNormals},
      {rhombus, Vec3(1, 1.5, 0.2), kNoNormals},
      {square, Vec3(0.5, 0.5, 0.5), kNoNormals},  // all four nodes equidistant in the plane's projection
  };
  std::vector<Configuration> configs;
  for (const Configuration& base : bases) {
    for (const SquareSymmetry& order : all_square_symmetries()) {
      Configuration c = base;
      for (int i = 0; i < 4; ++i)
        c.nodes[static_cast<std::size_t>(order.caller_node(i))] = base.nodes[static_cast<std::size_t>(i)];
      configs.push_back(c);
      // Placements with scale and rotation: the reference's tie tolerance absorbs their rounding.
      for (int p = 0; p < 3; ++p) configs.push_back(testing::place(c, rng, SquareSymmetry{}));
    }
  }
  expect_matches_reference(configs, SurfaceKind::kBilinear, 16);
}

Configuration make(const std::array<Vec3, 4>& nodes, const Vec3& slave) {
  Configuration c{nodes, slave, kNoNormals};
  for (auto& n : c.normals) n = Vec3(0, 0, 1);
  return c;
}

/// The extremes of tests/extremes (issue 5) that concern the frame, and the Gregory normal cases.
std::vector<Configuration> extreme_cases() {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> warped = {Vec3(0, 0, 0), Vec3(1, 0, 0.15), Vec3(1.1, 0.95, -0.1),
                                      Vec3(-0.05, 1, 0.2)};
  const Vec3 s(0.3, 0.4, 0.2);
  std::vector<Configuration> cases;
  // Ordinary, and the slave at a corner, on an edge, on the plane, far away.
  for (const Vec3& slave : {s, Vec3(0, 0, 0), Vec3(1.1, 0.95, -0.1), Vec3(0.5, 0, 0.075), Vec3(0.3, 0.4, 0.0),
                            Vec3(1e3, 0.5, 0.0), Vec3(0.2, 0.1, 1e3), Vec3(0.2, 0.1, -1e3)}) {
    cases.push_back(make(warped, slave));
  }
  // Thin and obtuse angles, aspect ratio 1e3 either way.
  for (const double degrees : {0.1, 1.0, 179.0, 179.9}) {
    const double t = degrees * std::numbers::pi / 180.0;
    cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.3 * std::cos(t / 2), 1.3 * std::sin(t / 2), 0),
                          Vec3(std::cos(t), std::sin(t), 0)},
                         Vec3(0.2, 0.01, 0.01)));
    cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0.05), Vec3(std::cos(t), std::sin(t), 0)},
                         Vec3(0.05, 0.05, 0.02)));
  }
  cases.push_back(
      make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1e-3, 0), Vec3(0, 1e-3, 0)}, Vec3(0.4, 0.0002, 0.001)));
  cases.push_back(
      make({Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(1e-3, 1, 0), Vec3(0, 1, 0)}, Vec3(0.0002, 0.4, 0.001)));
  // Collapsed: coincident pairs, all coincident, collinear, D on the ray AB (folded), bow tie.
  cases.push_back(make({Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, s));
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, s));
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 0)}, s));
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)}, s));
  cases.push_back(make({Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)}, s));
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(2, 0, 0)}, s));
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2.5, 2.5, 2.5), Vec3(-1, -1, -1)}, s));
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0)}, s));
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)}, s));
  // Straight angles: at B (usable, the reference takes another corner: no network input), at A.
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)}, Vec3(0.9, 0.3, 0.2)));
  cases.push_back(make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0)}, Vec3(0.2, 0.3, 0.2)));
  cases.push_back(
      make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1 - 1e-9, 1, 0)}, Vec3(0.6, 0.3, 0.2)));
  // Non-finite values anywhere; differences that overflow.
  for (int k = 0; k < 15; k += 4) {
    for (const double bad : {nan, inf, -inf}) {
      Configuration c = make(square, s);
      (k < 12 ? c.nodes[static_cast<std::size_t>(k / 3)] : c.slave)[k % 3] = bad;
      cases.push_back(c);
    }
  }
  cases.push_back(
      make({Vec3(-1.5e308, 0, 0), Vec3(1.5e308, 0, 0), Vec3(1.5e308, 1.5e308, 0), Vec3(-1.5e308, 1.5e308, 0)},
           Vec3(0, 1e307, 1e307)));
  return cases;
}

TEST(CanonicalFrameKernel, MatchesNormaliseOnTheExtremeCasesAtEveryScaleAndPlacement) {
  std::mt19937_64 rng(104);
  std::vector<Configuration> configs;
  for (const Configuration& base : extreme_cases()) {
    configs.push_back(base);
    // Rotated and translated 1e5 element sizes (the inputs keep ~11 digits relative to the element).
    const Eigen::Matrix3d r = testing::random_rotation_matrix(rng);
    Configuration moved = base;
    for (auto& x : moved.nodes) x = r * x + Vec3(1e5, -2e5, 3e5);
    moved.slave = r * moved.slave + Vec3(1e5, -2e5, 3e5);
    configs.push_back(moved);
  }
  expect_matches_reference(configs, SurfaceKind::kBilinear, 16);
}

TEST(CanonicalFrameKernel, ExtremeScalesGiveTheUnitScalesResult) {
  // The features, symmetry and status of a configuration do not depend on its scale: the kernel at each scale
  // against the reference at unit scale and at that scale (both scale such queries by a power of two first).
  std::vector<Configuration> unit;
  for (const Configuration& base : extreme_cases()) {
    if (base.is_finite(false) && base.nodes[0].x() > -1e300) unit.push_back(base);
  }
  for (const double scale : {1e-300, 1e-150, 1e-6, 1e6, 1e150, 1e300}) {
    std::vector<Configuration> scaled = unit;
    for (Configuration& c : scaled) {
      for (auto& x : c.nodes) x *= scale;
      c.slave *= scale;
    }
    const std::vector<KernelResult> got = run_kernel(scaled, SurfaceKind::kBilinear, 16);
    for (std::size_t i = 0; i < unit.size(); ++i) {
      const geometry::NormaliseOutcome ref = geometry::normalise(unit[i], SurfaceKind::kBilinear);
      ASSERT_EQ(got[i].status, reference_status(ref)) << "scale " << scale << " config " << i;
      const geometry::NormaliseOutcome at_scale = geometry::normalise(scaled[i], SurfaceKind::kBilinear);
      ASSERT_EQ(reference_status(at_scale), reference_status(ref)) << "scale " << scale << " config " << i;
      if (at_scale.value) {
        EXPECT_EQ(at_scale.value->symmetry, ref.value->symmetry) << "scale " << scale << " config " << i;
      }
      if (got[i].status != 0) continue;
      EXPECT_NEAR(got[i].scale * scale, ref.value->frame.scale(), 1e-14 * ref.value->frame.scale());
      // The scaled inputs are rounded once more: the unit case's tolerance, a little wider.
      std::ostringstream what;
      what << "scale " << scale << " config " << i;
      expect_same_frame(got[i], *ref.value, SurfaceKind::kBilinear,
                        4.0 * frame_tolerance(unit[i], *ref.value), what.str());
    }
  }
}

TEST(CanonicalFrameKernel, GregoryNormalsOfAnyLengthInThePlaneOrOnBothSides) {
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0.2), Vec3(0, 2, 0)};
  std::vector<Configuration> configs;
  const Configuration base{square,
                           Vec3(0.5, 0.7, 0.4),
                           {Vec3(0.05, 0.1, 1), Vec3(-0.1, 0.05, 1), Vec3(0.1, 0.1, 1), Vec3(0, -0.1, 1)}};
  for (const double length : {1e-300, 1e-200, 1e-60, 1.0, 1e60, 1e200, 1e300}) {
    Configuration c = base;
    for (auto& n : c.normals) n *= length;
    configs.push_back(c);
    for (auto& n : c.normals) n = -n;  // all on the back side: the same patch
    configs.push_back(c);
  }
  Configuration in_plane = base;
  in_plane.normals[1] = Vec3(1, 0, 0);
  configs.push_back(in_plane);
  Configuration both_sides = base;
  both_sides.normals[2] = -both_sides.normals[2];
  configs.push_back(both_sides);
  Configuration zero = base;
  zero.normals[3] = Vec3::Zero();
  configs.push_back(zero);
  Configuration nan_normal = base;
  nan_normal.normals[0].y() = std::numeric_limits<double>::quiet_NaN();
  configs.push_back(nan_normal);
  Configuration along_edge = base;
  along_edge.normals[0] = Vec3(1, 0, 1e-14);
  configs.push_back(along_edge);
  expect_matches_reference(configs, SurfaceKind::kGregory, 16);
}

/// Configurations on a tie of each kind, for bilinear and Gregory: S midway between two nodes (2 forms), |AB|
/// = |AD| with S on the diagonal (2), S over the centre of a square (8), S and C on the plane of A, B, D
/// (Gregory: 2 orientations of z), S on a flat square's centre (16), and one with no tie.
std::vector<Configuration> tie_cases() {
  const std::array<Vec3, 4> normals = {Vec3(0.05, -0.03, 1), Vec3(-0.02, 0.06, 1), Vec3(-0.1, 0.02, 1),
                                       Vec3(0.04, 0.05, 1)};
  const auto with = [&](const std::array<Vec3, 4>& nodes, const Vec3& slave) {
    return Configuration{nodes, slave, normals};
  };
  const std::array<Vec3, 4> strip = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0.2), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0.1), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> flat = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> kite = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.1, 0.9, 0), Vec3(0, 0.8, 0)};
  return {with(strip, Vec3(0, 0.5, 0.1)),    with(square, Vec3(0.3, 0.3, 0.2)),
          with(square, Vec3(0.5, 0.5, 0.3)), with(kite, Vec3(0.3, 0.2, 0.0)),
          with(flat, Vec3(0.5, 0.5, 0.0)),   with(flat, Vec3(0.5, 0.2, 0.0)),
          with(strip, Vec3(0.3, 0.2, 0.1))};
}

TEST(CanonicalFrameKernel, ListsEveryCanonicalFormOfATieAsTheReferenceDoes) {
  // cnn_cf_forms against geometry::canonical_forms: the same count and, form by form, the same symmetry and
  // features, for every tie case in every node order and placement; the block pass flags exactly the queries
  // with more than one form.
  std::mt19937_64 rng(108);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    const int gregory = kind == SurfaceKind::kGregory ? 1 : 0;
    int tied = 0;
    for (const Configuration& base : tie_cases()) {
      for (const SquareSymmetry& order : all_square_symmetries()) {
        Configuration c = base;
        for (int i = 0; i < 4; ++i) {
          c.nodes[static_cast<std::size_t>(order.caller_node(i))] = base.nodes[static_cast<std::size_t>(i)];
          c.normals[static_cast<std::size_t>(order.caller_node(i))] =
              base.normals[static_cast<std::size_t>(i)];
        }
        for (int p = 0; p < 3; ++p) {
          const Configuration placed = p == 0 ? c : testing::place(c, rng, SquareSymmetry{});
          const geometry::CanonicalForms ref = geometry::canonical_forms(placed, kind);
          ASSERT_GT(ref.count, 0);
          std::vector<double> x;
          testing::append_raw(placed, kind, x);
          std::array<double, 16 * CNN_CF_MAX_FORMS> f{};
          std::array<double, 12 * CNN_CF_MAX_FORMS> nrm{};
          std::array<double, CNN_CF_INFO_ROWS * CNN_CF_MAX_FORMS> info{};
          // The block pass's flag (one lane).
          cnn_canonicalise_block(1, gregory, x.data(), f.data(), nrm.data(), info.data());
          const std::string what = std::string(to_string(kind)) + " order " + std::to_string(order.rotation) +
                                   (order.mirror ? "m" : "") + " placement " + std::to_string(p);
          ASSERT_EQ(cnn_cf_needs_forms(info[5], gregory) != 0, ref.count > 1) << what;
          const int count = cnn_cf_forms(x.data(), gregory, f.data(), nrm.data(), info.data());
          ASSERT_EQ(count, ref.count) << what;
          {
            // The C99 compilation lists the same forms.
            std::array<double, 16 * CNN_CF_MAX_FORMS> f99{};
            std::array<double, 12 * CNN_CF_MAX_FORMS> nrm99{};
            std::array<double, CNN_CF_INFO_ROWS * CNN_CF_MAX_FORMS> info99{};
            ASSERT_EQ(contactnn_forms_c99(x.data(), gregory, f99.data(), nrm99.data(), info99.data()), count)
                << what;
            for (int k = 0; k < count; ++k)
              EXPECT_EQ(info99[CNN_CF_INFO_ROWS * static_cast<std::size_t>(k) + 1],
                        info[CNN_CF_INFO_ROWS * static_cast<std::size_t>(k) + 1])
                  << what;
          }
          tied += count > 1;
          for (int k = 0; k < count; ++k) {
            const geometry::NormalisedConfiguration& n = ref.form[static_cast<std::size_t>(k)];
            KernelResult r;
            const auto at = static_cast<std::size_t>(CNN_CF_INFO_ROWS * k);
            r.status = static_cast<int>(info[at]);
            const int code = static_cast<int>(info[at + 1]);
            r.symmetry = SquareSymmetry{code % 4, code >= 4};
            r.orientation = info[at + 2];
            for (std::size_t j = 0; j < 16; ++j) r.features[j] = f[16 * static_cast<std::size_t>(k) + j];
            for (std::size_t j = 0; j < 12; ++j) r.normals[j] = nrm[12 * static_cast<std::size_t>(k) + j];
            ASSERT_EQ(r.status, 0) << what << " form " << k;
            EXPECT_EQ(r.orientation, n.orientation) << what << " form " << k;
            expect_same_frame(r, n, kind, frame_tolerance(placed, n), what + " form " + std::to_string(k));
          }
        }
      }
    }
    EXPECT_GT(tied, 100) << to_string(kind);
  }
}

TEST(CanonicalFrameKernel, TheC99CompilationAgreesWithTheCxxOne) {
  // tests/search/canonical_frame_c99.c is compiled with -std=c99 -pedantic -Werror and includes the header
  // twice (the guard lets two exported headers share it).
  std::mt19937_64 rng(105);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    std::vector<Configuration> configs;
    for (int i = 0; i < 500; ++i) configs.push_back(random_world(rng));
    expect_matches_reference(configs, kind, 16, 1.0, true);
  }
}

TEST(EmbeddedSources, AreTheHeadersVerbatim) {
  // The exported C header embeds the kernels from this text: it must be the files, byte for byte, with
  // canonical_frame.h's parts in place of their first #include "search/PART" line (a later one dropped).
  const auto read = [](const std::string& name) {
    std::ifstream in(std::string(CONTACTNN_SOURCE_DIR) + "/lib/search/" + name, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  std::string frame = read("canonical_frame.h");
  const std::string sigmoid = read("vector_sigmoid.h"), include = "#include \"search/";
  std::vector<std::string> parts;
  for (std::size_t at = frame.find(include); at != std::string::npos; at = frame.find(include, at)) {
    const std::size_t name = at + include.size(), end = frame.find('\n', at);
    const std::string part = frame.substr(name, frame.find('"', name) - name);
    const bool first = std::find(parts.begin(), parts.end(), part) == parts.end();
    if (first) parts.push_back(part);
    const std::string text = first ? read(part) : std::string();
    ASSERT_TRUE(!first || !text.empty()) << part;
    frame.replace(at, end + 1 - at, text);
  }
  ASSERT_GT(parts.size(), 1u);
  EXPECT_EQ(canonical_frame_source(), frame);
  EXPECT_EQ(vector_sigmoid_source(), sigmoid);
}

// ---- The training domain ----

/// A domain with the paper's filters of `kind` and feature ranges that cut through the sampled region, so
/// that about half of the configurations fall outside.
geometry::TrainingDomain test_domain(SurfaceKind kind) {
  geometry::TrainingDomain d;
  d.surface = kind;
  d.filters = testing::paper_filters(kind);
  const std::array<double, 16> lo = {-0.5, 0.2,  -0.2, -1.5, 0.1,  -1.2, -1.0, 0.0,
                                     -0.2, -0.2, -0.2, -0.2, -0.2, -0.2, -0.2, -0.2};
  const std::array<double, 16> hi = {1.8, 1.9, 0.25, 1.2, 1.0, 1.5, 1.6, 0.25,
                                     0.2, 0.2, 0.2,  0.2, 0.2, 0.2, 0.2, 0.2};
  for (int f = 0; f < feature_count(kind); ++f) {
    d.feature_min.push_back(lo[static_cast<std::size_t>(f)]);
    d.feature_max.push_back(hi[static_cast<std::size_t>(f)]);
  }
  return d;
}

/// The kernel's domain verdict per configuration (status 0 -> in, 5 -> out), for configurations that
/// normalise.
std::vector<int> kernel_domain(const std::vector<Configuration>& configs, SurfaceKind kind,
                               const cnn_domain& d, int lanes) {
  const bool gregory = kind == SurfaceKind::kGregory;
  std::vector<int> verdict;
  for (std::size_t first = 0; first < configs.size(); first += static_cast<std::size_t>(lanes)) {
    const auto n = static_cast<std::size_t>(lanes);
    const std::vector<double> in = raw_block(configs, first, n, kind);
    std::vector<double> f(16 * n), nrm(12 * n), info(CNN_CF_INFO_ROWS * n);
    cnn_canonicalise_block(lanes, gregory, in.data(), f.data(), nrm.data(), info.data());
    cnn_domain_block(lanes, gregory, &d, f.data(), nrm.data(), info.data());
    for (std::size_t l = 0; l < n && first + l < configs.size(); ++l)
      verdict.push_back(static_cast<int>(info[l]));
  }
  return verdict;
}

/// Runs the domain kernel on `configs` and expects its verdict to be TrainingDomain::contains' for every
/// configuration that normalises to a canonical form; returns how many were inside and outside.
std::pair<int, int> expect_kernel_agrees(const std::vector<Configuration>& configs, SurfaceKind kind,
                                         const geometry::TrainingDomain& domain, const std::string& what) {
  const std::vector<int> got = kernel_domain(configs, kind, domain_bounds(domain), 16);
  int inside = 0, outside = 0;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const geometry::NormaliseOutcome n = geometry::normalise(configs[i], kind);
    if (!n.value || !n.value->canonical) continue;
    const bool contains = domain.contains(n.value->config, n.value->features.data());
    EXPECT_EQ(got[i], contains ? 0 : 5) << what << " config " << i;
    (contains ? inside : outside) += 1;
  }
  return {inside, outside};
}

TEST(DomainKernel, AgreesWithTrainingDomainContains) {
  std::mt19937_64 rng(106);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    const geometry::TrainingDomain domain = test_domain(kind);
    std::vector<Configuration> configs;
    for (int i = 0; i < 2000; ++i) {
      // Half from the paper's domain, half perturbed out of it (angles, tilts, ranges, nearest node).
      Configuration local = testing::random_domain_configuration(kind, rng);
      if (i % 2 == 1) {
        local.nodes[2] += Vec3(0.3 * u(rng), 0.3 * u(rng), 0.1 * u(rng));
        local.slave += Vec3(0.3 * u(rng), 0.3 * u(rng), 0.1 * u(rng));
        for (auto& n : local.normals) n = (n + Vec3(0.1 * u(rng), 0.1 * u(rng), 0.0)).normalized();
      }
      configs.push_back(testing::place(local, rng, random_order(rng)));
    }
    const auto [inside, outside] = expect_kernel_agrees(configs, kind, domain, std::string(to_string(kind)));
    // Both verdicts are exercised in earnest.
    EXPECT_GT(inside, 300) << to_string(kind);
    EXPECT_GT(outside, 300) << to_string(kind);
  }
}

TEST(DomainKernel, AngleBoundsOnEitherSideOfARightAngleAgreeWithTheReference) {
  // The kernel compares the interior angles through their cosines. The paper's 60-120 degrees (the other
  // tests' bounds) is symmetric about 90, so a corner taken for its supplement passes unseen there, and its
  // upper cosine is negative. These bounds are not symmetric, and two of them have a positive upper or a
  // negative lower cosine.
  std::mt19937_64 rng(108);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    for (const auto& [lo, hi] : {std::pair{45.0, 100.0}, std::pair{80.0, 135.0}, std::pair{0.0, 95.0},
                                 std::pair{10.0, 89.0}, std::pair{95.0, 170.0}}) {
      // Only the angles (and convexity) decide: wide feature ranges, the other filters off.
      geometry::TrainingDomain domain = test_domain(kind);
      std::fill(domain.feature_min.begin(), domain.feature_min.end(), -1e3);
      std::fill(domain.feature_max.begin(), domain.feature_max.end(), 1e3);
      domain.filters.xy_limit = 1e3;
      domain.filters.z_limit = 1e3;
      domain.filters.ad_not_longer_than_ab = false;
      domain.filters.nearest_node_a = false;
      domain.filters.segment_test_a = false;
      domain.filters.max_normal_tilt_tangent = 1e3;
      domain.filters.min_angle_degrees = lo;
      domain.filters.max_angle_degrees = hi;
      std::vector<Configuration> configs;
      for (int i = 0; i < 1000; ++i) {
        // A parallelogram with an angle of 40 to 140 degrees at A, C moved, S above: corners around both
        // bounds.
        const double angle = (90.0 + 50.0 * u(rng)) * std::numbers::pi / 180.0, length = 0.8 + 0.2 * u(rng);
        const Vec3 d(length * std::cos(angle), length * std::sin(angle), 0.0);
        const Vec3 c = Vec3(1, 0, 0) + d + Vec3(0.15 * u(rng), 0.15 * u(rng), 0.05 * u(rng));
        const Vec3 up(0.1 * u(rng), 0.1 * u(rng), 1.0);
        const Configuration local{{Vec3(0, 0, 0), Vec3(1, 0, 0), c, d},
                                  Vec3(0.3 + 0.2 * u(rng), 0.3, 0.1 * u(rng)),
                                  {up, up, up, up}};
        configs.push_back(testing::place(local, rng, random_order(rng)));
      }
      std::ostringstream what;
      what << to_string(kind) << " angles " << lo << "-" << hi;
      const auto [inside, outside] = expect_kernel_agrees(configs, kind, domain, what.str());
      // No flat quadrilateral has every angle below (above) 90 degrees: with an upper bound below 90 (a
      // positive cosine) or a lower bound above 90 (a negative one) every configuration is outside.
      EXPECT_GT(inside, lo < 90.0 && hi > 90.0 ? 20 : -1) << to_string(kind) << " angles " << lo << "-" << hi;
      EXPECT_GT(outside, 20) << to_string(kind) << " angles " << lo << "-" << hi;
    }
  }
}

TEST(DomainKernel, ConfigurationsOnTheBoundsAgreeWithTheReference) {
  // Features exactly on a range bound or on a filter's boundary: grid-like configurations of the bilinear
  // study (S equidistant from A and B, |AD| = |AB|, xy on the range bound) in several placements.
  std::mt19937_64 rng(107);
  geometry::TrainingDomain domain = test_domain(SurfaceKind::kBilinear);
  domain.feature_max[0] = 1.5;  // x_C
  domain.feature_min[4] = 0.5;  // y_D
  const cnn_domain bounds = domain_bounds(domain);
  std::vector<Configuration> configs;
  for (const Vec3& slave : {Vec3(0.5, 0.3, 0.1), Vec3(0.2, 0.2, 0.05), Vec3(0.4, 0.0, 0.2)}) {
    for (const Vec3& d : {Vec3(0, 1, 0), Vec3(0.6, 0.8, 0), Vec3(-0.3, 0.5, 0)}) {
      const Configuration c{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.5, 1.2, 0.1), d}, slave, kNoNormals};
      configs.push_back(c);
      for (int p = 0; p < 4; ++p) configs.push_back(testing::place(c, rng, SquareSymmetry{}));
    }
  }
  const std::vector<int> got = kernel_domain(configs, SurfaceKind::kBilinear, bounds, 16);
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const geometry::NormaliseOutcome n = geometry::normalise(configs[i], SurfaceKind::kBilinear);
    ASSERT_TRUE(n.value && n.value->canonical);
    EXPECT_EQ(got[i], domain.contains(n.value->config, n.value->features.data()) ? 0 : 5) << "config " << i;
  }
}

// ---- The float pass of a float network's bilinear block (cnn_canonicalise_domain_block_f) ----

/// One block's verdicts and features by a pass over `lanes` lanes.
struct PassOutput {
  std::vector<double> f, info;
};

/// The double pass (cnn_canonicalise_block, then cnn_domain_block with `d`) or the float pass over `configs`
/// (bilinear), as blocks of `lanes` lanes.
std::vector<PassOutput> run_pass(const std::vector<Configuration>& configs, const cnn_domain* d,
                                 bool float_pass, int lanes) {
  std::vector<PassOutput> out;
  const auto n = static_cast<std::size_t>(lanes);
  for (std::size_t first = 0; first < configs.size(); first += n) {
    const std::vector<double> in = raw_block(configs, first, n, SurfaceKind::kBilinear);
    std::vector<double> f(16 * n), info(CNN_CF_INFO_ROWS * n);
    if (float_pass) {
      cnn_canonicalise_domain_block_f(lanes, d, in.data(), f.data(), info.data());
    } else {
      cnn_canonicalise_block(lanes, 0, in.data(), f.data(), nullptr, info.data());
      if (d != nullptr) cnn_domain_block(lanes, 0, d, f.data(), nullptr, info.data());
    }
    for (std::size_t l = 0; l < n && first + l < configs.size(); ++l) {
      PassOutput o;
      for (std::size_t k = 0; k < 8; ++k) o.f.push_back(f[k * n + l]);
      for (std::size_t k = 0; k < CNN_CF_INFO_ROWS; ++k) o.info.push_back(info[k * n + l]);
      out.push_back(o);
    }
  }
  return out;
}

/// The float pass against the double pass on `configs`: the same status, symmetry, orientation, tie code and
/// domain verdict on every lane, features to float rounding. Returns the share of the lanes decided in float
/// (features not those of the double pass bit for bit).
double expect_float_pass_decides_as_double(const std::vector<Configuration>& configs, const cnn_domain* d,
                                           const std::string& what) {
  const std::vector<PassOutput> dbl = run_pass(configs, d, false, 32), flt = run_pass(configs, d, true, 32);
  int in_float = 0;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const PassOutput &a = dbl[i], &b = flt[i];
    EXPECT_EQ(b.info[0], a.info[0]) << what << " config " << i << ": status";
    if (b.info[0] != a.info[0] || (a.info[0] != 0.0 && a.info[0] != 5.0)) continue;
    EXPECT_EQ(b.info[1], a.info[1]) << what << " config " << i << ": symmetry";
    EXPECT_EQ(b.info[2], a.info[2]) << what << " config " << i << ": orientation";
    EXPECT_EQ(b.info[5], a.info[5]) << what << " config " << i << ": tie code";
    EXPECT_EQ(b.info[4], 0.0) << what << " config " << i << ": row 4";
    bool same = true;
    for (std::size_t k = 0; k < 8; ++k) {
      // The float features: within 2e-4 relative of the double ones (measured: 4e-5 on near-degenerate
      // corners, 1e-6 on well-shaped segments); a wrong sign, row or symmetry is off by far more.
      EXPECT_NEAR(b.f[k], a.f[k], 2e-4 * std::max(1.0, std::abs(a.f[k])))
          << what << " config " << i << " feature " << k;
      same = same && b.f[k] == a.f[k];
    }
    in_float += same ? 0 : 1;
  }
  return static_cast<double>(in_float) / static_cast<double>(configs.size());
}

TEST(FloatFramePass, DecidesEveryLaneAsTheDoublePassDoes) {
  // Random segments in any order and placement, the paper's domain placed at random, with no domain, a domain
  // that cuts through the samples and the shipped network's: every verdict is the double pass's, and most
  // lanes (well over 80 in 100) are decided in float, or the pass would be a slower double pass.
  std::mt19937_64 rng(121);
  std::vector<Configuration> any, paper;
  for (int i = 0; i < 3000; ++i) any.push_back(random_world(rng));
  for (int i = 0; i < 3000; ++i) {
    paper.push_back(testing::place(testing::random_domain_configuration(SurfaceKind::kBilinear, rng), rng,
                                   random_order(rng)));
  }
  const cnn_domain cut = domain_bounds(test_domain(SurfaceKind::kBilinear));
  geometry::TrainingDomain wide = test_domain(SurfaceKind::kBilinear);
  std::fill(wide.feature_min.begin(), wide.feature_min.end(), -1e3);
  std::fill(wide.feature_max.begin(), wide.feature_max.end(), 1e3);
  const cnn_domain paper_filters = domain_bounds(wide);
  for (const auto& [name, d] : {std::pair<const char*, const cnn_domain*>{"no domain", nullptr},
                                {"cut domain", &cut},
                                {"paper filters", &paper_filters}}) {
    const double share_any = expect_float_pass_decides_as_double(any, d, std::string("any, ") + name);
    const double share_paper = expect_float_pass_decides_as_double(paper, d, std::string("paper, ") + name);
    EXPECT_GT(share_any, 0.8) << name;
    EXPECT_GT(share_paper, 0.8) << name;
    RecordProperty(std::string("decided_in_float_") + (d == nullptr ? "none"
                                                       : d == &cut  ? "cut"
                                                                    : "paper"),
                   std::to_string(share_paper));
  }
}

TEST(FloatFramePass, TiesSlavesOnThePlaneAndExtremeCasesGoToTheDoublePass) {
  // What float cannot decide: S exactly or nearly on the plane of A, B, D (touching contact), |AB| = |AD|
  // (square elements), S equidistant from two nodes, corners of a fraction of a degree, collapsed segments,
  // non-finite and extreme values. Verdicts as the double pass's, at any placement.
  std::mt19937_64 rng(122);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Configuration> configs = extreme_cases();
  for (int i = 0; i < 400; ++i) {
    Configuration c = testing::random_domain_configuration(SurfaceKind::kBilinear, rng);
    switch (i % 5) {
      case 0: c.slave.z() = 0.0; break;                                         // on the plane
      case 1: c.slave.z() = (i % 2 ? 1.0 : -1.0) * 1e-6 * (1 + u(rng)); break;  // nearly on it
      case 2:
        c.nodes[3] = Vec3(0.0, 1.0, 0.0);
        c.nodes[1] = Vec3(1.0, 0.0, 0.0);
        break;  // |AB| = |AD|
      case 3:   // S midway between A and B
        c.slave = Vec3(0.5, 0.2 * u(rng), 0.1 * u(rng));
        c.nodes[1] = Vec3(1.0, 0.0, 0.0);
        break;
      default:
        c.nodes[3] = Vec3(1.0, 1e-4 * (1.5 + u(rng)), 0.0);
        break;  // a corner of a hundredth of a degree
    }
    configs.push_back(c);
    configs.push_back(testing::place(c, rng, random_order(rng)));
  }
  const cnn_domain cut = domain_bounds(test_domain(SurfaceKind::kBilinear));
  (void)expect_float_pass_decides_as_double(configs, nullptr, "hard cases");
  (void)expect_float_pass_decides_as_double(configs, &cut, "hard cases, cut domain");
}

TEST(FloatFramePass, WhatTheDoublePassSaysFloatLeavesItLeaves) {
  // cnn_cff_leaves reads from the double pass's outputs that the float pass would leave a lane undecided; a
  // caller that expects touching contact skips the float pass on a block where it holds for every lane, which
  // gives the same bits only if it never holds for a lane float decides. Swept across the float pass's own
  // thresholds: slaves 1e-9 .. 1e-3 off the plane of A, B, D (and near A), |AD| / |AB| - 1 from 1e-9 to 1e-4,
  // corners down to a hundredth of a degree, with and without a domain. And it must hold where real decks
  // need it: slaves exactly on the plane, exact squares, exact ties.
  std::mt19937_64 rng(125);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(0.0, 1.0);
  std::vector<Configuration> configs, exact;
  for (int i = 0; i < 6000; ++i) {
    Configuration c = testing::random_domain_configuration(SurfaceKind::kBilinear, rng);
    const double tiny = std::pow(10.0, -3.0 - 6.0 * e(rng));
    switch (i % 6) {
      case 0: c.slave.z() = (u(rng) < 0.0 ? -1.0 : 1.0) * tiny; break;
      case 1: c.slave = Vec3(tiny * u(rng), tiny * u(rng), tiny * u(rng)); break;  // near A, off the plane
      case 2:  // |AD|^2 = |AB|^2 (1 +- tiny)
        c.nodes[1] = Vec3(1.0, 0.0, 0.0);
        c.nodes[3] = c.nodes[3].normalized() * std::sqrt(1.0 + (u(rng) < 0.0 ? -tiny : tiny));
        break;
      case 3: c.nodes[3] = Vec3(1.0, std::pow(10.0, -2.0 - 2.0 * e(rng)), 0.0); break;  // thin corner at A
      default: break;
    }
    configs.push_back(testing::place(c, rng, random_order(rng)));
    Configuration t = testing::random_domain_configuration(SurfaceKind::kBilinear, rng);
    switch (i % 3) {
      case 0:
        t.nodes[2].z() = 0.0;
        t.slave.z() = 0.0;
        break;  // a flat segment, the slave on it or beside it
      case 1:   // a square, the slave anywhere above it
        t.nodes = {Vec3(0.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), Vec3(1.0, 1.0, 0.0), Vec3(0.0, 1.0, 0.0)};
        t.slave = Vec3(0.5 + 0.6 * u(rng), 0.5 + 0.6 * u(rng), 0.3 * e(rng));
        break;
      default:  // the slave as near A as B, the others farther
        t.nodes = {Vec3(0.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), Vec3(1.1, 0.9, 0.1 * u(rng)),
                   Vec3(-0.1, 1.0, 0.0)};
        t.slave = Vec3(0.5, 0.1 * u(rng), 0.1 * u(rng));
        break;
    }
    exact.push_back(testing::place(t, rng, random_order(rng)));
  }
  const cnn_domain cut = domain_bounds(test_domain(SurfaceKind::kBilinear));
  for (const cnn_domain* d : {static_cast<const cnn_domain*>(nullptr), &cut}) {
    int leaves = 0, undecided = 0, decided = 0;
    for (const auto* set : {&configs, &exact}) {
      const std::size_t n = 32;
      for (std::size_t first = 0; first < set->size(); first += n) {
        const std::vector<double> in = raw_block(*set, first, n, SurfaceKind::kBilinear);
        std::vector<double> f(8 * n), info(CNN_CF_INFO_ROWS * n), ff(8 * n), fi(CNN_CF_INFO_ROWS * n);
        cnn_canonicalise_block(static_cast<int>(n), 0, in.data(), f.data(), nullptr, info.data());
        if (d != nullptr) cnn_domain_block(static_cast<int>(n), 0, d, f.data(), nullptr, info.data());
        (void)cnn_cff_block(static_cast<int>(n), d, in.data(), ff.data(), fi.data());
        for (std::size_t l = 0; l < n && first + l < set->size(); ++l) {
          const int says = cnn_cff_leaves(static_cast<int>(n), static_cast<int>(l), f.data(), info.data());
          const bool left = fi[4 * n + l] != 0.0;
          ASSERT_FALSE(says && !left)
              << (set == &exact ? "exact " : "") << "config " << first + l << (d ? ", cut domain" : "")
              << ": said undecided, but float decides it";
          if (set == &exact) {
            EXPECT_TRUE(says) << "exact case " << first + l << " (kind " << (first + l) % 3 << ")";
          } else {
            leaves += says;
            undecided += left;
            decided += !left;
          }
        }
      }
    }
    // Both sides of the thresholds were reached: lanes it names, lanes float decides, and lanes float leaves
    // that it does not name (it is a sufficient condition, not float's own test).
    EXPECT_GT(leaves, 300) << (d ? "cut domain" : "no domain");
    EXPECT_GT(decided, 2000) << (d ? "cut domain" : "no domain");
    EXPECT_GT(undecided - leaves, 50) << (d ? "cut domain" : "no domain");
  }
  // On random queries of the paper's domain it names almost no lane (one such lane in a block of 32 keeps
  // the float pass running there).
  std::vector<Configuration> paper;
  for (int i = 0; i < 3200; ++i) {
    paper.push_back(testing::place(testing::random_domain_configuration(SurfaceKind::kBilinear, rng), rng,
                                   random_order(rng)));
  }
  int named = 0;
  const std::vector<PassOutput> dbl = run_pass(paper, nullptr, false, 32);
  for (const PassOutput& o : dbl) {
    std::vector<double> f = o.f, info = o.info;
    named += cnn_cff_leaves(1, 0, f.data(), info.data());
  }
  EXPECT_LT(named, 64) << "of 3200 random queries of the paper's domain";
}

TEST(FloatFramePass, GivesTheSameBitsInEveryNodeOrder) {
  // The float pass rounds the nodes relative to the slave node and takes differences after the canonical
  // relabelling: the 8 node orders of a query (no tie) give the same features, bit for bit, and the same
  // canonical symmetry relative to their order.
  std::mt19937_64 rng(124);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int in_float = 0;
  for (int i = 0; i < 300; ++i) {
    const Configuration local = testing::random_domain_configuration(SurfaceKind::kBilinear, rng);
    std::vector<Configuration> orders;
    std::mt19937_64 placement(1000 + static_cast<std::uint64_t>(i));
    for (const SquareSymmetry& order : all_square_symmetries()) {
      std::mt19937_64 same = placement;  // the same rotation, scale and translation for every order
      orders.push_back(testing::place(local, same, order));
    }
    const std::vector<PassOutput> got = run_pass(orders, nullptr, true, 8);
    const std::vector<PassOutput> dbl = run_pass(orders, nullptr, false, 8);
    bool decided = true;
    for (std::size_t k = 0; k < 8; ++k) decided = decided && got[0].f[k] != dbl[0].f[k];
    in_float += decided ? 1 : 0;
    for (std::size_t o = 1; o < orders.size(); ++o) {
      ASSERT_EQ(got[o].info[0], got[0].info[0]) << "config " << i << " order " << o;
      for (std::size_t k = 0; k < 8; ++k)
        EXPECT_EQ(got[o].f[k], got[0].f[k]) << "config " << i << " order " << o;
    }
  }
  EXPECT_GT(in_float, 200) << "most of these queries are decided in float";
}

TEST(FloatFramePass, GivesTheSameFeaturesAtEveryPowerOfTwoScale) {
  // The float pass scales each query by a power of two before rounding to float: the same bits at every
  // scale, as the double pass (the search's answers are scale-free; tests/search/test_local_search checks
  // them at 2^-200 and 2^200).
  std::mt19937_64 rng(123);
  std::vector<Configuration> base;
  for (int i = 0; i < 64; ++i) base.push_back(random_world(rng));
  const std::vector<PassOutput> ref = run_pass(base, nullptr, true, 32);
  for (const int e : {-300, -100, -20, 7, 60, 250}) {
    std::vector<Configuration> scaled = base;
    for (Configuration& c : scaled) {
      for (Vec3& x : c.nodes) x = std::ldexp(1.0, e) * x;
      c.slave = std::ldexp(1.0, e) * c.slave;
    }
    const std::vector<PassOutput> got = run_pass(scaled, nullptr, true, 32);
    for (std::size_t i = 0; i < base.size(); ++i) {
      ASSERT_EQ(got[i].info[0], ref[i].info[0]) << "2^" << e << " config " << i;
      for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(got[i].f[k], ref[i].f[k]) << "2^" << e << " config " << i;
    }
  }
}

}  // namespace
}  // namespace contactnn::search
