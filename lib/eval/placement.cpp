#include "eval/placement.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "mlp/random.hpp"

namespace contactnn::eval {

using geometry::Configuration;
using geometry::Vec3;

Configuration configuration_from_features(SurfaceKind kind, const double* f) {
  Configuration c;
  c.nodes[0] = Vec3::Zero();
  c.nodes[1] = Vec3(1.0, 0.0, 0.0);
  c.nodes[2] = Vec3(f[0], f[1], f[2]);
  c.nodes[3] = Vec3(f[3], f[4], 0.0);
  c.slave = Vec3(f[5], f[6], f[7]);
  for (int i = 0; i < 4; ++i) {
    c.normals[i] =
        kind == SurfaceKind::kGregory ? Vec3(f[8 + 2 * i], f[9 + 2 * i], 1.0).normalized() : Vec3::Zero();
  }
  return c;
}

Placement random_placement(std::uint64_t seed, std::uint64_t index) {
  mlp::Rng rng(mlp::Rng::derive_seed(seed, index));
  // Shoemake (1992), "Uniform random rotations", Graphics Gems III: three uniforms -> a unit quaternion.
  const double u1 = rng.uniform();
  const double u2 = rng.uniform();
  const double u3 = rng.uniform();
  const double a = std::sqrt(1.0 - u1);
  const double b = std::sqrt(u1);
  const double two_pi = 2.0 * std::numbers::pi;
  const Eigen::Quaterniond q(b * std::cos(two_pi * u3), a * std::sin(two_pi * u2), a * std::cos(two_pi * u2),
                             b * std::sin(two_pi * u3));
  Placement p;
  p.rotation = q.normalized().toRotationMatrix();
  p.scale = std::pow(10.0, rng.uniform(-2.0, 2.0));
  for (int k = 0; k < 3; ++k) p.translation[k] = p.scale * rng.uniform(-10.0, 10.0);
  return p;
}

Configuration place(const Configuration& config, const Placement& p) {
  Configuration out;
  for (int i = 0; i < 4; ++i) {
    out.nodes[i] = p.scale * (p.rotation * config.nodes[i]) + p.translation;
    out.normals[i] = p.rotation * config.normals[i];
  }
  out.slave = p.scale * (p.rotation * config.slave) + p.translation;
  return out;
}

}  // namespace contactnn::eval
