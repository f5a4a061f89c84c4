#include "geometry/domain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "geometry/segment_checks.hpp"

namespace contactnn::geometry {

bool DomainFilters::accepts(const geometry::Configuration& c, SurfaceKind kind, double relative_tolerance,
                            double segment_test_tolerance) const {
  const double tol = relative_tolerance;
  const double xy = xy_limit * (1.0 + tol);
  const double zl = z_limit * (1.0 + tol);
  const auto inside_xy = [&](const Vec3& p) { return std::abs(p.x()) < xy && std::abs(p.y()) < xy; };
  const Vec3& a = c.nodes[0];
  const Vec3& b = c.nodes[1];
  const Vec3& cc = c.nodes[2];
  const Vec3& d = c.nodes[3];
  if (!inside_xy(cc) || !inside_xy(d) || !inside_xy(c.slave)) return false;
  if (!(std::abs(cc.z()) < zl) || !(std::abs(c.slave.z()) < zl)) return false;
  if (ad_not_longer_than_ab && !((d - a).squaredNorm() <= (1.0 + tol) * (b - a).squaredNorm())) return false;
  if (nearest_node_a && !geometry::first_node_is_nearest(c.nodes, c.slave, tol)) return false;
  const double segment_tol = segment_test_tolerance < 0.0 ? tol : segment_test_tolerance;
  if (segment_test_a && !geometry::passes_segment_test(a, b, d, c.slave, segment_tol)) return false;
  if (convex && !geometry::is_convex(c.nodes, tol)) return false;
  if (min_angle_degrees > 0.0 || max_angle_degrees < 180.0) {
    const double slack_degrees = 180.0 * tol;
    for (const double angle : geometry::interior_angles_degrees(c.nodes)) {
      if (!(angle >= min_angle_degrees - slack_degrees && angle <= max_angle_degrees + slack_degrees))
        return false;
    }
  }
  if (kind == SurfaceKind::kGregory) {
    for (int i = 0; i < 4; ++i) {
      const Vec3 corner = (c.nodes[(i + 1) % 4] - c.nodes[i]).cross(c.nodes[(i + 3) % 4] - c.nodes[i]);
      const Vec3& n = c.normals[i];
      // tan(angle) = |corner x n| / (corner . n); a normal on the far side is never accepted.
      const double cosine_part = corner.dot(n);
      const double sine_part = corner.cross(n).norm();
      const double slack = tol * corner.norm() * n.norm();
      if (!(cosine_part > 0.0) || !(sine_part < max_normal_tilt_tangent * cosine_part + slack)) return false;
    }
  }
  return true;
}

std::string DomainFilters::describe() const {
  std::ostringstream os;
  os << "xy_limit = " << xy_limit << "\n"
     << "z_limit = " << z_limit << "\n"
     << "ad_not_longer_than_ab = " << (ad_not_longer_than_ab ? "true" : "false") << "\n"
     << "nearest_node_a = " << (nearest_node_a ? "true" : "false") << "\n"
     << "segment_test_a = " << (segment_test_a ? "true" : "false") << "\n"
     << "convex = " << (convex ? "true" : "false") << "\n"
     << "min_angle_degrees = " << min_angle_degrees << "\n"
     << "max_angle_degrees = " << max_angle_degrees << "\n"
     << "max_normal_tilt_tangent = " << max_normal_tilt_tangent << "\n";
  return os.str();
}

TrainingDomain TrainingDomain::from_features(SurfaceKind kind, const double* features, long rows,
                                             const std::vector<Status>& status,
                                             const DomainFilters& filters) {
  const int n_features = feature_count(kind);
  CONTACTNN_REQUIRE(static_cast<long>(status.size()) == rows,
                    "status has " << status.size() << " rows, features have " << rows);
  TrainingDomain domain;
  domain.surface = kind;
  domain.filters = filters;
  domain.feature_min.assign(static_cast<std::size_t>(n_features), std::numeric_limits<double>::infinity());
  domain.feature_max.assign(static_cast<std::size_t>(n_features), -std::numeric_limits<double>::infinity());
  long used = 0;
  for (long r = 0; r < rows; ++r) {
    if (status[static_cast<std::size_t>(r)] != Status::kOk) continue;
    ++used;
    for (int f = 0; f < n_features; ++f) {
      const double x = features[r * n_features + f];
      domain.feature_min[f] = std::min(domain.feature_min[f], x);
      domain.feature_max[f] = std::max(domain.feature_max[f], x);
    }
  }
  CONTACTNN_REQUIRE(used > 0, "no row with status ok: the training domain is empty");
  constexpr std::size_t kMaxGridValues = 10000;
  std::vector<double> values;
  for (int f = 0; f < n_features; ++f) {
    values.clear();
    for (long r = 0; r < rows; ++r) {
      if (status[static_cast<std::size_t>(r)] == Status::kOk) values.push_back(features[r * n_features + f]);
    }
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    if (values.size() < 2) continue;
    // A grid repeats each value over many rows; a random sample hardly ever repeats one.
    if (values.size() > kMaxGridValues || 2 * values.size() > static_cast<std::size_t>(used)) {
      // A continuous feature (random sampling): a finite sample's extremes fall short of the domain it was
      // drawn from by about (range / rows); the filters bound the domain itself.
      const double widen = kContinuousWidening * (domain.feature_max[f] - domain.feature_min[f]);
      domain.feature_min[f] -= widen;
      domain.feature_max[f] += widen;
      continue;
    }
    double step = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i < values.size(); ++i) step = std::min(step, values[i] - values[i - 1]);
    domain.feature_min[f] -= 0.5 * step;
    domain.feature_max[f] += 0.5 * step;
  }
  return domain;
}

bool TrainingDomain::contains(const geometry::Configuration& normalised, const double* features) const {
  const int n_features = feature_count(surface);
  for (int f = 0; f < n_features; ++f) {
    const double slack = kRelativeTolerance * std::max(1.0, feature_max[f] - feature_min[f]);
    if (!(features[f] >= feature_min[f] - slack && features[f] <= feature_max[f] + slack)) return false;
  }
  return filters.accepts(normalised, surface, kRelativeTolerance, kSegmentTestTolerance);
}

}  // namespace contactnn::geometry
