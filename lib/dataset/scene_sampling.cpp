#include "dataset/scene_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "dataset/labeller.hpp"
#include "dataset/random_stream.hpp"
#include "dataset/row_sampler.hpp"
#include "geometry/affine_frame.hpp"
#include "geometry/bilinear_patch.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::dataset {

using geometry::Configuration;
using geometry::Vec3;

namespace {

constexpr std::int64_t kMaxDrawsPerRow = 1'000'000;
/// The recorded domain's limits are the accepted rows' extremes widened by this fraction (a sample's
/// extremes fall short of the domain drawn from).
constexpr double kWidening = 0.01;

double shortest_edge(const std::array<Vec3, 4>& nodes) {
  double e = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) e = std::min(e, (nodes[(i + 1) % 4] - nodes[i]).norm());
  return e;
}

/// Uniform in the unit ball, by rejection from the cube.
Vec3 in_unit_ball(RandomStream& random) {
  for (;;) {
    const Vec3 v(random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1));
    if (v.squaredNorm() <= 1.0) return v;
  }
}

/// `n` (unit) tilted in a uniformly random direction by an angle whose tangent is uniform in [0,
/// max_tangent).
Vec3 tilted(const Vec3& n, double max_tangent, RandomStream& random) {
  const Vec3 t1 = n.unitOrthogonal();
  const Vec3 t2 = n.cross(t1);
  const double tangent = max_tangent * random.uniform01();
  const double phi = 2.0 * M_PI * random.uniform01();
  return (n + tangent * (std::cos(phi) * t1 + std::sin(phi) * t2)).normalized();
}

/// tan of the largest angle between a node normal and its corner's own normal (DomainFilters' tilt).
double largest_tilt_tangent(const Configuration& c) {
  double largest = 0.0;
  for (int i = 0; i < 4; ++i) {
    const Vec3 corner = (c.nodes[(i + 1) % 4] - c.nodes[i]).cross(c.nodes[(i + 3) % 4] - c.nodes[i]);
    const double cosine_part = corner.dot(c.normals[i]);
    largest = std::max(largest, cosine_part > 0.0 ? corner.cross(c.normals[i]).norm() / cosine_part
                                                  : std::numeric_limits<double>::infinity());
  }
  return largest;
}

void check_domain_options(const SceneDomainOptions& domain) {
  CONTACTNN_REQUIRE(domain.deformation >= 0.0 && domain.deformation < 0.5,
                    "deformation must be in [0, 0.5) of the shortest edge, got " << domain.deformation);
  CONTACTNN_REQUIRE(domain.capture > 0.0, "capture must be > 0, got " << domain.capture);
  CONTACTNN_REQUIRE(domain.boundary_fraction >= 0.0 && domain.boundary_fraction <= 1.0,
                    "boundary_fraction must be in [0, 1], got " << domain.boundary_fraction);
  CONTACTNN_REQUIRE(domain.normal_tilt_tangent >= 0.0,
                    "normal_tilt_tangent must be >= 0, got " << domain.normal_tilt_tangent);
}

/// One draw of the scene's domain: what sample_scene's rows are made from.
struct SceneDraw {
  const std::vector<SceneSegment>& segments;
  const SceneDomainOptions& domain;
  const EnumerationOptions& options;
  std::vector<double> cumulative_area;  ///< segments drawn in proportion to their area
  double total_area = 0.0;

  SceneDraw(const std::vector<SceneSegment>& s, const SceneDomainOptions& d, const EnumerationOptions& o)
      : segments(s), domain(d), options(o), cumulative_area(s.size()) {
    for (std::size_t k = 0; k < segments.size(); ++k) {
      const auto& x = segments[k].nodes;
      total_area += 0.5 * (x[2] - x[0]).cross(x[3] - x[1]).norm();
      cumulative_area[k] = total_area;
    }
    CONTACTNN_REQUIRE(total_area > 0.0 && std::isfinite(total_area), "the scene's segments have no area");
  }

  /// A segment drawn by area, each node moved by up to `deformation` of its shortest edge (Gregory: the node
  /// normals tilted); writes that edge into `e`.
  Configuration deformed_segment(RandomStream& random, double& e) const {
    const double pick = random.uniform01() * total_area;
    const auto k = static_cast<std::size_t>(std::min<std::ptrdiff_t>(
        std::lower_bound(cumulative_area.begin(), cumulative_area.end(), pick) - cumulative_area.begin(),
        static_cast<std::ptrdiff_t>(segments.size()) - 1));
    const SceneSegment& segment = segments[k];
    e = shortest_edge(segment.nodes);
    Configuration c{};
    for (int i = 0; i < 4; ++i) c.nodes[i] = segment.nodes[i] + domain.deformation * e * in_unit_ball(random);
    for (int i = 0; i < 4; ++i) {
      c.normals[i] = options.surface == SurfaceKind::kGregory
                         ? tilted(segment.normals[i], domain.normal_tilt_tangent, random)
                         : Vec3::Zero();
    }
    return c;
  }

