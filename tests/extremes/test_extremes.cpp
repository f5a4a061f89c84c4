// The label solver at the extremes (issue 5, part 1): every case of the table below goes through
// dataset::label_configuration (world coordinates in, SPEC 4 normalisation, SPEC 2 projection) unchanged,
// scaled by 1e-6 .. 1e6, randomly rotated and translated by 1e5 element sizes, and each result is checked
// for: the expected status, finite coordinates and gap, bounded iterations, the same labels as the unit
// case (1e-8), the exact answer where one is known by construction, and agreement with an independent
// dense-grid reference (brute-force minimum of |S - P|^2 over a fine grid of [-1,1]^2, refined) wherever a
// projection exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "dataset/labeller.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/gregory_patch.hpp"
#include "projection/newton_projection.hpp"
#include "test_support.hpp"

namespace contactnn::extremes {
namespace {

using geometry::BilinearPatch;
using geometry::Configuration;
using geometry::Vec3;

// Labels of a transformed configuration against the unit case: the bound.
constexpr double kInvarianceTol = 1e-8;
// A known answer (a point built on the surface, or moved along its normal) is met to solver accuracy
// (|step| < 1e-13) times the conditioning of the thinnest cases (aspect ratio 1e3).
constexpr double kExactTol = 1e-9;
// The refined grid locates the minimum to ~1e-11 on O(1) cases; 1e-7 leaves room for the thin ones.
constexpr double kReferenceParamTol = 1e-7;
// A reference minimum closer than this to the domain boundary is treated as lying on it.
constexpr double kBoundaryBand = 1e-6;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------------
// The cases, in "unit" coordinates (element size about 1).

struct Case {
  std::string name;
  Configuration config;
  std::vector<Status> allowed;                       ///< acceptable statuses in the unit case
  std::optional<std::array<double, 2>> exact_param;  ///< known answer, when S was built from it
  double exact_gap = 0.0;                            ///< with exact_param
  /// How much the problem amplifies a relative rounding of its inputs (1 for a well-shaped segment with S
  /// within an element size; ~1e3 for S 1e3 element sizes away, or a 1e3:1 segment; their product for both).
  /// Translated 1e5 element sizes from the origin, the inputs keep only ~11 digits relative to the element,
  /// so there the labels can only agree to condition x that rounding (see kInvarianceTol's use).
  double condition = 1.0;
};

Case conditioned(Case c, double condition) {
  c.condition = condition;
  return c;
}

Configuration make(const std::array<Vec3, 4>& nodes, const Vec3& slave) {
  return Configuration{nodes, slave, {}};
}

/// The unit normal of the bilinear facet at (xi, eta) (SPEC 2 orientation: P_xi x P_eta).
Vec3 unit_normal(const std::array<Vec3, 4>& nodes, double xi, double eta) {
  const geometry::SurfacePoint p = BilinearPatch(nodes).evaluate(xi, eta);
  return p.d_s.cross(p.d_t).normalized();
}

/// S = P(xi, eta) + gap n(xi, eta): (xi, eta) is the closest point when |gap| is below the radius of
/// curvature.
Case on_normal(std::string name, const std::array<Vec3, 4>& nodes, double xi, double eta, double gap) {
  const Vec3 s = BilinearPatch(nodes).position(xi, eta) + gap * unit_normal(nodes, xi, eta);
  return Case{std::move(name), make(nodes, s), {Status::kOk}, std::array<double, 2>{xi, eta}, gap};
}

/// A collapsed segment: status degenerate, nothing to compare.
Case collapsed(std::string name, const Configuration& config) {
  return Case{std::move(name), config, {Status::kDegenerate}, std::nullopt, 0.0};
}

const std::array<Vec3, 4> kSquare = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
// A moderately warped, non-parallel quad: the corners are off a common plane by 0.1 to 0.2 of an edge.
const std::array<Vec3, 4> kWarped = {Vec3(0, 0, 0), Vec3(1, 0, 0.15), Vec3(1.1, 0.95, -0.1),
                                     Vec3(-0.05, 1, 0.2)};

std::array<Vec3, 4> kite_with_angle_at_a(double degrees) {
  const double t = degrees * std::numbers::pi / 180.0;
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.3 * std::cos(t / 2), 1.3 * std::sin(t / 2), 0),
          Vec3(std::cos(t), std::sin(t), 0)};
}

std::array<Vec3, 4> obtuse_at_a(double degrees) {
  const double t = degrees * std::numbers::pi / 180.0;
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0.05), Vec3(std::cos(t), std::sin(t), 0)};
}

// Two in-domain minima of |S - P|^2 (found by a search over random warped quads): the one near
// (0.76, -0.75) is nearer; plain Newton from the centre ends in the other, near (-0.60, 0.62).
const std::array<Vec3, 4> kTwoRootQuad = {Vec3(0, 0, 1.3976875724555624), Vec3(1, 0, -1.0455432115554117),
                                          Vec3(1.1753571775883207, 1.03741714200146, 0.86540608150966014),
                                          Vec3(0.13310002003853594, 1, -1.3349819312208751)};
const Vec3 kTwoRootSlave(0.58471905301707772, 0.41054635016860636, -0.75814015064901641);

