// Random local-search queries for lib/search's tests and benchmark: configurations of the paper's domains
// (bilinear: Section 5.1; Gregory: Section 6.3.1, angles 60-120 degrees and node normals tilted by a tangent
// below 0.2), drawn uniformly in the normalised frame by rejection, then placed at a random position,
// orientation and scale and given in a random node order, as an FE code hands them over (SPEC 6 rows).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "core/conventions.hpp"
#include "core/symmetry.hpp"
#include "dataset/labeller.hpp"
#include "geometry/configuration.hpp"
#include "geometry/domain.hpp"

namespace contactnn::testing {

using geometry::Configuration;
using geometry::Vec3;

/// The filters of the paper's study of `kind` (configs/bilinear-paper.toml, configs/gregory-paper.toml).
inline geometry::DomainFilters paper_filters(SurfaceKind kind) {
  geometry::DomainFilters f;
  if (kind == SurfaceKind::kGregory) {
    f.min_angle_degrees = 60.0;
    f.max_angle_degrees = 120.0;
    f.max_normal_tilt_tangent = 0.2;
  }
  return f;
}

/// Node normals: each node's corner normal (next - X) x (prev - X) tilted in a random direction by an angle
/// whose tangent is uniform in [0, max_tangent) (the generator's rule, lib/dataset/enumeration.cpp).
inline std::array<Vec3, 4> tilted_normals(const std::array<Vec3, 4>& nodes, double max_tangent,
                                          std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::array<Vec3, 4> normals;
  for (int i = 0; i < 4; ++i) {
    const Vec3 corner = (nodes[(i + 1) % 4] - nodes[i]).cross(nodes[(i + 3) % 4] - nodes[i]).normalized();
    const Vec3 t1 = corner.unitOrthogonal();
    const Vec3 t2 = corner.cross(t1);
    const double tangent = max_tangent * unit(rng);
    const double phi = 2.0 * std::numbers::pi * unit(rng);
    normals[i] = (corner + tangent * (std::cos(phi) * t1 + std::sin(phi) * t2)).normalized();
  }
  return normals;
}

/// A configuration of the paper's domain of `kind` in the normalised frame (A = 0, B = (1,0,0), D in the
/// xy-plane), uniform over the filters' region: drawn by rejection from a proposal that is uniform on a
/// region containing every accepted configuration. Bilinear: C, S in (-2, 2)^2 x (-0.3, 0.3), D in (-2, 2) x
/// (0, 2). Gregory (the angle at A is in [60, 120] degrees and |AD| <= 1): D uniform on that sector of the
/// unit disk, S in [-0.5, 0.6] x [-0.05, 1] (A must be its nearest node and its projection in the angle at
/// A), C in the box. `filters`: the paper's by default; narrower ones of the same kind (e.g. a bilinear angle
/// bound) keep the proposal valid.
inline Configuration random_domain_configuration(SurfaceKind kind, std::mt19937_64& rng,
                                                 const geometry::DomainFilters& filters) {
  std::uniform_real_distribution<double> xy(-2.0, 2.0), z(-0.3, 0.3), up(0.0, 2.0), unit(0.0, 1.0);
  std::uniform_real_distribution<double> sx(-0.5, 0.6), sy(-0.05, 1.0);
  const double third = std::numbers::pi / 3.0;
  for (;;) {
    Configuration c{{Vec3::Zero(), Vec3(1, 0, 0), Vec3(xy(rng), xy(rng), z(rng)), Vec3::Zero()},
                    Vec3::Zero(),
                    {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}};
    if (kind == SurfaceKind::kGregory) {
      const double r = std::sqrt(unit(rng)), angle = third * (1.0 + unit(rng));
      c.nodes[3] = Vec3(r * std::cos(angle), r * std::sin(angle), 0.0);
      c.slave = Vec3(sx(rng), sy(rng), z(rng));
      // The shape filters first (cheap and most often failed), then normals within the tilt bound.
      geometry::DomainFilters shape = filters;
      shape.max_normal_tilt_tangent = 1e300;
      if (!shape.accepts(c, SurfaceKind::kBilinear)) continue;
      c.normals = tilted_normals(c.nodes, filters.max_normal_tilt_tangent, rng);
    } else {
      c.nodes[3] = Vec3(xy(rng), up(rng), 0.0);
      c.slave = Vec3(xy(rng), xy(rng), z(rng));
    }
    if (filters.accepts(c, kind)) return c;
  }
}

inline Configuration random_domain_configuration(SurfaceKind kind, std::mt19937_64& rng) {
  return random_domain_configuration(kind, rng, paper_filters(kind));
}

/// A uniformly random rotation (a normalised Gaussian quaternion).
inline Eigen::Matrix3d random_rotation_matrix(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q.toRotationMatrix();
}

/// `c` moved by x -> scale R x + t (scale log-uniform in [1e-2, 1e2], t uniform in [-10, 10]^3 times the
/// scale, normals rotated and given a random length in [0.5, 2]), in the node order `order` (canonical node i
/// becomes the caller's node order.caller_node(i)). Local coordinates follow order.to_caller.
inline Configuration place(const Configuration& c, std::mt19937_64& rng, const SquareSymmetry& order) {
  std::uniform_real_distribution<double> unit(0.0, 1.0), shift(-10.0, 10.0), length(0.5, 2.0);
  const Eigen::Matrix3d r = random_rotation_matrix(rng);
  const double scale = std::pow(10.0, -2.0 + 4.0 * unit(rng));
  const Vec3 t = scale * Vec3(shift(rng), shift(rng), shift(rng));
  Configuration out;
  for (int i = 0; i < 4; ++i) {
    const auto k = static_cast<std::size_t>(order.caller_node(i));
    out.nodes[k] = scale * (r * c.nodes[static_cast<std::size_t>(i)]) + t;
    out.normals[k] = length(rng) * (r * c.normals[static_cast<std::size_t>(i)]);
  }
  out.slave = scale * (r * c.slave) + t;
  return out;
}

/// A random one of the 8 node orders.
inline SquareSymmetry random_order(std::mt19937_64& rng) {
  return all_square_symmetries()[std::uniform_int_distribution<std::size_t>(0, 7)(rng)];
}

/// Appends the SPEC 6 row of `world` (15 values, 27 for Gregory) to `raw`.
inline void append_raw(const Configuration& world, SurfaceKind kind, std::vector<double>& raw) {
  for (const Vec3& x : world.nodes) raw.insert(raw.end(), {x.x(), x.y(), x.z()});
  raw.insert(raw.end(), {world.slave.x(), world.slave.y(), world.slave.z()});
  if (kind == SurfaceKind::kGregory) {
    for (const Vec3& n : world.normals) raw.insert(raw.end(), {n.x(), n.y(), n.z()});
  }
}

/// The configuration of row `row` of `raw`.
inline Configuration configuration_of(const double* raw, SurfaceKind kind, std::size_t row) {
  const int stride = kind == SurfaceKind::kGregory ? 27 : 15;
  const double* x = raw + row * static_cast<std::size_t>(stride);
  Configuration c;
  for (int i = 0; i < 4; ++i)
    c.nodes[static_cast<std::size_t>(i)] = Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  c.slave = Vec3(x[12], x[13], x[14]);
  for (int i = 0; i < 4; ++i) {
    c.normals[static_cast<std::size_t>(i)] =
        kind == SurfaceKind::kGregory ? Vec3(x[15 + 3 * i], x[16 + 3 * i], x[17 + 3 * i]) : Vec3::Zero();
  }
  return c;
}

/// The labels' points moved by `offset` in a random direction (seeded), where the label is ok; the domain
/// centre elsewhere. An FE code's previous time step, as near as `offset` (tests of start+newton:K,
/// bench_search).
inline std::vector<double> starts_near(const std::vector<dataset::Label>& labels, SurfaceKind kind,
                                       double offset, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
  const double centre = kind == SurfaceKind::kGregory ? 0.5 : 0.0;
  std::vector<double> start(2 * labels.size(), centre);
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const double a = angle(rng);
    if (labels[i].status != Status::kOk) continue;
    start[2 * i] = labels[i].param[0] + offset * std::cos(a);
    start[2 * i + 1] = labels[i].param[1] + offset * std::sin(a);
  }
  return start;
}

