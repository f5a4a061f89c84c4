// Shared by the tests: random configurations in the paper's domain, random rigid motions, and an
// independent closest-point oracle (dense grid search refined by finite-difference Newton), so the
// reference solver is never checked against itself.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <filesystem>
#include <random>

#include "core/conventions.hpp"
#include "core/symmetry.hpp"
#include "geometry/configuration.hpp"
#include "geometry/domain.hpp"

namespace contactnn::testing {

using geometry::Vec3;

/// `c` with its nodes (and normals) relabelled: the returned configuration's node order.caller_node(i) is c's
/// node i. The same segment and slave, given in another node order.
inline geometry::Configuration relabel(const geometry::Configuration& c, const SquareSymmetry& order) {
  geometry::Configuration out = c;
  for (int i = 0; i < 4; ++i) {
    out.nodes[static_cast<std::size_t>(order.caller_node(i))] = c.nodes[static_cast<std::size_t>(i)];
    out.normals[static_cast<std::size_t>(order.caller_node(i))] = c.normals[static_cast<std::size_t>(i)];
  }
  return out;
}

/// A random configuration of the bilinear study (paper Section 5.1) in the normalised frame, drawn by
/// rejection until DomainFilters{} accepts it.
inline geometry::Configuration random_paper_configuration(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> xy(-2.0, 2.0), z(-0.3, 0.3);
  const geometry::DomainFilters filters;
  for (;;) {
    geometry::Configuration c{
        {Vec3::Zero(), Vec3(1, 0, 0), Vec3(xy(rng), xy(rng), z(rng)), Vec3(xy(rng), std::abs(xy(rng)), 0)},
        Vec3(xy(rng), xy(rng), z(rng)),
        {}};
    if (filters.accepts(c, SurfaceKind::kBilinear)) return c;
  }
}

/// A uniformly random rotation (from a normalised Gaussian quaternion).
inline Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q.toRotationMatrix();
}

/// x -> scale * R x + t applied to every node, the slave and (rotated only) the normals.
inline geometry::Configuration transform(const geometry::Configuration& c, const Eigen::Matrix3d& r,
                                         double scale, const Vec3& t) {
  geometry::Configuration out = c;
  for (int i = 0; i < 4; ++i) {
    out.nodes[i] = scale * (r * c.nodes[i]) + t;
    out.normals[i] = r * c.normals[i];
  }
  out.slave = scale * (r * c.slave) + t;
  return out;
}

/// Independent closest point on a surface over its domain: the minimum of |S - P|^2 on an n x n grid,
/// then Newton on the gradient with central finite-difference derivatives of `position` only (no
/// analytic derivative code shared with the solver under test). Returns the parameters.
template <class SurfaceT>
std::array<double, 2> oracle_closest_point(const SurfaceT& surface, const Vec3& s, int n = 401) {
  const ParamDomain d = param_domain(SurfaceT::kKind);
  const auto f = [&](double a, double b) { return (s - surface.position(a, b)).squaredNorm(); };
  std::array<double, 2> best{d.lo, d.lo};
  double best_f = f(best[0], best[1]);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double a = d.lo + (d.hi - d.lo) * i / (n - 1);
      const double b = d.lo + (d.hi - d.lo) * j / (n - 1);
      const double v = f(a, b);
      if (v < best_f) {
        best_f = v;
        best = {a, b};
      }
    }
  }
  // Finite-difference Newton on grad f (h chosen for ~1e-10 accuracy of the second differences' use).
  const double h = 1e-5;
  for (int it = 0; it < 30; ++it) {
    const double a = best[0], b = best[1];
    const double fa = (f(a + h, b) - f(a - h, b)) / (2 * h);
    const double fb = (f(a, b + h) - f(a, b - h)) / (2 * h);
    const double faa = (f(a + h, b) - 2 * f(a, b) + f(a - h, b)) / (h * h);
    const double fbb = (f(a, b + h) - 2 * f(a, b) + f(a, b - h)) / (h * h);
    const double fab = (f(a + h, b + h) - f(a + h, b - h) - f(a - h, b + h) + f(a - h, b - h)) / (4 * h * h);
    const double det = faa * fbb - fab * fab;
    if (!(det > 0)) break;
    const double da = (fbb * fa - fab * fb) / det;
    const double db = (faa * fb - fab * fa) / det;
    best = {a - da, b - db};
    if (std::max(std::abs(da), std::abs(db)) < 1e-13) break;
  }
  return best;
}

/// A folder for one test file's outputs under the build tree, created if missing. ctest -j runs every test
/// case as its own process, so the cases of one file share it and must use distinct file names.
inline std::filesystem::path test_output_dir(const std::string& name) {
  const auto dir = std::filesystem::path(CONTACTNN_BINARY_DIR) / name;
  std::filesystem::create_directories(dir);
  return dir;
}

/// test_output_dir(group) / name, emptied (or created): a fresh folder for one test case.
inline std::filesystem::path fresh_test_dir(const std::string& group, const std::string& name) {
  const auto dir = test_output_dir(group) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace contactnn::testing