std::vector<Case> build_cases() {
  std::vector<Case> cases;
  const auto add = [&](Case c) { cases.push_back(std::move(c)); };
  const std::vector<Status> ok = {Status::kOk};
  const std::vector<Status> converged_or_not = {Status::kOk, Status::kOutside, Status::kNoConvergence};

  // 1. The slave node exactly at each corner, on each edge, on the surface: gap 0.
  const char* corner_names[] = {"A", "B", "C", "D"};
  const std::array<std::array<double, 2>, 4> corners = {{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  for (int i = 0; i < 4; ++i) {
    add({std::string("slave_at_corner_") + corner_names[i],
         make(kWarped, kWarped[static_cast<std::size_t>(i)]), ok, corners[static_cast<std::size_t>(i)], 0.0});
  }
  const std::array<std::pair<const char*, std::array<double, 2>>, 4> edges = {
      {{"AB", {0.3, -1}}, {"BC", {1, -0.4}}, {"CD", {0.6, 1}}, {"DA", {-1, 0.2}}}};
  for (const auto& [edge, p] : edges) {
    add({std::string("slave_on_edge_") + edge, make(kWarped, BilinearPatch(kWarped).position(p[0], p[1])), ok,
         p, 0.0});
  }
  add(on_normal("slave_on_surface", kWarped, 0.3, -0.5, 0.0));
  add(on_normal("slave_above_surface", kWarped, 0.3, -0.5, 0.1));
  // 2. Behind the surface (penetration, gap < 0), also behind a corner.
  add(on_normal("slave_behind_surface", kWarped, 0.3, -0.5, -0.1));
  add(on_normal("slave_behind_corner_C", kWarped, 1, 1, -0.05));
  // 3. 1e3 element sizes away: along the normal of a flat segment (exact), of a warped one (reference),
  //    and sideways in the plane (the stationary point lies beyond the solver's bounded box).
  add(conditioned(on_normal("slave_1e3_above_flat", kSquare, 0.2, 0.1, 1e3), 1e3));
  add(conditioned(on_normal("slave_1e3_behind_flat", kSquare, 0.2, 0.1, -1e3), 1e3));
  add({"slave_1e3_above_warped",
       make(kWarped, BilinearPatch(kWarped).position(0.2, 0.1) + 1e3 * unit_normal(kWarped, 0.2, 0.1)),
       converged_or_not, std::nullopt, 0.0});
  add({"slave_1e3_sideways_flat",
       make(kSquare, Vec3(1e3, 0.5, 0.0)),
       {Status::kOutside, Status::kNoConvergence},
       std::nullopt,
       0.0});
  add({"slave_1e3_diagonal_flat",
       make(kSquare, Vec3(1e3, 1e3, 1e3) / std::sqrt(3.0)),
       {Status::kOutside, Status::kNoConvergence},
       std::nullopt,
       0.0});
  add({"slave_just_outside_edge_BC",
       make(kSquare, Vec3(1.01, 0.5, 0.2)),
       {Status::kOutside},
       std::array<double, 2>{1.02, 0.0},
       0.2});
  // 4. Nearly degenerate segments.
  add(on_normal("interior_angle_1_degree", kite_with_angle_at_a(1.0), 0.2, 0.3, 0.01));
  add(on_normal("interior_angle_0.1_degree", kite_with_angle_at_a(0.1), 0.2, 0.3, 0.001));
  add(on_normal("interior_angle_0.1_degree_slave_at_A", kite_with_angle_at_a(0.1), -1, -1, 0.0));
  add(on_normal("interior_angle_179_degrees", obtuse_at_a(179.0), -0.7, -0.7, 0.02));
  add(on_normal("interior_angle_179.9_degrees", obtuse_at_a(179.9), -0.9, -0.9, 0.02));
  add(on_normal("interior_angle_179.9_degrees_slave_at_A", obtuse_at_a(179.9), -1, -1, 0.0));
  const std::array<Vec3, 4> thin = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1e-3, 0), Vec3(0, 1e-3, 0)};
  const std::array<Vec3, 4> tall = {Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(1e-3, 1, 0), Vec3(0, 1, 0)};
  add(conditioned(on_normal("aspect_ratio_1e3_long_AB", thin, 0.4, -0.3, 1e-3), 1e3));
  add(conditioned(on_normal("aspect_ratio_1e3_long_AB_slave_far", thin, 0.4, -0.3, 1.0), 1e6));
  add(conditioned(on_normal("aspect_ratio_1e3_short_AB", tall, 0.4, -0.3, 1e-3), 1e3));
  const std::array<Vec3, 4> thin_warped = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1e-3, 2e-4),
                                           Vec3(0, 1e-3, -1e-4)};
  add(conditioned(on_normal("aspect_ratio_1e3_warped", thin_warped, 0.1, 0.5, 2e-4), 1e3));
  add({"strongly_warped_two_roots", make(kTwoRootQuad, kTwoRootSlave), ok, std::nullopt, 0.0});
  // z = xi * eta over the square [-1,1]^2 (the lead's saddle) with S far above: a ridge of near-equal roots.
  add({"saddle_slave_above_centre",
       make({Vec3(-1, -1, 1), Vec3(1, -1, -1), Vec3(1, 1, 1), Vec3(-1, 1, -1)}, Vec3(0.05, 0.02, 1.5)), ok,
       std::nullopt, 0.0});
  // Opposite edges at right angles: the most twisted a bilinear facet gets.
  add({"twisted_90_degrees",
       make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 1), Vec3(0, 1, 0)}, Vec3(0.6, 0.3, 0.2)),
       converged_or_not, std::nullopt, 0.0});
  // Three nodes on a line (a triangle with a 180-degree corner at B): usable, the Jacobian vanishes at B
  // only.
  add({"three_collinear_nodes",
       make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)}, Vec3(0.6, 0.3, 0.2)), ok,
       std::nullopt, 0.0});
  // D on the line AB behind A: a straight angle at A, a triangle with A on an edge, like the case above.
  add({"D_on_line_AB_straight_angle_at_A",
       make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0)}, Vec3(0.2, 0.3, 0.2)), ok,
       std::nullopt, 0.0});
  // Two nodes 1e-9 apart (above the 1e-10 coincidence threshold): a triangle, still projected.
  add({"nearly_coincident_nodes_1e-9",
       make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1 - 1e-9, 1, 0)}, Vec3(0.6, 0.3, 0.2)), ok,
       std::nullopt, 0.0});
  // 5. Collapsed segments: degenerate.
  const Vec3 s(0.3, 0.4, 0.2);
  add(collapsed("coincident_A_B", make({Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, s)));
  add(collapsed("coincident_B_C", make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, s)));
  add(collapsed("coincident_C_D", make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 0)}, s)));
  add(collapsed("coincident_D_A", make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 0, 0)}, s)));
  add(collapsed("coincident_A_C", make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)}, s)));
  add(collapsed("coincident_B_D", make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 0)}, s)));
  add(collapsed("all_nodes_coincident",
                make({Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)}, s)));
  add(collapsed("all_nodes_collinear",
                make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(2, 0, 0)}, s)));
  add(collapsed("all_nodes_collinear_oblique",
                make({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2.5, 2.5, 2.5), Vec3(-1, -1, -1)}, s)));
  // D on the ray AB: the corner at A has zero angle and the segment folds onto itself.
  add(collapsed("D_on_ray_AB_folded", make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0)}, s)));
  // A self-intersecting "bow tie" ABDC has parallel diagonals: zero area by the diagonal formula.
  add(collapsed("bow_tie_zero_area", make({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)}, s)));
  return cases;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = build_cases();
  return all;
}