/// Rows first .. first + count - 1 of `raw` (SPEC 6 rows of `kind`), as a query list of their own.
inline std::vector<double> rows_of(const std::vector<double>& raw, SurfaceKind kind, std::size_t first,
                                   std::size_t count = 1) {
  const std::size_t stride = kind == SurfaceKind::kGregory ? 27 : 15;
  return {raw.begin() + static_cast<std::ptrdiff_t>(first * stride),
          raw.begin() + static_cast<std::ptrdiff_t>((first + count) * stride)};
}

/// `count` random queries of the domain of `kind` that `filters` cut out (the paper's by default), placed at
/// random, as SPEC 6 rows.
inline std::vector<double> random_queries(SurfaceKind kind, std::size_t count, std::uint64_t seed,
                                          const geometry::DomainFilters& filters) {
  std::mt19937_64 rng(seed);
  std::vector<double> raw;
  raw.reserve(count * (kind == SurfaceKind::kGregory ? 27 : 15));
  for (std::size_t i = 0; i < count; ++i) {
    const Configuration local = random_domain_configuration(kind, rng, filters);
    append_raw(place(local, rng, random_order(rng)), kind, raw);
  }
  return raw;
}

inline std::vector<double> random_queries(SurfaceKind kind, std::size_t count, std::uint64_t seed) {
  return random_queries(kind, count, seed, paper_filters(kind));
}