  /// A foot point's (xi, eta): uniform, or with `boundary_fraction` on the nodes (half of it) and edges.
  std::pair<double, double> foot_point(RandomStream& random) const {
    double xi = random.uniform(-1.0, 1.0);
    double eta = random.uniform(-1.0, 1.0);
    const double where = random.uniform01();
    if (where < 0.5 * domain.boundary_fraction) {  // at a node
      xi = xi < 0.0 ? -1.0 : 1.0;
      eta = eta < 0.0 ? -1.0 : 1.0;
    } else if (where < domain.boundary_fraction) {  // on an edge
      if (random.uniform01() < 0.5) {
        xi = xi < 0.0 ? -1.0 : 1.0;
      } else {
        eta = eta < 0.0 ? -1.0 : 1.0;
      }
    }
    return {xi, eta};
  }

  detail::Attempt operator()(RandomStream& random) const {
    detail::Attempt attempt;
    // 1. A segment, deformed.
    double e = 0.0;
    Configuration c = deformed_segment(random, e);
    // 2. The slave along the facet's normal over a foot point.
    const auto [xi, eta] = foot_point(random);
    const geometry::SurfacePoint foot = geometry::BilinearPatch(c.nodes).evaluate(xi, eta);
    const Vec3 normal = foot.d_s.cross(foot.d_t);
    if (!(normal.norm() > 0.0)) return attempt;
    c.slave = foot.position + random.uniform(-domain.capture, domain.capture) * e * normal.normalized();
    // 3. A pair the global search could make: the segment's node nearest S, and (domain.segment_test) S
    // passes
    //    the segment test of Eqs 3-6 there, as the paper's pairs; the surface search's need not.
    const int a = geometry::canonical_symmetry(c.nodes, c.slave).rotation;
    if (domain.segment_test &&
        !geometry::passes_segment_test(c.nodes[a], c.nodes[(a + 1) % 4], c.nodes[(a + 3) % 4], c.slave,
                                       geometry::kSegmentTestTolerance)) {
      return attempt;
    }
    // 4. The label; inside the segment, as the paper's sets.
    attempt.label = label_configuration(c, options.surface, options.projection);
    attempt.keep = attempt.label->status == Status::kOk;
    return attempt;
  }
};

/// The domain drawn, as filters: the accepted rows' extremes, widened by kWidening.
geometry::DomainFilters drawn_domain(const LabelledSet& set, bool segment_test, bool gregory) {
  geometry::DomainFilters f{};
  f.xy_limit = 0.0;
  f.z_limit = 0.0;
  f.min_angle_degrees = 180.0;
  f.max_angle_degrees = 0.0;
  f.max_normal_tilt_tangent = 0.0;
  bool all_convex = true;
  for (Eigen::Index r = 0; r < set.size(); ++r) {
    Configuration c{};
    c.nodes[1] = Vec3(1, 0, 0);
    c.nodes[2] = Vec3(set.features(r, 0), set.features(r, 1), set.features(r, 2));
    c.nodes[3] = Vec3(set.features(r, 3), set.features(r, 4), 0.0);
    c.slave = Vec3(set.features(r, 5), set.features(r, 6), set.features(r, 7));
    for (const Vec3* p : {&c.nodes[2], &c.nodes[3], &c.slave}) {
      f.xy_limit = std::max({f.xy_limit, std::abs(p->x()), std::abs(p->y())});
      f.z_limit = std::max(f.z_limit, std::abs(p->z()));
    }
    for (const double angle : geometry::interior_angles_degrees(c.nodes)) {
      f.min_angle_degrees = std::min(f.min_angle_degrees, angle);
      f.max_angle_degrees = std::max(f.max_angle_degrees, angle);
    }
    all_convex = all_convex && geometry::is_convex(c.nodes);
    if (gregory) {
      for (int i = 0; i < 4; ++i) {
        c.normals[i] = Vec3(set.features(r, 8 + 2 * i), set.features(r, 9 + 2 * i), 1.0).normalized();
      }
      f.max_normal_tilt_tangent = std::max(f.max_normal_tilt_tangent, largest_tilt_tangent(c));
    }
  }
  f.xy_limit *= 1.0 + kWidening;
  f.z_limit = std::max(f.z_limit * (1.0 + kWidening), 1e-12);
  f.convex = all_convex;
  f.segment_test_a = segment_test;
  f.min_angle_degrees = std::max(0.0, f.min_angle_degrees - 180.0 * kWidening);
  f.max_angle_degrees = std::min(180.0, f.max_angle_degrees + 180.0 * kWidening);
  f.max_normal_tilt_tangent = gregory ? f.max_normal_tilt_tangent * (1.0 + kWidening)
                                      : geometry::DomainFilters{}.max_normal_tilt_tangent;
  return f;
}

}  // namespace

LabelledSet sample_scene(const std::vector<SceneSegment>& segments, const SceneDomainOptions& domain,
                         const EnumerationOptions& options, std::int64_t count, EnumerationSummary& summary,
                         const ProgressFn& progress) {
  CONTACTNN_REQUIRE(!segments.empty(), "the scene has no master segment to sample");
  CONTACTNN_REQUIRE(count >= 1, "count must be >= 1, got " << count);
  check_domain_options(domain);
  const SceneDraw draw(segments, domain, options);
  LabelledSet set = detail::sample_rows(
      options.surface, count, options.seed, kMaxDrawsPerRow,
      [&](RandomStream& random) { return draw(random); }, summary, progress,
      "no configuration of the scene's domain was accepted in " + std::to_string(kMaxDrawsPerRow) + " draws");
  set.filters = drawn_domain(set, domain.segment_test, options.surface == SurfaceKind::kGregory);
  return set;
}

}  // namespace contactnn::dataset