// ---------------------------------------------------------------------------------------------------
// Transforms: scale, random rotation, translation by 1e5 element sizes.

struct Transform {
  std::string name;
  double scale;
  Eigen::Matrix3d rotation;
  Vec3 translation;
};

std::vector<Transform> transforms() {
  std::vector<Transform> out;
  std::mt19937_64 rng(2007);
  std::normal_distribution<double> g;
  for (const double scale : {1e-6, 1e-3, 1.0, 1e3, 1e6}) {
    const std::string s = "scale " + std::to_string(scale);
    out.push_back({s, scale, Eigen::Matrix3d::Identity(), Vec3::Zero()});
    out.push_back({s + ", rotated", scale, testing::random_rotation(rng), Vec3::Zero()});
    const Vec3 direction = Vec3(g(rng), g(rng), g(rng)).normalized();
    out.push_back({s + ", rotated, translated by 1e5 element sizes", scale, testing::random_rotation(rng),
                   1e5 * scale * direction});
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------
// The dense-grid reference, independent of the solver: no derivatives, no Newton.

struct Reference {
  std::array<double, 2> param{};
  double sqr_distance = 0.0;
  bool interior = false;  ///< at least kBoundaryBand from the boundary of [-1,1]^2
};

/// Minimum of |S - P|^2 over [-1,1]^2: a 161 x 161 grid, then each of the best coarse local minima refined
/// by shrinking 9 x 9 grids. Coordinates are shifted so node A is the origin. Inside a refinement the change
/// |S-P|^2 - |S-P0|^2 = dP.(dP - 2 (S - P0)) is compared, with dP = P - P0 formed from parameter differences
/// (P = a0 + a1 xi + a2 eta + a3 xi eta), so its rounding is relative to |dP|, not to |P|: a slave 1e3
/// element sizes away, or a segment 1e3 times thinner than long, still resolves the minimum to ~1e-12.
Reference dense_reference(const Configuration& world) {
  std::array<Vec3, 4> q = world.nodes;
  for (auto& node : q) node -= world.nodes[0];
  const Vec3 s = world.slave - world.nodes[0];
  const BilinearPatch patch(q);
  const Vec3 a1 = 0.25 * (-q[0] + q[1] + q[2] - q[3]);
  const Vec3 a2 = 0.25 * (-q[0] - q[1] + q[2] + q[3]);
  const Vec3 a3 = 0.25 * (q[0] - q[1] + q[2] - q[3]);
  const auto sqr = [&](double a, double b) { return (s - patch.position(a, b)).squaredNorm(); };
  // P(x, y) - P(cx, cy), with x y - cx cy = (x - cx) y + cx (y - cy).
  const auto dp = [&](double x, double y, double cx, double cy) {
    const double dx = x - cx, dy = y - cy;
    return Vec3(a1 * dx + a2 * dy + a3 * (dx * y + cx * dy));
  };
  constexpr int n = 161;
  std::vector<double> f(n * n);
  const auto at = [](int i) { return -1.0 + 2.0 * i / (n - 1); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) f[static_cast<std::size_t>(i * n + j)] = sqr(at(i), at(j));
  }
  std::vector<std::pair<double, std::array<int, 2>>> minima;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double v = f[static_cast<std::size_t>(i * n + j)];
      bool local = true;
      for (int di = -1; di <= 1 && local; ++di) {
        for (int dj = -1; dj <= 1; ++dj) {
          const int a = i + di, b = j + dj;
          if (a < 0 || b < 0 || a >= n || b >= n || (di == 0 && dj == 0)) continue;
          if (f[static_cast<std::size_t>(a * n + b)] < v) {
            local = false;
            break;
          }
        }
      }
      if (local) minima.push_back({v, {i, j}});
    }
  }
  std::sort(minima.begin(), minima.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  if (minima.size() > 6) minima.resize(6);

  Reference best;
  best.sqr_distance = kInf;
  for (const auto& [value, ij] : minima) {
    std::array<double, 2> c = {at(ij[0]), at(ij[1])};
    double h = 2.0 / (n - 1);
    for (int round = 0; round < 200 && h > 1e-16; ++round) {
      const Vec3 to_s = s - patch.position(c[0], c[1]);
      std::array<double, 2> next = c;
      double next_value = 0.0;  // relative to the centre
      for (int a = -4; a <= 4; ++a) {
        for (int b = -4; b <= 4; ++b) {
          const double x = std::clamp(c[0] + h * a / 4.0, -1.0, 1.0);
          const double y = std::clamp(c[1] + h * b / 4.0, -1.0, 1.0);
          const Vec3 d = dp(x, y, c[0], c[1]);
          const double v = d.dot(d - 2.0 * to_s);
          if (v < next_value) {
            next_value = v;
            next = {x, y};
          }
        }
      }
      // Centre still best: the minimum is within a grid step, shrink. Otherwise follow the descent.
      if (next == c) h *= 0.3;
      c = next;
    }
    const double d2 = sqr(c[0], c[1]);
    if (d2 < best.sqr_distance) {
      best.param = c;
      best.sqr_distance = d2;
    }
  }
  best.interior = std::abs(best.param[0]) < 1 - kBoundaryBand && std::abs(best.param[1]) < 1 - kBoundaryBand;
  return best;
}