/// Which rows spoil_rows spoils, and how far its tiny and huge rows are scaled.
struct Spoiling {
  std::size_t first = 0;  ///< the first spoiled row; then every seventh
  double tiny = 1e-200;   ///< every value of a tiny row is multiplied by this
  double huge = 1e200;    ///< the coordinates of a huge row by this (float consumers: 1e-20 and 1e20)
};

/// Every seventh row of `raw` (SPEC 6 rows of `kind`) from `s.first` spoiled in turn, so that every status is
/// reached: a NaN, a collapsed segment (A = B), the slave node moved up to 1e3 away, a tiny row, a huge row,
/// a random box of values in (-1e3, 1e3).
inline void spoil_rows(SurfaceKind kind, std::vector<double>& raw, std::uint64_t seed,
                       const Spoiling& s = {}) {
  const std::size_t columns = kind == SurfaceKind::kGregory ? 27 : 15;
  const std::size_t count = raw.size() / columns;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = s.first; i < count; i += 7) {
    double* q = raw.data() + i * columns;
    switch ((i / 7) % 6) {
      case 0: q[i % columns] = std::numeric_limits<double>::quiet_NaN(); break;
      case 1:
        for (std::size_t k = 3; k < 6; ++k) q[k] = q[k - 3];
        break;
      case 2:
        for (std::size_t k = 12; k < 15; ++k) q[k] += 1e3 * u(rng);
        break;
      case 3:
        for (std::size_t k = 0; k < columns; ++k) q[k] *= s.tiny;
        break;
      case 4:
        for (std::size_t k = 0; k < 15; ++k) q[k] *= s.huge;
        break;
      default:
        for (std::size_t k = 0; k < columns; ++k) q[k] = 1e3 * u(rng);
        break;
    }
  }
}

/// random_queries with spoil_rows applied (seed + 1 for the spoiling).
inline std::vector<double> mixed_queries(SurfaceKind kind, std::size_t count, std::uint64_t seed,
                                         const Spoiling& s = {}) {
  std::vector<double> raw = random_queries(kind, count, seed);
  spoil_rows(kind, raw, seed + 1, s);
  return raw;
}

/// Methods that together take every path of lib/search's block kernel (network, lean and converged Newton,
/// the closed form, the hybrids, four_triangles), for tests that compare runs of the same queries. The same
/// on both surfaces (on a Gregory patch the closed form is its corner facet's), but four_triangles, which has
/// no Gregory form. start+newton:2 starts from what the output's param holds when run() is called: (0, 0) in
/// tests whose outputs start zeroed (the centre of a bilinear facet, a corner of a Gregory patch).
inline std::vector<std::string> methods_of(SurfaceKind kind) {
  std::vector<std::string> methods = {"network",
                                      "newton:0",
                                      "newton:3",
                                      "newton",
                                      "network+newton:2",
                                      "closed_form",
                                      "closed_form+newton:2",
                                      "start+newton:2"};
  if (kind == SurfaceKind::kBilinear) methods.emplace_back("four_triangles");
  return methods;
}

/// Queries on a tie (tests/search/test_canonical_frame.cpp has the same shapes), each in all 8 node orders
/// and placed at random (16 queries per shape).
inline std::vector<Configuration> tie_queries(std::mt19937_64& rng) {
  const std::array<Vec3, 4> normals = {Vec3(0.05, -0.03, 1), Vec3(-0.02, 0.06, 1), Vec3(-0.1, 0.02, 1),
                                       Vec3(0.04, 0.05, 1)};
  const std::array<Vec3, 4> strip = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0.6, 0.1), Vec3(0, 0.6, 0)};
  const std::array<Vec3, 4> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0.1), Vec3(0, 1, 0)};
  const std::array<Vec3, 4> flat = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.05, 0.95, 0), Vec3(0, 0.9, 0)};
  const std::vector<Configuration> bases = {
      {strip, Vec3(0.5, 0.2, 0.1), normals},    // as near A as B
      {square, Vec3(0.3, 0.3, 0.15), normals},  // |AB| = |AD|, S on the diagonal
      {square, Vec3(0.5, 0.5, 0.2), normals},   // all four nodes, each on its diagonal
      {flat, Vec3(0.3, 0.25, 0.0), normals},    // S and C on the plane of A, B, D (Gregory: z tie)
      {flat, Vec3(0.5, 0.3, 0.0), normals},     // both
      // As near A as B, one form in the paper's domain and one outside it: z_S scaled by the longer edge at A
      // (1.2) is 0.28, by the one at B (1.1) 0.31, over the domain's 0.3.
      {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1.1, 0), Vec3(0, 1.2, 0)}, Vec3(0.5, 0.3, 0.34), normals},
  };
  std::vector<Configuration> out;
  for (const Configuration& base : bases) {
    for (const SquareSymmetry& order : all_square_symmetries()) {
      for (int p = 0; p < 2; ++p) out.push_back(testing::place(base, rng, order));
    }
  }
  return out;
}

}  // namespace contactnn::testing