double sqr_distance_at(const Configuration& world, const std::array<double, 2>& param) {
  std::array<Vec3, 4> shifted = world.nodes;
  for (auto& node : shifted) node -= world.nodes[0];
  return (world.slave - world.nodes[0] - BilinearPatch(shifted).position(param[0], param[1])).squaredNorm();
}

double element_size(const Configuration& c) { return geometry::max_node_distance(c.nodes); }

bool converged(Status s) { return s == Status::kOk || s == Status::kOutside; }

std::string describe(const dataset::Label& l) {
  return std::string(to_string(l.status)) + " (" + std::to_string(l.param[0]) + ", " +
         std::to_string(l.param[1]) + ") gap " + std::to_string(l.gap) + " iterations " +
         std::to_string(l.iterations);
}

/// What every label must satisfy, whatever the input: finite values, bounded iterations.
void expect_sane(const dataset::Label& l, const std::string& where) {
  const int max_iterations = projection::ProjectionOptions{}.max_iterations;
  EXPECT_TRUE(std::isfinite(l.param[0]) && std::isfinite(l.param[1])) << where;
  EXPECT_TRUE(std::isfinite(l.gap)) << where;
  EXPECT_GE(l.iterations, 0) << where;
  EXPECT_LE(l.iterations, max_iterations) << where;
  if (!converged(l.status)) {
    EXPECT_EQ(l.gap, 0.0) << where << ": a non-converged label carries no gap";
  }
}

// ---------------------------------------------------------------------------------------------------

class ExtremeCase : public ::testing::TestWithParam<std::size_t> {
 protected:
  [[nodiscard]] const Case& the_case() const { return cases()[GetParam()]; }
};

TEST_P(ExtremeCase, UnitCaseHasTheExpectedStatusAndAnswer) {
  const Case& c = the_case();
  const dataset::Label l = dataset::label_configuration(c.config, SurfaceKind::kBilinear);
  expect_sane(l, c.name);
  EXPECT_NE(std::find(c.allowed.begin(), c.allowed.end(), l.status), c.allowed.end())
      << c.name << ": got " << describe(l);
  if (c.exact_param) {
    ASSERT_EQ(l.status,
              c.exact_param.value()[0] > 1 || c.exact_param.value()[1] > 1 ? Status::kOutside : Status::kOk)
        << describe(l);
    EXPECT_NEAR(l.param[0], c.exact_param.value()[0], kExactTol) << describe(l);
    EXPECT_NEAR(l.param[1], c.exact_param.value()[1], kExactTol) << describe(l);
    EXPECT_NEAR(l.gap, c.exact_gap, kExactTol * std::max(1.0, std::abs(c.exact_gap))) << describe(l);
  }
}

TEST_P(ExtremeCase, SameLabelsAtEveryScaleRotationAndTranslation) {
  const Case& c = the_case();
  const dataset::Label unit = dataset::label_configuration(c.config, SurfaceKind::kBilinear);
  for (const Transform& t : transforms()) {
    const Configuration world = testing::transform(c.config, t.rotation, t.scale, t.translation);
    const dataset::Label l = dataset::label_configuration(world, SurfaceKind::kBilinear);
    const std::string where = c.name + " at " + t.name + ": " + describe(l) + " vs unit " + describe(unit);
    expect_sane(l, where);
    ASSERT_EQ(l.status, unit.status) << where;
    if (!converged(l.status)) continue;
    // The rounding the world inputs carry relative to the element, amplified by the case's conditioning:
    // below 1e-8 except for ill-conditioned cases translated far from the origin.
    double largest = std::max(world.slave.cwiseAbs().maxCoeff(), 0.0);
    for (const Vec3& node : world.nodes) largest = std::max(largest, node.cwiseAbs().maxCoeff());
    const double input_rounding = std::numeric_limits<double>::epsilon() * largest / element_size(world);
    const double tol = std::max(kInvarianceTol, 4.0 * c.condition * input_rounding);
    EXPECT_NEAR(l.param[0], unit.param[0], tol) << where;
    EXPECT_NEAR(l.param[1], unit.param[1], tol) << where;
    EXPECT_NEAR(l.gap / t.scale, unit.gap, tol * std::max(1.0, std::abs(unit.gap))) << where;
  }
}

TEST_P(ExtremeCase, AgreesWithDenseGridReferenceWhereAProjectionExists) {
  const Case& c = the_case();
  if (std::find(c.allowed.begin(), c.allowed.end(), Status::kDegenerate) != c.allowed.end()) {
    // A collapsed segment has no projection to compare: it must be reported as such everywhere.
    for (const Transform& t : transforms()) {
      const Configuration world = testing::transform(c.config, t.rotation, t.scale, t.translation);
      EXPECT_EQ(dataset::label_configuration(world, SurfaceKind::kBilinear).status, Status::kDegenerate)
          << c.name << " at " << t.name;
    }
    return;
  }
  for (const Transform& t : transforms()) {
    const Configuration world = testing::transform(c.config, t.rotation, t.scale, t.translation);
    const dataset::Label l = dataset::label_configuration(world, SurfaceKind::kBilinear);
    const Reference ref = dense_reference(world);
    const double size = element_size(world);
    const std::string where = c.name + " at " + t.name + ": " + describe(l) + " vs reference (" +
                              std::to_string(ref.param[0]) + ", " + std::to_string(ref.param[1]) + ")";
    // Distances compare to rounding of the (shifted) world coordinates.
    const double d2_tol = 1e-10 * size * (size + std::sqrt(ref.sqr_distance));
    if (l.status == Status::kOk) {
      // An in-domain stationary point is never nearer than the domain's minimum...
      EXPECT_GE(sqr_distance_at(world, l.param), ref.sqr_distance - d2_tol) << where;
    }
    if (ref.interior) {
      // ...and where that minimum is interior it is a stationary point the label must find.
      ASSERT_EQ(l.status, Status::kOk) << where;
      EXPECT_NEAR(l.param[0], ref.param[0], kReferenceParamTol) << where;
      EXPECT_NEAR(l.param[1], ref.param[1], kReferenceParamTol) << where;
      EXPECT_NEAR(sqr_distance_at(world, l.param), ref.sqr_distance, d2_tol) << where;
    }
  }
}

std::string case_name(const ::testing::TestParamInfo<std::size_t>& info) {
  std::string name = cases()[info.param].name;
  for (char& ch : name) {
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(Bilinear, ExtremeCase, ::testing::Range<std::size_t>(0, cases().size()), case_name);

// ---------------------------------------------------------------------------------------------------
// Cases that are not one configuration.

TEST(Extremes, TwoRootQuadReallyHasTwoInDomainMinimaAndTheNearerIsReturned) {
  const BilinearPatch patch(kTwoRootQuad);
  const projection::ProjectionResult far_root =
      projection::newton_until_converged(patch, kTwoRootSlave, {-0.6, 0.6});
  const projection::ProjectionResult near_root =
      projection::newton_until_converged(patch, kTwoRootSlave, {0.75, -0.75});
  ASSERT_EQ(far_root.status, Status::kOk);
  ASSERT_EQ(near_root.status, Status::kOk);
  EXPECT_GT(std::abs(far_root.param[0] - near_root.param[0]), 1.0);  // really two roots
  EXPECT_LT(near_root.sqr_distance, far_root.sqr_distance - 0.05);
  // Plain Newton from the centre finds the farther root; the reference solver must not.
  const projection::ProjectionResult one_start =
      projection::project_point(patch, kTwoRootSlave, projection::ProjectionOptions{.starts_per_axis = 1});
  EXPECT_NEAR(one_start.param[0], far_root.param[0], 1e-9);
  const dataset::Label label =
      dataset::label_configuration(make(kTwoRootQuad, kTwoRootSlave), SurfaceKind::kBilinear);
  ASSERT_EQ(label.status, Status::kOk);
  EXPECT_NEAR(label.param[0], near_root.param[0], 1e-9);
  EXPECT_NEAR(label.param[1], near_root.param[1], 1e-9);
}

TEST(Extremes, NonFiniteInAnyCoordinateIsInvalid) {
  const Configuration base = make(kWarped, Vec3(0.3, 0.4, 0.2));
  for (int coordinate = 0; coordinate < 15; ++coordinate) {
    for (const double bad : {kNaN, kInf, -kInf}) {
      Configuration c = base;
      Vec3& point = coordinate < 12 ? c.nodes[static_cast<std::size_t>(coordinate / 3)] : c.slave;
      point[coordinate % 3] = bad;
      const dataset::Label l = dataset::label_configuration(c, SurfaceKind::kBilinear);
      const std::string where = "coordinate " + std::to_string(coordinate) + " = " + std::to_string(bad);
      EXPECT_EQ(l.status, Status::kInvalid) << where;
      expect_sane(l, where);
      EXPECT_EQ(l.iterations, 0) << where;
    }
  }
}

TEST(Extremes, ScalesAtTheLimitsOfDoubleGiveTheUnitLabels) {
  // Beyond the 1e-6..1e6: the normalisation measures lengths without squaring them where squares
  // would under- or overflow (beyond ~1e+-154), so labels hold from 1e-300 to 1e307.
  const auto found = std::find_if(cases().begin(), cases().end(),
                                  [](const Case& x) { return x.name == "slave_behind_surface"; });
  ASSERT_NE(found, cases().end());
  const Case& c = *found;
  const dataset::Label unit = dataset::label_configuration(c.config, SurfaceKind::kBilinear);
  std::mt19937_64 rng(11);
  for (const double scale : {1e-300, 1e-200, 1e-160, 1e-100, 1e100, 1e160, 1e200, 1e300, 1e307}) {
    const Configuration world =
        testing::transform(c.config, testing::random_rotation(rng), scale, Vec3::Zero());
    const dataset::Label l = dataset::label_configuration(world, SurfaceKind::kBilinear);
    const std::string where =
        "scale 1e" + std::to_string(std::lround(std::log10(scale))) + ": " + describe(l);
    expect_sane(l, where);
    ASSERT_EQ(l.status, unit.status) << where;
    EXPECT_NEAR(l.param[0], unit.param[0], kInvarianceTol) << where;
    EXPECT_NEAR(l.param[1], unit.param[1], kInvarianceTol) << where;
    EXPECT_NEAR(l.gap / scale, unit.gap, kInvarianceTol) << where;
  }
  // Node differences that overflow (nodes at -+1.5e308): no frame, degenerate, nothing non-finite.
  const Configuration overflow =
      make({Vec3(-1.5e308, 0, 0), Vec3(1.5e308, 0, 0), Vec3(1.5e308, 1e308, 0), Vec3(-1.5e308, 1e308, 0)},
           Vec3(0, 1e307, 1e307));
  const dataset::Label l = dataset::label_configuration(overflow, SurfaceKind::kBilinear);
  expect_sane(l, "overflowing node differences: " + describe(l));
  EXPECT_EQ(l.status, Status::kDegenerate) << describe(l);
}

TEST(Extremes, RandomHostileConfigurationsNeverGiveNonFiniteLabels) {
  // Random nodes and slaves over 12 orders of magnitude, with random collapses and non-finite values:
  // every status is allowed, a NaN, an unbounded iteration count or a crash is not.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> pick(0, 19);
  for (int k = 0; k < 3000; ++k) {
    const double scale = std::pow(10.0, 6 * u(rng));
    Configuration c;
    for (auto& node : c.nodes) node = scale * Vec3(u(rng), u(rng), u(rng));
    c.slave = scale * std::pow(10.0, 3 * u(rng)) * Vec3(u(rng), u(rng), u(rng));
    switch (pick(rng)) {
      case 0: c.nodes[1] = c.nodes[0]; break;
      case 1: c.nodes[3] = c.nodes[2]; break;
      case 2: c.nodes[2] = 0.5 * (c.nodes[1] + c.nodes[3]); break;
      case 3: c.slave = c.nodes[2]; break;
      case 4: c.nodes[k % 4][k % 3] = kNaN; break;
      case 5: c.slave[k % 3] = -kInf; break;
      default: break;
    }
    const dataset::Label l = dataset::label_configuration(c, SurfaceKind::kBilinear);
    expect_sane(l, "hostile configuration " + std::to_string(k));
  }
}

// ---------------------------------------------------------------------------------------------------
// Gregory segments (SPEC 3): node normals at the paper's tilt limit (tangent 0.2), beyond it, at right
// angles to the segment's normal, parallel to an edge, flipped, of zero length and non-finite.

using geometry::GregoryPatch;

struct GregoryCase {
  std::string name;
  Configuration config;  ///< with normals
  std::vector<Status> allowed;
  std::optional<std::array<double, 2>> exact_param;
  double exact_gap = 0.0;
};

/// `normal` tilted away from +z towards `direction` (in the xy-plane) by the angle whose tangent is
/// `tangent`.
Vec3 tilted(double tangent, double direction_degrees) {
  const double d = direction_degrees * std::numbers::pi / 180.0;
  return Vec3(tangent * std::cos(d), tangent * std::sin(d), 1.0);
}

std::vector<GregoryCase> build_gregory_cases() {
  std::vector<GregoryCase> cases;
  const std::array<Vec3, 4> square = kSquare;
  const Vec3 up(0, 0, 1);
  const auto with = [](std::array<Vec3, 4> nodes, std::array<Vec3, 4> normals, Vec3 slave) {
    return Configuration{nodes, slave, normals};
  };
  const std::vector<Status> ok = {Status::kOk};
  const std::vector<Status> degenerate = {Status::kDegenerate};
  const std::vector<Status> converged_or_not = {Status::kOk, Status::kOutside, Status::kNoConvergence};
  // Flat square, plane normals: the bilinear facet, u = (xi + 1)/2 (SPEC 1); S above, on, below the surface.
  cases.push_back({"flat_plane_normals_above", with(square, {up, up, up, up}, Vec3(0.3, 0.6, 0.2)), ok,
                   std::array<double, 2>{0.3, 0.6}, 0.2});
  cases.push_back({"flat_plane_normals_behind", with(square, {up, up, up, up}, Vec3(0.3, 0.6, -0.2)), ok,
                   std::array<double, 2>{0.3, 0.6}, -0.2});
  cases.push_back({"flat_plane_normals_at_corner_C", with(square, {up, up, up, up}, Vec3(1, 1, 0)), ok,
                   std::array<double, 2>{1.0, 1.0}, 0.0});
  cases.push_back({"flat_plane_normals_on_edge_AB", with(square, {up, up, up, up}, Vec3(0.4, 0, 0)), ok,
                   std::array<double, 2>{0.4, 0.0}, 0.0});
  cases.push_back({"flat_plane_normals_any_length",
                   with(square, {1e-300 * up, 1e300 * up, 3.0 * up, 1e-5 * up}, Vec3(0.3, 0.6, 0.2)), ok,
                   std::array<double, 2>{0.3, 0.6}, 0.2});
  // At the paper's tilt limit (tangent 0.2), each normal leaning its own way: a curved patch.
  const std::array<Vec3, 4> limit = {tilted(0.2, 225), tilted(0.2, -45), tilted(0.2, 45), tilted(0.2, 135)};
  cases.push_back(
      {"tilt_tangent_0.2_outward", with(square, limit, Vec3(0.35, 0.55, 0.1)), ok, std::nullopt, 0.0});
  cases.push_back({"tilt_tangent_0.2_all_one_way",
                   with(square, {tilted(0.2, 30), tilted(0.2, 30), tilted(0.2, 30), tilted(0.2, 30)},
                        Vec3(0.7, 0.2, -0.05)),
                   ok, std::nullopt, 0.0});
  // Beyond it: tangent 1 (45 degrees) and 5 (79 degrees): a strongly curved patch, still projected.
  cases.push_back(
      {"tilt_tangent_1",
       with(square, {tilted(1, 225), tilted(1, -45), tilted(1, 45), tilted(1, 135)}, Vec3(0.5, 0.4, 0.1)),
       converged_or_not, std::nullopt, 0.0});
  cases.push_back(
      {"tilt_tangent_5",
       with(square, {tilted(5, 200), tilted(5, 0), tilted(5, 80), tilted(5, 160)}, Vec3(0.5, 0.4, 0.3)),
       converged_or_not, std::nullopt, 0.0});
  cases.push_back({"tilt_tangent_1_warped_quad",
                   with(kWarped, {tilted(1, 10), tilted(0.5, 100), tilted(1, 190), tilted(0.5, 280)},
                        Vec3(0.5, 0.5, 0.3)),
                   converged_or_not, std::nullopt, 0.0});
  // Parallel to an edge: the normal at A along AB (in the plane): no slope, degenerate; nearly so (1e-12 rad
  // off the plane): the edge's projection onto A's tangent plane vanishes, degenerate.
  cases.push_back({"normal_parallel_to_edge_AB",
                   with(square, {Vec3(1, 0, 0), up, up, up}, Vec3(0.3, 0.6, 0.2)), degenerate, std::nullopt,
                   0.0});
  cases.push_back({"normal_nearly_parallel_to_edge_AB",
                   with(square, {Vec3(1, 0, 1e-12), up, up, up}, Vec3(0.3, 0.6, 0.2)), degenerate,
                   std::nullopt, 0.0});
  cases.push_back({"normal_in_plane_not_along_an_edge",
                   with(square, {up, up, Vec3(-1, 1, 0), up}, Vec3(0.3, 0.6, 0.2)), degenerate, std::nullopt,
                   0.0});
  cases.push_back({"normal_flipped", with(square, {up, up, -up, up}, Vec3(0.3, 0.6, 0.2)), degenerate,
                   std::nullopt, 0.0});
  cases.push_back({"normal_zero_length", with(square, {up, Vec3::Zero(), up, up}, Vec3(0.3, 0.6, 0.2)),
                   degenerate, std::nullopt, 0.0});
  cases.push_back({"collapsed_segment",
                   with({Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, {up, up, up, up},
                        Vec3(0.3, 0.6, 0.2)),
                   degenerate, std::nullopt, 0.0});
  return cases;
}

const std::vector<GregoryCase>& gregory_cases() {
  static const std::vector<GregoryCase> all = build_gregory_cases();
  return all;
}

/// Dense-grid reference over [0,1]^2 of a Gregory patch built from the world configuration (shifted to A).
Reference gregory_reference(const Configuration& world) {
  std::array<Vec3, 4> q = world.nodes;
  for (auto& node : q) node -= world.nodes[0];
  const Vec3 s = world.slave - world.nodes[0];
  const GregoryPatch patch(q, world.normals);
  const auto f = [&](double a, double b) { return (s - patch.position(a, b)).squaredNorm(); };
  constexpr int n = 161;
  Reference best;
  best.sqr_distance = kInf;
  std::vector<std::array<double, 2>> starts;
  std::vector<double> values(n * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      values[static_cast<std::size_t>(i * n + j)] = f(double(i) / (n - 1), double(j) / (n - 1));
  }
  std::vector<std::pair<double, std::array<double, 2>>> coarse;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      coarse.push_back(
          {values[static_cast<std::size_t>(i * n + j)], {double(i) / (n - 1), double(j) / (n - 1)}});
  }
  std::partial_sort(coarse.begin(), coarse.begin() + 8, coarse.end(),
                    [](const auto& x, const auto& y) { return x.first < y.first; });
  for (int k = 0; k < 8; ++k) {
    std::array<double, 2> c = coarse[static_cast<std::size_t>(k)].second;
    double h = 1.0 / (n - 1);
    for (int round = 0; round < 200 && h > 1e-14; ++round) {
      std::array<double, 2> next = c;
      double next_value = f(c[0], c[1]);
      for (int a = -4; a <= 4; ++a) {
        for (int b = -4; b <= 4; ++b) {
          const double x = std::clamp(c[0] + h * a / 4.0, 0.0, 1.0);
          const double y = std::clamp(c[1] + h * b / 4.0, 0.0, 1.0);
          const double v = f(x, y);
          if (v < next_value) {
            next_value = v;
            next = {x, y};
          }
        }
      }
      if (next == c) h *= 0.3;
      c = next;
    }
    if (f(c[0], c[1]) < best.sqr_distance) {
      best.param = c;
      best.sqr_distance = f(c[0], c[1]);
    }
  }
  best.interior = best.param[0] > kBoundaryBand && best.param[0] < 1 - kBoundaryBand &&
                  best.param[1] > kBoundaryBand && best.param[1] < 1 - kBoundaryBand;
  return best;
}

class GregoryExtremeCase : public ::testing::TestWithParam<std::size_t> {
 protected:
  [[nodiscard]] const GregoryCase& the_case() const { return gregory_cases()[GetParam()]; }
};

TEST_P(GregoryExtremeCase, ExpectedStatusSameLabelsEverywhereAndTheDenseReference) {
  const GregoryCase& c = the_case();
  const dataset::Label unit = dataset::label_configuration(c.config, SurfaceKind::kGregory);
  expect_sane(unit, c.name);
  ASSERT_NE(std::find(c.allowed.begin(), c.allowed.end(), unit.status), c.allowed.end())
      << c.name << ": got " << describe(unit);
  if (c.exact_param) {
    ASSERT_EQ(unit.status, Status::kOk) << describe(unit);
    EXPECT_NEAR(unit.param[0], c.exact_param.value()[0], kExactTol) << describe(unit);
    EXPECT_NEAR(unit.param[1], c.exact_param.value()[1], kExactTol) << describe(unit);
    EXPECT_NEAR(unit.gap, c.exact_gap, kExactTol) << describe(unit);
  }
  const bool collapsed =
      std::find(c.allowed.begin(), c.allowed.end(), Status::kDegenerate) != c.allowed.end();
  for (const Transform& t : transforms()) {
    const Configuration world = testing::transform(c.config, t.rotation, t.scale, t.translation);
    const dataset::Label l = dataset::label_configuration(world, SurfaceKind::kGregory);
    const std::string where = c.name + " at " + t.name + ": " + describe(l) + " vs unit " + describe(unit);
    expect_sane(l, where);
    ASSERT_EQ(l.status, unit.status) << where;
    if (!converged(l.status)) continue;
    double largest = world.slave.cwiseAbs().maxCoeff();
    for (const Vec3& node : world.nodes) largest = std::max(largest, node.cwiseAbs().maxCoeff());
    const double tol = std::max(kInvarianceTol,
                                4.0 * std::numeric_limits<double>::epsilon() * largest / element_size(world));
    EXPECT_NEAR(l.param[0], unit.param[0], tol) << where;
    EXPECT_NEAR(l.param[1], unit.param[1], tol) << where;
    EXPECT_NEAR(l.gap / t.scale, unit.gap, tol) << where;
    if (collapsed || GregoryPatch::diagnose(world.nodes, world.normals) != geometry::GregoryDefect::kNone)
      continue;
    // The reference evaluates |S - P|^2 directly: its minimum is located to ~sqrt(eps) = 1e-8.
    const Reference ref = gregory_reference(world);
    std::array<Vec3, 4> q = world.nodes;
    for (auto& node : q) node -= world.nodes[0];
    const double d2 =
        (world.slave - world.nodes[0] - GregoryPatch(q, world.normals).position(l.param[0], l.param[1]))
            .squaredNorm();
    const double size = element_size(world);
    if (l.status == Status::kOk) {
      EXPECT_GE(d2, ref.sqr_distance - 1e-10 * size * size) << where;
    }
    if (ref.interior) {
      ASSERT_EQ(l.status, Status::kOk)
          << where << " reference (" << ref.param[0] << ", " << ref.param[1] << ")";
      EXPECT_NEAR(l.param[0], ref.param[0], 1e-6) << where;
      EXPECT_NEAR(l.param[1], ref.param[1], 1e-6) << where;
    }
  }
}

std::string gregory_case_name(const ::testing::TestParamInfo<std::size_t>& info) {
  std::string name = gregory_cases()[info.param].name;
  for (char& ch : name) {
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(Gregory, GregoryExtremeCase,
                         ::testing::Range<std::size_t>(0, gregory_cases().size()), gregory_case_name);

TEST(Extremes, GregoryNonFiniteNormalComponentIsInvalid) {
  const Vec3 up(0, 0, 1);
  for (int component = 0; component < 12; ++component) {
    for (const double bad : {kNaN, kInf, -kInf}) {
      Configuration c{kSquare, Vec3(0.3, 0.6, 0.2), {up, up, up, up}};
      c.normals[static_cast<std::size_t>(component / 3)][component % 3] = bad;
      const dataset::Label l = dataset::label_configuration(c, SurfaceKind::kGregory);
      EXPECT_EQ(l.status, Status::kInvalid) << "normal component " << component << " = " << bad;
      expect_sane(l, "normal component " + std::to_string(component));
    }
  }
}

}  // namespace
}  // namespace contactnn::extremes
